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
// The paper fills cells with a spring-metaphor inpainting; ours is its membrane
// analogue: a breadth-first fill from the known cells (each new ring takes the mean of
// its known neighbours) relaxed by Gauss-Seidel iterations of Laplace's equation. The
// paper's low-outlier pass is left out: simulated returns have no low noise.
//
// Only the per-cell minima depend on the points, and a minimum does not depend on the
// order it is taken in, so the result is the same whatever the batching or the threads.
#include "ground_internal.hpp"

#include <engine/error.hpp>
#include <engine/frames.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace sim {
namespace {

[[noreturn]] void fail(const char* parameter, double value, const char* allowed) {
    std::ostringstream s;
    s << "ground: " << parameter << " = " << value << ": allowed " << allowed;
    throw engine::Error(s.str());
}

constexpr float kEmpty = std::numeric_limits<float>::infinity();
constexpr int kTileBits = 6, kTile = 1 << kTileBits;  // cells of a sparse tile: 64 x 64

// out[i] = min (or max) of in[i - r .. i + r] clipped to [0, n): a running window with a
// monotonic queue of indices, O(n) whatever r.
void runningExtreme(const float* in, std::ptrdiff_t stride, float* out, int n, int r, bool take_max,
                    std::vector<int>& queue) {
    queue.resize(std::size_t(n));
    int head = 0, tail = 0, next = 0;
    const auto worse = [&](float queued, float incoming) { return take_max ? queued <= incoming : queued >= incoming; };
    for (int i = 0; i < n; ++i) {
        for (; next < n && next <= i + r; ++next) {
            const float v = in[next * stride];
            while (tail > head && worse(in[queue[std::size_t(tail - 1)] * stride], v)) --tail;
            queue[std::size_t(tail++)] = next;
        }
        while (queue[std::size_t(head)] < i - r) ++head;
        out[i * stride] = in[queue[std::size_t(head)] * stride];
    }
}

// Erosion (take_max false) or dilation of an nx x ny raster by the disk of radius r cells
// (the cells whose centres are within r of the centre). The disk is a stack of rows:
// row dy spans |dx| <= floor(sqrt(r^2 - dy^2)), so each row offset is one running
// extreme along x, folded into `out` shifted by +-dy. O(r) per cell, O(cells) memory.
void diskFilter(const std::vector<float>& in, std::vector<float>& out, int nx, int ny, int r, bool take_max,
                std::vector<float>& row_pass, std::vector<int>& queue) {
    row_pass.resize(in.size());
    out.assign(in.size(), take_max ? -kEmpty : kEmpty);
    const auto fold = [&](float a, float b) { return take_max ? std::max(a, b) : std::min(a, b); };
    for (int dy = 0; dy <= r; ++dy) {
        const int half = int(std::floor(std::sqrt(double(r) * r - double(dy) * dy) + 1e-9));
        for (int j = 0; j < ny; ++j)
            runningExtreme(in.data() + std::size_t(j) * nx, 1, row_pass.data() + std::size_t(j) * nx, nx, half,
                           take_max, queue);
        for (int j = 0; j < ny; ++j) {
            float* o = out.data() + std::size_t(j) * nx;
            for (const int source : {j - dy, j + dy}) {
                if (source < 0 || source >= ny || (dy == 0 && source != j - dy)) continue;
                const float* h = row_pass.data() + std::size_t(source) * nx;
                for (int i = 0; i < nx; ++i) o[i] = fold(o[i], h[i]);
            }
        }
    }
}

// Fills the cells of `z` whose `known` is 0: rings of cells next to filled ones take the
// mean of their filled 8-neighbours, then Gauss-Seidel relaxes the filled values towards
// the mean of their 4-neighbours (a membrane held by the known cells). Nothing known:
// `z` is left as it is.
void inpaint(std::vector<float>& z, const std::vector<std::uint8_t>& known, int nx, int ny) {
    const std::size_t n = z.size();
    std::vector<int> ring(n, -1);  // ring of each cell: 0 known, k filled in the k-th ring
    std::vector<std::size_t> layer, next_layer, holes;
    for (std::size_t c = 0; c < n; ++c)
        if (known[c]) ring[c] = 0;
    if (std::find(known.begin(), known.end(), 1) == known.end()) return;
    const auto neighbours = [&](std::size_t c, auto&& visit) {
        const int i = int(c % std::size_t(nx)), j = int(c / std::size_t(nx));
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                if ((di == 0 && dj == 0) || i + di < 0 || i + di >= nx || j + dj < 0 || j + dj >= ny) continue;
                visit(std::size_t(j + dj) * std::size_t(nx) + std::size_t(i + di));
            }
    };
    for (std::size_t c = 0; c < n; ++c) {
        if (ring[c] >= 0) continue;
        bool next_to_known = false;
        neighbours(c, [&](std::size_t d) { next_to_known |= ring[d] == 0; });
        if (next_to_known) {
            ring[c] = 1;
            layer.push_back(c);
        }
    }
    for (int k = 1; !layer.empty(); ++k) {
        for (const std::size_t c : layer) {
            double sum = 0;
            int count = 0;
            neighbours(c, [&](std::size_t d) {
                if (ring[d] >= 0 && ring[d] < k) {
                    sum += z[d];
                    ++count;
                }
            });
            z[c] = float(sum / count);
            holes.push_back(c);
        }
        next_layer.clear();
        for (const std::size_t c : layer)
            neighbours(c, [&](std::size_t d) {
                if (ring[d] < 0) {
                    ring[d] = k + 1;
                    next_layer.push_back(d);
                }
            });
        std::sort(next_layer.begin(), next_layer.end());
        layer.swap(next_layer);
    }
    std::sort(holes.begin(), holes.end());
    // Successive over-relaxation (factor kOmega) settles in far fewer sweeps than plain
    // Gauss-Seidel; the sweep order is fixed, so the result is too.
    constexpr int kMaxSweeps = 100;
    constexpr double kSettled_m = 1e-3, kOmega = 1.8;
    for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
        double change = 0;
        for (const std::size_t c : holes) {
            const int i = int(c % std::size_t(nx)), j = int(c / std::size_t(nx));
            double sum = 0;
            int count = 0;
            const auto take = [&](bool inside, std::size_t d) {
                if (!inside) return;
                sum += z[d];
                ++count;
            };
            take(i > 0, c - 1);
            take(i + 1 < nx, c + 1);
            take(j > 0, c - std::size_t(nx));
            take(j + 1 < ny, c + std::size_t(nx));
            if (count == 0) continue;
            const float v = float(z[c] + kOmega * (sum / count - z[c]));
            change = std::max(change, double(std::abs(v - z[c])));
            z[c] = v;
        }
        if (change < kSettled_m) break;
    }
}

class SmrfFit final : public TerrainFit {
public:
    explicit SmrfFit(const SmrfOptions& o) : o_(o), inv_cell_(1.0 / o.cell_m) {}

    void add(std::span<const engine::CloudPoint> points) override {
        for (const engine::CloudPoint& p : points) {
            const double fx = std::floor(double(p.position.x) * inv_cell_), fy = std::floor(double(p.position.y) * inv_cell_);
            if (!(std::abs(fx) < 1e9 && std::abs(fy) < 1e9) || !std::isfinite(p.position.z)) continue;
            const int ix = int(fx), iy = int(fy);
            float* tile = tileFor(ix >> kTileBits, iy >> kTileBits);
            float& cell = tile[((iy & (kTile - 1)) << kTileBits) | (ix & (kTile - 1))];
            cell = std::min(cell, p.position.z);
            ix_min_ = std::min(ix_min_, ix);
            ix_max_ = std::max(ix_max_, ix);
            iy_min_ = std::min(iy_min_, iy);
            iy_max_ = std::max(iy_max_, iy);
        }
    }

    void fit() override {
        grid_ = TerrainGrid{};
        grid_.cell_m = o_.cell_m;
        if (ix_max_ < ix_min_) return;
        const std::uint64_t nx = std::uint64_t(ix_max_ - ix_min_) + 1, ny = std::uint64_t(iy_max_ - iy_min_) + 1;
        if (nx * ny > o_.max_cells) {
            std::ostringstream s;
            s << "ground: smrf cell_m (--smrf-cell-m) = " << o_.cell_m << ": the cloud spans " << double(nx) * o_.cell_m
              << " x " << double(ny) * o_.cell_m << " m, " << nx * ny << " cells; allowed at most " << o_.max_cells
              << " cells (raise --smrf-cell-m)";
            throw engine::Error(s.str());
        }
        const int w = int(nx), h = int(ny);
        grid_.nx = w;
        grid_.ny = h;
        grid_.x0_m = (double(ix_min_) + 0.5) * o_.cell_m;
        grid_.y0_m = (double(iy_min_) + 0.5) * o_.cell_m;
        // 1) the minimum surface.
        std::vector<float> minimum(std::size_t(w) * std::size_t(h), kEmpty);
        for (const auto& [key, index] : tiles_) {
            const int tx = int(std::int32_t(std::uint32_t(key >> 32))), ty = int(std::int32_t(std::uint32_t(key)));
            const float* tile = tile_data_.data() + std::size_t(index) * kTile * kTile;
            for (int b = 0; b < kTile; ++b)
                for (int a = 0; a < kTile; ++a) {
                    const float v = tile[(b << kTileBits) | a];
                    if (v == kEmpty) continue;
                    const int i = (tx << kTileBits) + a - ix_min_, j = (ty << kTileBits) + b - iy_min_;
                    minimum[std::size_t(j) * std::size_t(w) + std::size_t(i)] = v;
                }
        }
        std::vector<std::uint8_t> observed(minimum.size());
        for (std::size_t c = 0; c < minimum.size(); ++c) observed[c] = minimum[c] != kEmpty;
        grid_.observed_cells = std::size_t(std::count(observed.begin(), observed.end(), 1));
        std::vector<float> surface = minimum;
        inpaint(surface, observed, w, h);

        // 2) objects, by openings of growing radius.
        std::vector<std::uint8_t> object(minimum.size(), 0);
        std::vector<float> eroded, opened, scratch;
        std::vector<int> queue;
        const int radii = std::max(1, int(std::ceil(o_.window_m / o_.cell_m - 1e-9)));
        for (int r = 1; r <= radii; ++r) {
            diskFilter(surface, eroded, w, h, r, false, scratch, queue);
            diskFilter(eroded, opened, w, h, r, true, scratch, queue);
            const float limit = float(o_.slope * double(r) * o_.cell_m);
            for (std::size_t c = 0; c < surface.size(); ++c)
                if (surface[c] - opened[c] > limit) object[c] = 1;
            surface.swap(opened);
        }

        // 3) the terrain from the cells that are ground.
        std::vector<std::uint8_t> ground(minimum.size());
        for (std::size_t c = 0; c < minimum.size(); ++c) ground[c] = observed[c] && !object[c];
        if (std::find(ground.begin(), ground.end(), 1) == ground.end()) ground = observed;
        grid_.z_m = std::move(minimum);
        inpaint(grid_.z_m, ground, w, h);

        // 4)'s threshold per cell, so that classify() looks it up.
        limit_m_.resize(grid_.z_m.size());
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i)
                limit_m_[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                    float(o_.threshold_m + o_.scalar * grid_.slopeAt(grid_.x0_m + i * o_.cell_m, grid_.y0_m + j * o_.cell_m));
    }

    const TerrainGrid& surface() const override { return grid_; }

    bool classify(const glm::vec3& p, float& height_m) const override {
        if (grid_.empty()) {
            height_m = 0.0f;
            return false;
        }
        // TerrainGrid::heightAt, inline: bilinear between cell centres, clamped at the edges.
        const int nx = grid_.nx, ny = grid_.ny;
        const double fx = std::clamp((double(p.x) - grid_.x0_m) * inv_cell_, 0.0, double(nx - 1));
        const double fy = std::clamp((double(p.y) - grid_.y0_m) * inv_cell_, 0.0, double(ny - 1));
        const int i0 = std::min(int(fx), std::max(nx - 2, 0)), j0 = std::min(int(fy), std::max(ny - 2, 0));
        const int i1 = std::min(i0 + 1, nx - 1), j1 = std::min(j0 + 1, ny - 1);
        const double tx = fx - i0, ty = fy - j0;
        const float* z = grid_.z_m.data();
        const std::size_t r0 = std::size_t(j0) * std::size_t(nx), r1 = std::size_t(j1) * std::size_t(nx);
        const double low = (1 - tx) * z[r0 + i0] + tx * z[r0 + i1];
        const double high = (1 - tx) * z[r1 + i0] + tx * z[r1 + i1];
        const double dz = double(p.z) - ((1 - ty) * low + ty * high);
        height_m = float(dz);
        // The threshold of the nearest cell.
        const std::size_t nearest = std::size_t(tx < 0.5 ? i0 : i1) + (ty < 0.5 ? r0 : r1);
        return std::abs(dz) <= double(limit_m_[nearest]);
    }

private:
    float* tileFor(int tx, int ty) {
        const std::uint64_t key = (std::uint64_t(std::uint32_t(tx)) << 32) | std::uint32_t(ty);
        if (key == last_key_ && last_tile_ != nullptr) return last_tile_;
        auto [it, added] = tiles_.try_emplace(key, std::uint32_t(tiles_.size()));
        if (added) {
            if (std::uint64_t(tiles_.size()) * kTile * kTile > 4 * std::uint64_t(o_.max_cells) + kTile * kTile) {
                std::ostringstream s;
                s << "ground: smrf cell_m (--smrf-cell-m) = " << o_.cell_m << ": the cloud covers more than "
                  << o_.max_cells << " cells (raise --smrf-cell-m)";
                throw engine::Error(s.str());
            }
            tile_data_.resize(tile_data_.size() + kTile * kTile, kEmpty);
        }
        last_key_ = key;
        last_tile_ = tile_data_.data() + std::size_t(it->second) * kTile * kTile;
        return last_tile_;
    }

    SmrfOptions o_;
    double inv_cell_;
    std::unordered_map<std::uint64_t, std::uint32_t> tiles_;  // tile (tx, ty) -> its block in tile_data_
    std::vector<float> tile_data_;
    std::uint64_t last_key_ = 0;
    float* last_tile_ = nullptr;
    int ix_min_ = std::numeric_limits<int>::max(), ix_max_ = std::numeric_limits<int>::min();
    int iy_min_ = std::numeric_limits<int>::max(), iy_max_ = std::numeric_limits<int>::min();
    TerrainGrid grid_;
    std::vector<float> limit_m_;  // per cell: threshold_m + scalar * slope
};

class SmrfFilter final : public GroundFilter {
public:
    explicit SmrfFilter(const SmrfOptions& o) : options_(o) {}
    GroundMethod method() const override { return GroundMethod::Smrf; }
    bool perView() const override { return false; }
    std::unique_ptr<TerrainFit> startCloud() const override { return std::make_unique<SmrfFit>(options_); }

private:
    SmrfOptions options_;
};

}  // namespace

void validate(const SmrfOptions& o) {
    if (!(std::isfinite(o.cell_m) && o.cell_m >= 0.01 && o.cell_m <= 1000.0))
        fail("smrf cell_m (--smrf-cell-m)", o.cell_m, "[0.01, 1000] metres");
    if (!(std::isfinite(o.slope) && o.slope > 0.0 && o.slope <= 100.0))
        fail("smrf slope (--smrf-slope)", o.slope, "(0, 100] (rise over run)");
    if (!(std::isfinite(o.window_m) && o.window_m > 0.0 && o.window_m / o.cell_m <= 1000.0))
        fail("smrf window_m (--smrf-window-m)", o.window_m, "> 0 metres and at most 1000 cells of --smrf-cell-m");
    if (!(std::isfinite(o.threshold_m) && o.threshold_m >= 0.0 && o.threshold_m <= 1000.0))
        fail("smrf threshold_m (--smrf-threshold-m)", o.threshold_m, "[0, 1000] metres");
    if (!(std::isfinite(o.scalar) && o.scalar >= 0.0 && o.scalar <= 1000.0))
        fail("smrf scalar (--smrf-scalar)", o.scalar, "[0, 1000] metres per unit slope");
    if (o.max_cells < 1) fail("smrf max_cells", double(o.max_cells), ">= 1");
}

std::unique_ptr<GroundFilter> makeSmrfFilter(const SmrfOptions& o) { return std::make_unique<SmrfFilter>(o); }
std::unique_ptr<TerrainFit> startSmrf(const SmrfOptions& o) { return std::make_unique<SmrfFit>(o); }

std::vector<std::uint8_t> findGroundSmrf(std::span<const glm::vec3> points, const SmrfOptions& o,
                                         TerrainGrid* surface, std::vector<float>* height_m) {
    SmrfFit fit(o);
    std::vector<engine::CloudPoint> chunk;
    constexpr std::size_t kChunk = 1 << 16;
    for (std::size_t i = 0; i < points.size(); i += kChunk) {
        const std::size_t n = std::min(kChunk, points.size() - i);
        chunk.assign(n, engine::CloudPoint{});
        for (std::size_t k = 0; k < n; ++k) chunk[k].position = points[i + k];
        fit.add(chunk);
    }
    fit.fit();
    std::vector<std::uint8_t> ground(points.size());
    if (height_m) height_m->resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        float h = 0;
        ground[i] = fit.classify(points[i], h);
        if (height_m) (*height_m)[i] = h;
    }
    if (surface) *surface = fit.surface();
    return ground;
}

}  // namespace sim
