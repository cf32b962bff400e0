// sim/src/ground_smrf.cpp: the simple morphological filter, SMRF (Pingel, Clarke and
// McBride 2013, ISPRS J. Photogrammetry and Remote Sensing 77:21-30), written from the
// paper, on the whole fused cloud:
//
//   1) minimum surface: the lowest z of the points in each cell_m cell; empty cells
//      (occlusions, gaps) are filled by interpolation (below).
//   2) objects: the surface is opened (erosion then dilation) with windows of radius
//      1, 2, ... cells up to window_m; a cell that an opening lowers by more than
//      slope * radius_m is an object (a building, a tree). Windows are disks, as in the
//      paper (a square would cut convex hilltops twice as deep at the same radius).
//   3) terrain (the DTM): the minimum surface at the cells that are not objects, the
//      object and empty cells interpolated from them.
//   4) a point is ground when |z - terrain(x, y)| <= threshold_m + scalar * slope(x, y),
//      terrain bilinear between cell centres, slope its local gradient.
//
// Ours, for real surveys (SmrfOptions::raised_segments, off in the generator): between
// 2) and 3), a patch of the surface left ground that stands more than 2 m above the
// surface around it on most of its border, or more than 5 m above wherever it is seen
// (a roof too wide for the openings, a bridge deck), is an object too; with
// SmrfOptions::sparse_openings (also off in the generator), the openings of 2) leave out
// the empty cells between a sparse survey's points.
// SmrfOptions::reconstruct (off; measured, see ground.hpp) puts morphological
// reconstruction (ground_reconstruct.hpp) into the object test or after it.
//
// The paper fills cells with a spring-metaphor inpainting; ours is its membrane
// analogue: a breadth-first fill from the known cells (each new ring takes the mean of
// its known neighbours) relaxed by Gauss-Seidel iterations of Laplace's equation (until
// settled, or a fixed number of sweeps with SmrfOptions::fill_sweeps, so that a tile's
// filled cells are the whole survey's). The paper's low-outlier pass is left out:
// simulated returns have no low noise (for real surveys RasterFit has its own,
// SmrfOptions::low_outlier_m, off by default).
//
// Only the per-cell minima depend on the points, and a minimum does not depend on the
// order it is taken in, so the result is the same whatever the batching or the threads.
#include "ground_internal.hpp"
#include "ground_learned_terrains.hpp"
#include "ground_raster.hpp"
#include "ground_reconstruct.hpp"
#include "parallel.hpp"

#include <core/error.hpp>
#include <core/frames.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace sim {
namespace {

// Erosion (take_max false) or dilation of an nx x ny raster by the disk of radius r cells
// (the cells whose centres are within r of the centre). The disk is a stack of rows:
// row dy spans |dx| <= floor(sqrt(r^2 - dy^2)), so each row offset is one running
// extreme along x (rows with the same half width share it), folded into `out` shifted
// by +-dy. O(r) per cell, O(cells) memory.
// The rows are shared among `pool`'s workers; each value is computed by the same
// operations whatever their number.
void diskFilter(const std::vector<float>& in, std::vector<float>& out, int nx, int ny, int r, bool take_max,
                std::vector<float>& row_pass, Workers& pool) {
    row_pass.resize(in.size());
    out.assign(in.size(), take_max ? -kNoPoint : kNoPoint);
    const auto fold = [&](float a, float b) { return take_max ? std::max(a, b) : std::min(a, b); };
    const std::size_t parts = std::size_t(std::clamp(pool.size(), 1, std::max(1, ny)));
    const auto first_row = [&](std::size_t part) { return int(std::size_t(ny) * part / parts); };
    int row_half = -1;  // the half width row_pass holds (near the disk's middle, rows share one)
    for (int dy = 0; dy <= r; ++dy) {
        const int half = int(std::floor(std::sqrt(double(r) * r - double(dy) * dy) + 1e-9));
        if (half != row_half)
            pool.run(parts, [&](std::size_t part) {
                std::vector<float> scratch;
                for (int j = first_row(part); j < first_row(part + 1); ++j)
                    runningExtreme(in.data() + std::size_t(j) * nx, row_pass.data() + std::size_t(j) * nx, nx, half,
                                   take_max, scratch);
            });
        row_half = half;
        pool.run(parts, [&](std::size_t part) {
            for (int j = first_row(part); j < first_row(part + 1); ++j) {
                float* o = out.data() + std::size_t(j) * nx;
                for (const int source : {j - dy, j + dy}) {
                    if (source < 0 || source >= ny || (dy == 0 && source != j - dy)) continue;
                    const float* h = row_pass.data() + std::size_t(source) * nx;
                    for (int i = 0; i < nx; ++i) o[i] = fold(o[i], h[i]);
                }
            }
        });
    }
}

// Raised segments (SmrfOptions::raised_segments): the observed cells of the ground-level
// surface joined into segments, two cells within kSegmentReach cells of each other
// joined when their levels differ by at most kSegmentJoin_m + kSegmentJoinSlope x their
// distance. A segment that holds ground and at most kSegmentMaxArea_m2, and whose level
// lies more than kSegmentDrop_m above that of the other segments' cells next to it on at
// least kSegmentDropShare of its border, stands above everything around it: a roof
// wider than the openings. Only neighbours in segments of at least kSegmentLowerArea_m2
// count as the lower side, so a few low returns left in a cell do not make the ground
// around them a roof, and the border runs on beyond the data's edge without a drop, so
// a terrace that the survey's edge cuts is not one either.
// A tall segment is raised even where the edge cuts it: looking out from each of its
// cells along the 8 rays of the raster, up to kTallReach cells, over the empty cells and
// over the small segments (under kSegmentLowerArea_m2) no more than kSegmentDrop_m below
// it (what stands on a roof), a ray ends on another segment (seen) or beyond the data
// (one that meets neither within its reach counts for neither). When at least
// kTallSeenShare of its rays are seen, and at least kSegmentDropShare of those end more
// than kTallDrop_m below it, on a segment of at least kSegmentLowerArea_m2, it is a roof
// cut by the edge (a tall building's shadow leaves no point between roof and ground,
// hence the reach): terrain that the edge cuts does not end in a step that high wherever
// it is seen.
constexpr int kSegmentReach = 2;
constexpr double kSegmentJoin_m = 0.5, kSegmentJoinSlope = 0.5;
constexpr double kSegmentDrop_m = 2.0, kSegmentDropShare = 0.7;
constexpr double kSegmentLowerArea_m2 = 100.0, kSegmentMaxArea_m2 = 20000.0;
constexpr int kTallReach = 18;
constexpr double kTallDrop_m = 5.0, kTallSeenShare = 0.1;

constexpr std::uint32_t kNoSegment = std::numeric_limits<std::uint32_t>::max();

// Each observed cell's segment (0, 1, ... in raster order; kNoSegment where no point
// fell); `count` gets the number of segments. Union-find towards the lowest index, then
// renumbered in place: a cell's root comes before it, so its number is already set.
std::vector<std::uint32_t> segmentCells(const std::vector<float>& level, const std::vector<std::uint8_t>& observed,
                                        int w, int h, double cell_m, std::uint32_t& count) {
    const std::size_t n = level.size();
    std::vector<std::uint32_t> parent(n);
    for (std::size_t c = 0; c < n; ++c) parent[c] = std::uint32_t(c);
    const auto find = [&](std::uint32_t c) {
        while (parent[c] != c) c = parent[c] = parent[parent[c]];
        return c;
    };
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
            if (!observed[c]) continue;
            for (int dj = 0; dj <= kSegmentReach; ++dj)
                for (int di = -kSegmentReach; di <= kSegmentReach; ++di) {
                    const int ii = i + di, jj = j + dj;
                    if ((dj == 0 && di <= 0) || ii < 0 || ii >= w || jj >= h) continue;
                    const std::size_t d = std::size_t(jj) * std::size_t(w) + std::size_t(ii);
                    const double dist_m = std::sqrt(double(di * di + dj * dj)) * cell_m;
                    if (!observed[d] ||
                        std::abs(double(level[c]) - double(level[d])) > kSegmentJoin_m + kSegmentJoinSlope * dist_m)
                        continue;
                    const std::uint32_t a = find(std::uint32_t(c)), b = find(std::uint32_t(d));
                    if (a != b) parent[std::max(a, b)] = std::min(a, b);
                }
        }
    for (std::size_t c = 0; c < n; ++c) parent[c] = observed[c] ? find(std::uint32_t(c)) : kNoSegment;
    count = 0;
    for (std::size_t c = 0; c < n; ++c) {
        if (parent[c] == kNoSegment) continue;
        parent[c] = parent[c] == c ? count++ : parent[parent[c]];
    }
    return parent;
}

// A segment's bounding box in cells, inclusive.
struct SegmentBox {
    int i0, i1, j0, j1;
};

// Takes the raised segments (above) out of `ground`; `tested` gets the boxes of the
// segments whose test a wider raster could turn (below).
void removeRaisedSegments(const std::vector<float>& level, const std::vector<std::uint8_t>& observed,
                          std::vector<std::uint8_t>& ground, int w, int h, double cell_m,
                          std::vector<SegmentBox>& tested) {
    std::uint32_t count = 0;
    const std::vector<std::uint32_t> segment = segmentCells(level, observed, w, h, cell_m, count);
    struct Tally {
        std::uint32_t cells = 0, ground = 0, border = 0, drops = 0, beyond = 0;
        std::uint32_t rays = 0, rays_seen = 0, rays_tall = 0;  // the tall test's (above)
    };
    std::vector<Tally> tally(count);
    for (std::size_t c = 0; c < segment.size(); ++c)
        if (segment[c] != kNoSegment) {
            ++tally[segment[c]].cells;
            tally[segment[c]].ground += ground[c];
        }
    // A segment's area against the rule's bounds: large enough to be the ground below a
    // step, small enough to be an object.
    const double cell_area_m2 = cell_m * cell_m;
    const auto large = [&](std::uint32_t t) { return double(tally[t].cells) * cell_area_m2 >= kSegmentLowerArea_m2; };
    const auto capped = [&](const Tally& t) { return double(t.cells) * cell_area_m2 <= kSegmentMaxArea_m2; };
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
            const std::uint32_t s = segment[c];
            if (s == kNoSegment) continue;
            for (int dj = -kSegmentReach; dj <= kSegmentReach; ++dj)
                for (int di = -kSegmentReach; di <= kSegmentReach; ++di) {
                    const int ii = i + di, jj = j + dj;
                    if (ii < 0 || ii >= w || jj < 0 || jj >= h) {  // beyond the data: not seen to drop
                        ++tally[s].border;
                        ++tally[s].beyond;
                        continue;
                    }
                    const std::size_t d = std::size_t(jj) * std::size_t(w) + std::size_t(ii);
                    const std::uint32_t t = segment[d];
                    if (t == kNoSegment || t == s) continue;
                    ++tally[s].border;
                    if (large(t) && double(level[c]) - double(level[d]) > kSegmentDrop_m) ++tally[s].drops;
                }
        }
    constexpr int kRayDi[8] = {1, 1, 0, -1, -1, -1, 0, 1}, kRayDj[8] = {0, 1, 1, 1, 0, -1, -1, -1};
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
            const std::uint32_t s = segment[c];
            if (s == kNoSegment || tally[s].ground == 0 || !large(s) || !capped(tally[s])) continue;
            for (int k = 0; k < 8; ++k)
                for (int step = 1; step <= kTallReach; ++step) {
                    const int ii = i + kRayDi[k] * step, jj = j + kRayDj[k] * step;
                    if (ii < 0 || ii >= w || jj < 0 || jj >= h) {
                        ++tally[s].rays;
                        break;
                    }
                    const std::size_t d = std::size_t(jj) * std::size_t(w) + std::size_t(ii);
                    const std::uint32_t t = segment[d];
                    if (t == kNoSegment) continue;
                    if (t == s) break;
                    const double drop_m = double(level[c]) - double(level[d]);
                    if (!large(t) && drop_m <= kSegmentDrop_m) continue;
                    ++tally[s].rays;
                    ++tally[s].rays_seen;
                    if (large(t) && drop_m > kTallDrop_m) ++tally[s].rays_tall;
                    break;
                }
        }
    const auto tall = [&](const Tally& t) {
        return t.rays_seen > 0 && double(t.rays_seen) >= kTallSeenShare * double(t.rays) &&
               double(t.rays_tall) >= kSegmentDropShare * double(t.rays_seen);
    };
    std::vector<SegmentBox> box(count, SegmentBox{w, -1, h, -1});
    for (std::size_t c = 0; c < segment.size(); ++c) {
        if (segment[c] == kNoSegment) continue;
        SegmentBox& b = box[segment[c]];
        const int i = int(c % std::size_t(w)), j = int(c / std::size_t(w));
        b = {std::min(b.i0, i), std::max(b.i1, i), std::min(b.j0, j), std::max(b.j1, j)};
    }
    // Those that could be raised seen whole: the drops on at least kSegmentDropShare / 2
    // of the border within the raster (a stretch of ground, with few or none, is not
    // worth a wider look).
    tested.clear();
    for (std::uint32_t s = 0; s < count; ++s) {
        const Tally& t = tally[s];
        if (t.ground > 0 && capped(t) &&
            ((t.border > t.beyond && double(t.drops) >= 0.5 * kSegmentDropShare * double(t.border - t.beyond)) ||
             (t.rays_seen > 0 && double(t.rays_tall) >= 0.5 * kSegmentDropShare * double(t.rays_seen))))
            tested.push_back(box[s]);
    }
    for (std::size_t c = 0; c < segment.size(); ++c) {
        if (segment[c] == kNoSegment) continue;
        const Tally& t = tally[segment[c]];
        if (t.ground > 0 && capped(t) &&
            ((t.border > 0 && double(t.drops) >= kSegmentDropShare * double(t.border)) || tall(t)))
            ground[c] = 0;
    }
}

class SmrfFit : public RasterFit {
  public:
    explicit SmrfFit(const SmrfOptions& o, std::vector<SmrfVariant> variants = {})
        : RasterFit(o.cell_m, o.max_cells, "smrf cell_m (--smrf-cell-m)"), o_(o), variants_(std::move(variants)) {
        threshold_m_ = o.threshold_m;
        low_outlier_m_ = o.low_outlier_m;
        z_unit_m_ = o.z_unit_m;
    }

  protected:
    // With variants: each one's terrain and the ground-level surface (SmrfTerrains).
    std::vector<TerrainGrid> variant_grids_;
    std::vector<float> levels_;

  private:
    void fitTerrain(std::vector<float>& minimum, const std::vector<std::uint8_t>& observed) override {
        const int w = grid_.nx, h = grid_.ny;
        std::vector<float> surface = minimum;
        inpaint(surface, observed, w, h, o_.fill_sweeps, threads_);
        // SmrfOptions::sparse_openings: the cells left out hold kNoPoint, which no erosion
        // takes. Every cell within r of one that holds a value has it in its disk, so the
        // erosions a valued cell dilates are finite and so is its opening; a left-out cell's
        // opening is set back to kNoPoint below, so that the next radius leaves it out too.
        const std::vector<std::uint8_t> left_out =
            o_.sparse_openings ? sparseEmptyCells(observed, w, h) : std::vector<std::uint8_t>{};
        for (std::size_t c = 0; c < left_out.size(); ++c)
            if (left_out[c]) surface[c] = kNoPoint;
        // The filled surface and the levels as they were, for the reconstructions after the
        // openings (SmrfOptions::reconstruct 2 to 5).
        std::vector<float> filled, levels;
        if (o_.reconstruct >= 2) filled = surface;
        if (o_.reconstruct == 3 || o_.reconstruct == 4) levels = minimum;

        // 2) objects, by openings of growing radius.
        std::vector<std::uint8_t> object(minimum.size(), 0);
        std::vector<float> eroded, opened, scratch;
        Workers pool(threads_);
        const auto radiiOf = [&](double window_m) { return std::max(1, int(std::ceil(window_m / o_.cell_m - 1e-9))); };
        const int radii = radiiOf(o_.window_m);
        // The variants see the same openings (each the opening of the one before), each
        // up to its own window with its own slope: one loop to the largest window.
        int all_radii = radii;
        for (const SmrfVariant& v : variants_) all_radii = std::max(all_radii, radiiOf(v.window_m));
        std::vector<std::vector<std::uint8_t>> variant_object(variants_.size(),
                                                              std::vector<std::uint8_t>(minimum.size(), 0));
        for (int r = 1; r <= all_radii; ++r) {
            diskFilter(surface, eroded, w, h, r, false, scratch, pool);
            const double radius_m = double(r) * o_.cell_m;
            const bool by_reconstruction = o_.reconstruct == 1 && radius_m >= o_.reconstruct_from_m &&
                                           (o_.reconstruct_to_m == 0.0 || radius_m <= o_.reconstruct_to_m);
            if (by_reconstruction && o_.reconstruct_steps == 0) {
                opened = eroded;
                reconstructByDilation(opened, surface, w, h);
            } else {
                diskFilter(eroded, opened, w, h, r, true, scratch, pool);
                if (by_reconstruction) geodesicDilation(opened, surface, w, h, o_.reconstruct_steps);
            }
            for (std::size_t c = 0; c < left_out.size(); ++c)
                if (left_out[c]) opened[c] = kNoPoint;  // kNoPoint - kNoPoint: no object test
            if (r <= radii) {
                const float limit = float(o_.slope * double(r) * o_.cell_m);
                for (std::size_t c = 0; c < surface.size(); ++c)
                    if (surface[c] - opened[c] > limit) object[c] = 1;
            }
            for (std::size_t k = 0; k < variants_.size(); ++k) {
                if (r > radiiOf(variants_[k].window_m)) continue;
                const float limit = float(variants_[k].slope * double(r) * o_.cell_m);
                for (std::size_t c = 0; c < surface.size(); ++c)
                    if (surface[c] - opened[c] > limit) variant_object[k][c] = 1;
            }
            surface.swap(opened);
        }
        if (!variants_.empty()) {
            levels_ = minimum;
            variant_grids_.assign(variants_.size(), grid_);
            for (std::size_t k = 0; k < variants_.size(); ++k) {
                std::vector<std::uint8_t> known(minimum.size());
                for (std::size_t c = 0; c < minimum.size(); ++c) known[c] = observed[c] && !variant_object[k][c];
                if (std::find(known.begin(), known.end(), 1) == known.end()) known = observed;
                variant_grids_[k].z_m = minimum;
                inpaint(variant_grids_[k].z_m, known, w, h, o_.fill_sweeps, threads_);
            }
        }

        // 3) the terrain from the cells that are ground.
        std::vector<std::uint8_t> ground(minimum.size());
        for (std::size_t c = 0; c < minimum.size(); ++c) ground[c] = observed[c] && !object[c];
        if (o_.raised_segments) removeRaisedSegments(minimum, observed, ground, w, h, o_.cell_m, tested_);
        reconstructObjects(filled, observed, ground, pool);
        if (std::find(ground.begin(), ground.end(), 1) == ground.end()) ground = observed;
        grid_.z_m = std::move(minimum);
        inpaint(grid_.z_m, ground, w, h, o_.fill_sweeps, threads_);
        reconstructSteps(filled, levels, observed, ground);

        // 4)'s threshold per cell, so that classify() looks it up.
        limit_m_.resize(grid_.z_m.size());
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i)
                limit_m_[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                    float(groundThreshold(o_.threshold_m) +
                          o_.scalar * grid_.slopeAt(grid_.x0_m + i * o_.cell_m, grid_.y0_m + j * o_.cell_m));
    }

    // A height in metres in the cloud's units.
    float inUnits(double m) const { return float(m / o_.z_unit_m); }

    // SmrfOptions::reconstruct 2 and 5, on the ground the openings left, before the terrain
    // is fitted from it (`filled`: the surface before the openings).
    void reconstructObjects(const std::vector<float>& filled, const std::vector<std::uint8_t>& observed,
                            std::vector<std::uint8_t>& ground, Workers& pool) const {
        const int w = grid_.nx, h = grid_.ny;
        if (o_.reconstruct == 2)
            domeGroundBack(filled, observed, ground, w, h, inUnits(o_.reconstruct_h_m), inUnits(o_.reconstruct_tol_m));
        if (o_.reconstruct == 5) {
            std::vector<float> eroded, scratch;
            diskFilter(filled, eroded, w, h, std::max(1, o_.reconstruct_steps), false, scratch, pool);
            topHatObjects(filled, eroded, ground, w, h, inUnits(o_.reconstruct_h_m));
        }
    }

    // SmrfOptions::reconstruct 3 and 4, after the terrain is fitted: the ground given back
    // up steps, and the terrain fitted again from `levels` (the cells' levels) if any was.
    void reconstructSteps(const std::vector<float>& filled, std::vector<float>& levels,
                          const std::vector<std::uint8_t>& observed, std::vector<std::uint8_t>& ground) {
        if (o_.reconstruct != 3 && o_.reconstruct != 4) return;
        const int w = grid_.nx, h = grid_.ny;
        if (stepGroundBack(filled, grid_.z_m, observed, ground, w, h, inUnits(o_.reconstruct_tol_m),
                           inUnits(o_.reconstruct_h_m), o_.reconstruct_steps, o_.reconstruct == 4) == 0)
            return;
        grid_.z_m = std::move(levels);
        inpaint(grid_.z_m, ground, w, h, o_.fill_sweeps, threads_);
    }

  public:
    void testedPatches(const glm::dvec2& lo, const glm::dvec2& hi, double reach_m,
                       std::vector<std::pair<glm::dvec2, glm::dvec2>>& out) const override {
        for (const SegmentBox& b : tested_) {
            // The cells' edges: cell i spans x0_m + (i -+ 0.5) cell_m.
            const glm::dvec2 a(grid_.x0_m + (b.i0 - 0.5) * o_.cell_m, grid_.y0_m + (b.j0 - 0.5) * o_.cell_m);
            const glm::dvec2 z(grid_.x0_m + (b.i1 + 0.5) * o_.cell_m, grid_.y0_m + (b.j1 + 0.5) * o_.cell_m);
            if (z.x <= lo.x - reach_m || a.x >= hi.x + reach_m || z.y <= lo.y - reach_m || a.y >= hi.y + reach_m)
                continue;
            out.emplace_back(a, z);
        }
    }

  private:
    SmrfOptions o_;
    std::vector<SmrfVariant> variants_;
    std::vector<SegmentBox> tested_;  // removeRaisedSegments()'s
};

class SmrfTerrainsFit final : public SmrfTerrains {
  public:
    SmrfTerrainsFit(const SmrfOptions& o, const std::vector<SmrfVariant>& variants) : fit_(o, variants) {}
    void add(std::span<const core::CloudPoint> points) override { fit_.add(points); }
    void addAll(std::span<const core::CloudPoint> points, int threads) override { fit_.addAll(points, threads); }
    void setFitThreads(int threads) override { fit_.setFitThreads(threads); }
    void fit() override { fit_.fit(); }
    const TerrainGrid& surface() const override { return fit_.surface(); }
    bool classify(const glm::vec3& p, float& height_m) const override { return fit_.classify(p, height_m); }
    bool classify(const core::CloudPoint& p, float& height_m) const override { return fit_.classify(p, height_m); }
    void thicknessSamples(const glm::dvec2& lo, const glm::dvec2& hi, std::vector<double>& out) const override {
        fit_.thicknessSamples(lo, hi, out);
    }
    void setGroundThickness(double sigma_m) override { fit_.setGroundThickness(sigma_m); }
    const TerrainGrid& variant(std::size_t k) const override { return fit_.variantGrid(k); }
    const std::vector<float>& levels() const override { return fit_.levelsOf(); }
    float limit(std::size_t cell) const override { return fit_.limitOf(cell); }

  private:
    struct Fit final : SmrfFit {
        using SmrfFit::SmrfFit;
        const TerrainGrid& variantGrid(std::size_t k) const { return variant_grids_[k]; }
        const std::vector<float>& levelsOf() const { return levels_; }
        float limitOf(std::size_t cell) const { return limit_m_[cell]; }
    };
    Fit fit_;
};

using SmrfFilter = WholeCloudFilter<SmrfFit, SmrfOptions, GroundMethod::Smrf>;

}  // namespace

void validate(const SmrfOptions& o) {
    if (!(std::isfinite(o.cell_m) && o.cell_m >= 0.01 && o.cell_m <= 1000.0))
        failGroundOption("smrf cell_m (--smrf-cell-m)", o.cell_m, "[0.01, 1000] metres");
    if (!(std::isfinite(o.slope) && o.slope > 0.0 && o.slope <= 100.0))
        failGroundOption("smrf slope (--smrf-slope)", o.slope, "(0, 100] (rise over run)");
    if (!(std::isfinite(o.window_m) && o.window_m > 0.0 && o.window_m / o.cell_m <= 1000.0))
        failGroundOption("smrf window_m (--smrf-window-m)", o.window_m,
                         "> 0 metres and at most 1000 cells of --smrf-cell-m");
    if (!(std::isfinite(o.threshold_m) && o.threshold_m >= 0.0 && o.threshold_m <= 1000.0))
        failGroundOption("smrf threshold_m (--smrf-threshold-m)", o.threshold_m, "[0, 1000] metres");
    if (!(std::isfinite(o.scalar) && o.scalar >= 0.0 && o.scalar <= 1000.0))
        failGroundOption("smrf scalar (--smrf-scalar)", o.scalar, "[0, 1000] metres per unit slope");
    if (o.max_cells < 1) failGroundOption("smrf max_cells", double(o.max_cells), ">= 1");
    if (!(std::isfinite(o.low_outlier_m) && o.low_outlier_m >= 0.0 && o.low_outlier_m <= 1000.0))
        failGroundOption("smrf low_outlier_m (--low-outlier-m)", o.low_outlier_m, "[0, 1000] metres, 0 = off");
    if (o.fill_sweeps < 0 || o.fill_sweeps > 10000)
        failGroundOption("smrf fill_sweeps", double(o.fill_sweeps), "[0, 10000], 0 = until settled");
    if (o.sparse_openings && o.reconstruct != 0)
        failGroundOption("smrf reconstruct", double(o.reconstruct), "0 when sparse_openings is on");
    if (o.reconstruct < 0 || o.reconstruct > 5)
        failGroundOption("smrf reconstruct", double(o.reconstruct),
                         "0 (off), 1 (opening by reconstruction), 2 (h-dome test), 3 (terrain up steps), 4 (ground up "
                         "steps), 5 (top-hat by reconstruction)");
    if (!(std::isfinite(o.reconstruct_h_m) && o.reconstruct_h_m > 0.0 && o.reconstruct_h_m <= 1000.0))
        failGroundOption("smrf reconstruct_h_m", o.reconstruct_h_m, "(0, 1000] metres");
    if (!(std::isfinite(o.reconstruct_tol_m) && o.reconstruct_tol_m >= 0.0 && o.reconstruct_tol_m <= 1000.0))
        failGroundOption("smrf reconstruct_tol_m", o.reconstruct_tol_m, "[0, 1000] metres");
    if (!(std::isfinite(o.reconstruct_from_m) && o.reconstruct_from_m >= 0.0 && o.reconstruct_from_m <= 1000.0))
        failGroundOption("smrf reconstruct_from_m", o.reconstruct_from_m, "[0, 1000] metres");
    if (!(std::isfinite(o.reconstruct_to_m) && o.reconstruct_to_m >= 0.0 && o.reconstruct_to_m <= 1000.0))
        failGroundOption("smrf reconstruct_to_m", o.reconstruct_to_m, "[0, 1000] metres, 0 = up to the window");
    if (o.reconstruct_steps < 0 || o.reconstruct_steps > 1000)
        failGroundOption("smrf reconstruct_steps", double(o.reconstruct_steps), "[0, 1000] cells, 0 = however far");
}

std::unique_ptr<const CloudGroundFilter> makeSmrfFilter(const SmrfOptions& o) {
    return std::make_unique<SmrfFilter>(o);
}
std::unique_ptr<TerrainFit> startSmrf(const SmrfOptions& o) { return std::make_unique<SmrfFit>(o); }

std::unique_ptr<SmrfTerrains> startSmrfTerrains(const SmrfOptions& o, const std::vector<SmrfVariant>& variants) {
    return std::make_unique<SmrfTerrainsFit>(o, variants);
}

std::vector<std::uint8_t> findGroundSmrf(std::span<const glm::vec3> points, const SmrfOptions& o, TerrainGrid* surface,
                                         std::vector<float>* height_m) {
    SmrfFit fit(o);
    return classifyInMemory(fit, points, surface, height_m);
}

}  // namespace sim
