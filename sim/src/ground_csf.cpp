// sim/src/ground_csf.cpp: the cloth simulation filter, CSF (Zhang, Qi, Wan, Wang, Xie,
// Wang and Yan 2016, Remote Sensing 8(6) 501), written from the paper, on the whole
// fused cloud:
//
//   1) the cloud is turned upside down (z' = -z); a cloth of particles cloth_m apart,
//      one per cell of the shared minimum-surface raster, starts above it;
//   2) each particle's intersection height (IHV) is the inverted height of the lowest
//      point of its cell (cells without a point: interpolated, ground_raster.hpp);
//   3) each step moves the movable particles by gravity (Verlet integration with
//      damping 0.01, gravity 0.2, the time step as given), then pulls each pair of
//      neighbours towards each other `rigidness` times (a movable particle moves half
//      the height difference to its neighbour), then a particle that reached its IHV
//      stops there for good; the simulation ends when no movable particle moved more
//      than 5 mm in a step, or after `iterations` steps;
//   4) post-processing on steep slopes, as the paper and its authors' implementation
//      do it: in each 4-connected region of more than 50 hanging particles, a particle
//      next to one that stopped is moved to its IHV and stops when the two IHVs differ
//      by under slope_join_m (0.3 m) and it hangs under slope_join_m above its own IHV;
//      the join spreads through the region under the same two tests;
//   5) a point within threshold_m of the cloth (turned back up: the DTM) is ground.
//
// The pairs are visited in a fixed order and nothing depends on the order of the points
// (only per-cell minima), so the result is the same whatever the threads or batching.
#include "ground_internal.hpp"
#include "ground_raster.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <cmath>
#include <deque>

namespace sim {
namespace {

constexpr double kGravity = 0.2, kDamping = 0.01;
constexpr double kStill_m = 0.005;  // a step moving no particle more than this ends the run
// The slope post-processing takes only regions of more than this many hanging particles,
// as the authors' implementation does (50 m2 at the default 1 m cloth; a count, so that
// it means the same in a survey's feet).
constexpr std::size_t kSlopeMinParticles = 50;

class CsfFit final : public RasterFit {
  public:
    explicit CsfFit(const CsfOptions& o) : RasterFit(o.cloth_m, o.max_cells, "csf cloth_m (--csf-cloth-m)"), o_(o) {
        threshold_m_ = o.threshold_m;
        low_outlier_m_ = o.low_outlier_m;
        z_unit_m_ = o.z_unit_m;
    }

  private:
    void fitTerrain(std::vector<float>& minimum, const std::vector<std::uint8_t>& observed) override {
        const int w = grid_.nx, h = grid_.ny;
        const std::size_t n = minimum.size();
        inpaint(minimum, observed, w, h);
        std::vector<double> ihv(n), z(n), previous(n);
        double top = -1e300;
        for (std::size_t c = 0; c < n; ++c) {
            ihv[c] = -double(minimum[c]);
            top = std::max(top, ihv[c]);
        }
        std::fill(z.begin(), z.end(), top + 1.0);
        previous = z;
        std::vector<std::uint8_t> movable(n, 1);
        const double fall = kGravity * o_.time_step * o_.time_step;
        // Neighbour pull: the movable ones of a pair move half their height difference
        // towards each other (both movable: they meet).
        const auto pull = [&](std::size_t a, std::size_t b) {
            const double d = 0.5 * (z[b] - z[a]);
            if (movable[a] && movable[b]) {
                z[a] += d;
                z[b] -= d;
            } else if (movable[a]) {
                z[a] += d;
            } else if (movable[b]) {
                z[b] -= d;
            }
        };
        std::vector<double> before(n);
        for (int step = 0; step < o_.iterations; ++step) {
            before = z;
            for (std::size_t c = 0; c < n; ++c) {
                if (!movable[c]) continue;
                const double next = z[c] + (1.0 - kDamping) * (z[c] - previous[c]) - fall;
                previous[c] = z[c];
                z[c] = next;
            }
            for (int r = 0; r < o_.rigidness; ++r) {
                for (int j = 0; j < h; ++j)
                    for (int i = 0; i + 1 < w; ++i) {
                        const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
                        pull(c, c + 1);
                    }
                for (int j = 0; j + 1 < h; ++j)
                    for (int i = 0; i < w; ++i) {
                        const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
                        pull(c, c + std::size_t(w));
                    }
            }
            double moved = 0;
            std::size_t still_movable = 0;
            for (std::size_t c = 0; c < n; ++c) {
                if (!movable[c]) continue;
                if (z[c] <= ihv[c]) {
                    z[c] = ihv[c];
                    movable[c] = 0;
                } else {
                    ++still_movable;
                }
                moved = std::max(moved, std::abs(z[c] - before[c]));
            }
            if (still_movable == 0 || (step > 0 && moved < kStill_m)) break;
        }
        slopePostProcess(ihv, z, movable, w, h);
        grid_.z_m.resize(n);
        for (std::size_t c = 0; c < n; ++c) grid_.z_m[c] = float(-z[c]);
        limit_m_.assign(n, float(groundThreshold(o_.threshold_m)));
    }

    // 4) slopes: in each connected region of more than kSlopeMinParticles hanging
    // particles, a particle beside a stopped one is moved to its IHV and stops
    // when the two IHVs differ by under slope_join_m and it hangs within slope_join_m of
    // its own IHV; the join spreads from there through the region under the same two
    // tests. A region hanging over a vehicle is smaller than that, and over a taller
    // object the cloth hangs further than slope_join_m above it: without either test
    // the join climbed a vehicle's side in steps under slope_join_m and lifted the
    // terrain under it.
    void slopePostProcess(const std::vector<double>& ihv, std::vector<double>& z, std::vector<std::uint8_t>& movable,
                          int w, int h) const {
        const std::size_t n = z.size();
        const auto neighbours = [&](std::size_t c, auto&& visit) {
            const int i = int(c % std::size_t(w)), j = int(c / std::size_t(w));
            if (i > 0) visit(c - 1);
            if (i + 1 < w) visit(c + 1);
            if (j > 0) visit(c - std::size_t(w));
            if (j + 1 < h) visit(c + std::size_t(w));
        };
        // The regions of hanging particles (4-connected), each marked when large enough.
        std::vector<std::uint8_t> large(n, 0), seen(n, 0);
        std::vector<std::size_t> region;
        for (std::size_t s = 0; s < n; ++s) {
            if (!movable[s] || seen[s]) continue;
            region.assign(1, s);
            seen[s] = 1;
            for (std::size_t k = 0; k < region.size(); ++k)
                neighbours(region[k], [&](std::size_t d) {
                    if (movable[d] && !seen[d]) {
                        seen[d] = 1;
                        region.push_back(d);
                    }
                });
            if (region.size() > kSlopeMinParticles)
                for (const std::size_t c : region) large[c] = 1;
        }
        const auto joins = [&](std::size_t c, std::size_t d) {
            return large[d] && movable[d] && std::abs(ihv[d] - ihv[c]) < o_.slope_join_m &&
                   z[d] - ihv[d] < o_.slope_join_m;
        };
        std::deque<std::size_t> queue;
        for (std::size_t c = 0; c < n; ++c)
            if (!movable[c]) queue.push_back(c);
        while (!queue.empty()) {
            const std::size_t c = queue.front();
            queue.pop_front();
            neighbours(c, [&](std::size_t d) {
                if (!joins(c, d)) return;
                z[d] = ihv[d];
                movable[d] = 0;
                queue.push_back(d);
            });
        }
    }

    CsfOptions o_;
};

using CsfFilter = WholeCloudFilter<CsfFit, CsfOptions, GroundMethod::Csf>;

}  // namespace

void validate(const CsfOptions& o) {
    if (!(std::isfinite(o.cloth_m) && o.cloth_m >= 0.01 && o.cloth_m <= 1000.0))
        failGroundOption("csf cloth_m (--csf-cloth-m)", o.cloth_m, "[0.01, 1000] metres");
    if (o.rigidness < 1 || o.rigidness > 3)
        failGroundOption("csf rigidness (--csf-rigidness)", o.rigidness, "1, 2 or 3");
    if (!(std::isfinite(o.threshold_m) && o.threshold_m >= 0.0 && o.threshold_m <= 1000.0))
        failGroundOption("csf threshold_m (--csf-threshold-m)", o.threshold_m, "[0, 1000] metres");
    if (!(std::isfinite(o.time_step) && o.time_step > 0.0 && o.time_step <= 10.0))
        failGroundOption("csf time_step (--csf-time-step)", o.time_step, "(0, 10]");
    if (o.iterations < 1 || o.iterations > 100000)
        failGroundOption("csf iterations (--csf-iterations)", o.iterations, "[1, 100000]");
    if (o.max_cells < 1) failGroundOption("csf max_cells", double(o.max_cells), ">= 1");
    if (!(std::isfinite(o.low_outlier_m) && o.low_outlier_m >= 0.0 && o.low_outlier_m <= 1000.0))
        failGroundOption("csf low_outlier_m (--low-outlier-m)", o.low_outlier_m, "[0, 1000] metres, 0 = off");
}

std::unique_ptr<const CloudGroundFilter> makeCsfFilter(const CsfOptions& o) { return std::make_unique<CsfFilter>(o); }
std::unique_ptr<TerrainFit> startCsf(const CsfOptions& o) { return std::make_unique<CsfFit>(o); }

std::vector<std::uint8_t> findGroundCsf(std::span<const glm::vec3> points, const CsfOptions& o, TerrainGrid* surface,
                                        std::vector<float>* height_m) {
    CsfFit fit(o);
    return classifyInMemory(fit, points, surface, height_m);
}

}  // namespace sim
