// viewer/lod.hpp: skip what a frame does not need: frustum culling of spatial
// cells and a point budget over a level-of-detail order built once per chunk at load, in
// the spirit of Potree (Schuetz 2016). Pure maths, no GL: the renderer
// (viewer/src/points/point_renderer.cpp) calls these and draws the prefixes they choose.
//
// Level of detail: every chunk that arrives from the stream is split into a grid of cells
// in x/y (about kLodCellPoints points each), and the points of every cell are shuffled with
// a fixed seed, so any prefix of a cell is a uniform random subsample of it. A frame then
// draws, per cell, a prefix whose length the budget allocation picks. The shuffled cell is
// cut into layers of doubling size (1/64, 1/64, 1/32, ... 1/2 of it), and each layer is
// ordered by place, blocks of the cell taken in a spread-out order: a GPU draws points
// that land near each other on screen faster than points in random order, and a prefix
// is still whole random layers plus an evenly spread part of the next one.
//
// Focus: what the operator works on (the pointer's hit, the designation, the cutting
// volume) is a set of spheres; the cells and nodes that touch one are drawn whole whatever
// the point budget, and the rest of the scene shares what is left of it.
#pragma once
#include <core/frames.hpp>
#include <core/point_cloud.hpp>
#include <render/orbit_camera.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace viewer {

struct LodOptions {
    std::size_t cell_points = 8192;  // target points per cell (grid side = sqrt(n / this))
    std::uint64_t seed = 0x1ada7;    // fixed: the same file gives the same order every run
};

/// One cell of a chunk: points [first, first + count) of the reordered chunk.
struct LodCell {
    std::size_t first = 0, count = 0;
    core::Bounds bounds;
};

/// Layers per cell (see the top of this file): the last holds half the cell's points.
inline constexpr int kLodLayers = 7;

/// The order of a point within its layer: a Morton code of its x/y in `box` (16 bits per
/// axis) whose top 6 bits, an 8 x 8 block of the box, are bit-reversed.
std::uint32_t spreadOrderKey(const glm::dvec3& p, const core::Bounds& box);

/// Reorders `points` in place into grid cells over its x/y bounds, each cell shuffled with
/// `options.seed` and its layers ordered by spreadOrderKey (a prefix of a cell is close to
/// a uniform subsample, exactly one at a layer's end); returns the cells in order (empty
/// cells left out). Deterministic.
std::vector<LodCell> buildLodOrder(std::vector<core::CloudPoint>& points, const LodOptions& options = {});

/// For each box: true if it may be seen by at least one of `frusta` (the union of the eyes'
/// frusta); false only when it is certainly outside all of them.
std::vector<bool> visibleInAny(std::span<const render::Frustum> frusta, std::span<const core::Bounds> boxes);

/// Screen-space importance of a box seen from `eye`: (r / max(d, r))^2 with r the box's
/// half diagonal and d the distance from the eye to its centre, i.e. about the solid angle
/// it covers over pi (1 when the eye is inside it). 0 for an empty box.
double screenImportance(const core::Bounds& box, const glm::dvec3& eye);

/// A ball of the local frame the operator works in.
struct FocusSphere {
    glm::dvec3 centre_local{0.0};
    double radius_m = 0.0;
};

/// Where the operator works: the nodes and cells touching any of these spheres are loaded
/// first and drawn at full density, whatever the point budget.
struct LodFocus {
    std::vector<FocusSphere> spheres;
    bool empty() const { return spheres.empty(); }
    /// True when `box` (not empty) comes within a sphere's radius of its centre.
    bool touches(const core::Bounds& box) const;
};

/// Radii of the focus spheres the viewer puts around the pointer's hit and the designated
/// point (the cutting volume brings its own): a vehicle-sized target and its shadow.
inline constexpr double kPointerFocusRadius_m = 6.0;
inline constexpr double kDesignationFocusRadius_m = 12.0;

/// Points to draw per cell: count_i = min(sizes_i, floor(lambda * importance_i)) with the
/// largest lambda that keeps the sum <= budget (water filling), so cells with more
/// importance get more points, none gets more than it has, and cells with importance 0
/// get none. budget 0 = unlimited (every cell with importance > 0 gets all of its points).
std::vector<std::size_t> allocateBudget(std::span<const double> importance, std::span<const std::size_t> sizes,
                                        std::size_t budget);

/// allocateBudget with a focus: cells with `focused` set and importance > 0 get all their
/// points whatever the budget; the others share what the focused cells leave of `budget`
/// (none when they take it all). budget 0 = unlimited. Equal to allocateBudget when no cell
/// is focused.
std::vector<std::size_t> allocateFocusedBudget(std::span<const double> importance, std::span<const std::size_t> sizes,
                                               const std::vector<bool>& focused, std::size_t budget);

}  // namespace viewer
