// sim/src/true_terrain.hpp: the scene's true terrain, rasterised from its ground-role
// meshes, to score what a ground filter kept: a target or environment point more than
// kAboveTerrain_m above the true terrain should stay coloured.
#pragma once
#include <core/scene.hpp>

#include <cstddef>
#include <vector>

namespace sim {

/// Points higher than this above the true terrain count in "target kept" and
/// "environment kept".
inline constexpr double kAboveTerrain_m = 0.5;

class TrueTerrain {
  public:
    /// The highest ground-role triangle over each cell centre of the square of half-side
    /// `half_m` around (cx, cy), local frame; cells of at least `min_cell_m`, at most
    /// `max_cells` of them (coarser cells over a wider square). Without ground triangles
    /// the terrain is empty.
    TrueTerrain(const core::Scene& scene, double cx, double cy, double half_m, double min_cell_m = 0.25,
                std::size_t max_cells = std::size_t(1) << 22);
    bool empty() const { return nx_ == 0; }
    /// The true terrain's height at (x, y), bilinear between the cell centres that a
    /// ground triangle covers; false outside the square or where no ground lies.
    bool heightAt(double x, double y, double& z_m) const;

  private:
    double x0_m_ = 0, y0_m_ = 0, cell_m_ = 1;
    int nx_ = 0, ny_ = 0;
    std::vector<float> z_m_;  // NaN where no ground triangle covers the cell centre
};

}  // namespace sim
