// sim/src/ground_raster.cpp: see ground_raster.hpp.
#include "ground_raster.hpp"
#include "parallel.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <sstream>
#include <thread>
#include <type_traits>

namespace sim {
namespace {
constexpr int kTileBits = 6, kTile = 1 << kTileBits;  // cells of a sparse tile: 64 x 64
constexpr int kTileCells = kTile * kTile;
// A tile keeps every cell once this many of its cells hold a point (RasterFit::Tile).
constexpr std::size_t kDenseAfter = kTileCells / 16;
}  // namespace

double normalQuantile(double p) {
    if (p > 0.5) return -normalQuantile(1.0 - p);
    const double t = std::sqrt(-2.0 * std::log(p));
    return -(t - (2.515517 + 0.802853 * t + 0.010328 * t * t) /
                     (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t));
}

CellLowest cellLevel(const float* low, int m, std::uint32_t n, double sigma_m) {
    double q[kCellLowest], sq = 0, sz = 0;
    for (int k = 0; k < m; ++k) {
        q[k] = normalQuantile((k + 1 - 0.375) / (double(n) + 0.25));
        sq += q[k];
        sz += low[k];
    }
    CellLowest out{double(low[0]), 0.0};
    if (m >= 2) {
        const double mq = sq / m, mz = sz / m;
        double sqq = 0, sqz = 0;
        for (int k = 0; k < m; ++k) {
            sqq += (q[k] - mq) * (q[k] - mq);
            sqz += (q[k] - mq) * (double(low[k]) - mz);
        }
        if (sqq > 0) out.slope_sigma_m = sqz / sqq;
    }
    if (sigma_m >= 0) {
        double level[kCellLowest];
        for (int k = 0; k < m; ++k) level[k] = double(low[k]) - sigma_m * q[k];
        std::sort(level, level + m);
        out.level_m = m % 2 ? level[m / 2] : 0.5 * (level[m / 2 - 1] + level[m / 2]);
    }
    return out;
}

std::vector<std::uint8_t> sparseEmptyCells(const std::vector<std::uint8_t>& known, int nx, int ny) {
    std::vector<std::uint8_t> out(known.size(), 0);
    const auto at = [&](int i, int j) { return known[std::size_t(j) * std::size_t(nx) + std::size_t(i)] != 0; };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            if (at(i, j)) continue;
            int near = 0, held = 0, cells = 0;
            for (int b = std::max(0, j - 2); b <= std::min(ny - 1, j + 2); ++b)
                for (int a = std::max(0, i - 2); a <= std::min(nx - 1, i + 2); ++a) {
                    ++cells;
                    if (!at(a, b)) continue;
                    ++held;
                    if (std::abs(a - i) <= 1 && std::abs(b - j) <= 1) ++near;
                }
            if (near > 0 && 2 * held < cells) out[std::size_t(j) * std::size_t(nx) + std::size_t(i)] = 1;
        }
    return out;
}

bool holeReaches(const std::vector<bool>& observed, int nx, int ny, const CutSides& cut, double i0, double i1,
                 double j0, double j1) {
    const std::size_t w = std::size_t(std::max(nx, 0)), h = std::size_t(std::max(ny, 0));
    if (w == 0 || h == 0 || observed.size() != w * h || w * h > std::numeric_limits<std::uint32_t>::max()) return false;
    std::vector<bool> seen(w * h, false);
    std::vector<std::uint32_t> stack;
    const auto push = [&](std::size_t i, std::size_t j) {
        const std::size_t c = j * w + i;
        if (observed[c] || seen[c]) return;
        seen[c] = true;
        stack.push_back(std::uint32_t(c));
    };
    for (std::size_t j = 0; j < h; ++j) {
        if (cut.low_x) push(0, j);
        if (cut.high_x) push(w - 1, j);
    }
    for (std::size_t i = 0; i < w; ++i) {
        if (cut.low_y) push(i, 0);
        if (cut.high_y) push(i, h - 1);
    }
    while (!stack.empty()) {
        const std::size_t c = stack.back();
        stack.pop_back();
        const std::size_t i = c % w, j = c / w;
        if (double(i) >= i0 && double(i) <= i1 && double(j) >= j0 && double(j) <= j1) return true;
        if (i > 0) push(i - 1, j);
        if (i + 1 < w) push(i + 1, j);
        if (j > 0) push(i, j - 1);
        if (j + 1 < h) push(i, j + 1);
    }
    return false;
}

namespace {

// out[i] = min (or max) of in[i - r .. i + r] clipped to [0, n), by van Herk and
// Gil-Werman: the row, padded by r identity values on each side, is cut into blocks of
// 2r + 1; each window spans the end of one block and the start of the next, so its
// extreme is that of a running extreme from the block's end and one from the next
// block's start. Three passes without branches on the data, O(n) whatever r.
template <bool kTakeMax>
void runningExtremeOf(const float* in, float* out, int n, int r, std::vector<float>& scratch) {
    constexpr float kIdentity =
        kTakeMax ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();
    const auto fold = [](float a, float b) { return kTakeMax ? std::max(a, b) : std::min(a, b); };
    const std::size_t b = std::size_t(2 * r + 1), m = std::size_t(n) + 2 * std::size_t(r);
    scratch.resize(3 * m);
    float* padded = scratch.data();
    float* from_start = scratch.data() + m;  // extreme of the block's values up to here
    float* to_end = scratch.data() + 2 * m;  // extreme of the block's values from here
    std::fill(padded, padded + r, kIdentity);
    std::copy(in, in + n, padded + r);
    std::fill(padded + r + n, padded + m, kIdentity);
    for (std::size_t start = 0; start < m; start += b) {
        const std::size_t end = std::min(start + b, m);
        from_start[start] = padded[start];
        for (std::size_t k = start + 1; k < end; ++k) from_start[k] = fold(from_start[k - 1], padded[k]);
        to_end[end - 1] = padded[end - 1];
        for (std::size_t k = end - 1; k-- > start;) to_end[k] = fold(to_end[k + 1], padded[k]);
    }
    for (std::size_t i = 0; i < std::size_t(n); ++i) out[i] = fold(to_end[i], from_start[i + b - 1]);
}

}  // namespace

void runningExtreme(const float* in, float* out, int n, int r, bool take_max, std::vector<float>& scratch) {
    if (take_max)
        runningExtremeOf<true>(in, out, n, r, scratch);
    else
        runningExtremeOf<false>(in, out, n, r, scratch);
}

namespace {

// The fill's cell states: a hole, and whether it or one of its four neighbours changed
// since its last update.
enum : std::uint8_t { kHole = 1, kStale = 2, kUpdate = kHole | kStale };
constexpr int kFillLanes = 4;
constexpr double kFillOmega = 1.8;

// One block of kFillLanes rows (the b-th) of a fill sweep (inpaint); returns the largest
// change when kTrack. A function of its own, its pointers in registers: a lambda called
// from several places kept them in memory, where every flag written could alias them.
template <bool kTrack>
double relaxBlock(float* z, std::uint8_t* state, int nx, int ny, int b) {
    const std::size_t row = std::size_t(nx);
    double change = 0;
    const auto update = [&](std::size_t c, int i, int j) {
        double sum = 0;
        int count = 0;
        const auto take = [&](bool inside, std::size_t d) {
            if (!inside) return;
            sum += z[d];
            ++count;
        };
        take(i > 0, c - 1);
        take(i + 1 < nx, c + 1);
        take(j > 0, c - row);
        take(j + 1 < ny, c + row);
        if (count == 0) {
            state[c] = kHole;
            return;
        }
        // sum / count; a division by 4, 2 or 1 is the multiplication by its exact inverse.
        const double mean = count == 4 ? sum * 0.25 : count == 2 ? sum * 0.5 : count == 1 ? sum : sum / count;
        const float v = float(z[c] + kFillOmega * (mean - z[c]));
        if constexpr (kTrack) change = std::max(change, double(std::abs(v - z[c])));
        if (std::bit_cast<std::uint32_t>(v) == std::bit_cast<std::uint32_t>(z[c])) {
            state[c] = kHole;
            return;
        }
        z[c] = v;
        if (i > 0) state[c - 1] |= kStale;
        if (i + 1 < nx) state[c + 1] |= kStale;
        if (j > 0) state[c - row] |= kStale;
        if (j + 1 < ny) state[c + row] |= kStale;
    };
    // update() for a cell with all four neighbours inside the raster: the same operations in
    // the same order (the sum from 0, left, right, up, down), without the edge tests.
    const auto interior = [&](std::size_t c) {
        double sum = 0;
        sum += z[c - 1];
        sum += z[c + 1];
        sum += z[c - row];
        sum += z[c + row];
        const float v = float(z[c] + kFillOmega * (sum * 0.25 - z[c]));
        if constexpr (kTrack) change = std::max(change, double(std::abs(v - z[c])));
        if (std::bit_cast<std::uint32_t>(v) == std::bit_cast<std::uint32_t>(z[c])) {
            state[c] = kHole;
            return;
        }
        z[c] = v;
        state[c - 1] |= kStale;
        state[c + 1] |= kStale;
        state[c - row] |= kStale;
        state[c + row] |= kStale;
    };
    const int j0 = b * kFillLanes, lanes = std::min(kFillLanes, ny - j0);
    for (int t = 0; t < nx + lanes - 1; ++t)
        for (int r = 0; r < lanes; ++r) {
            const int i = t - r;
            if (i < 0 || i >= nx) continue;
            const std::size_t c = std::size_t(j0 + r) * row + std::size_t(i);
            if (state[c] != kUpdate) continue;
            if (i > 0 && i + 1 < nx && j0 + r > 0 && j0 + r + 1 < ny)
                interior(c);
            else
                update(c, i, j0 + r);
        }
    return change;
}

// Runs `sweeps` sweeps of `blocks` blocks each, where block b of sweep s reads and writes
// only blocks b - 1 to b + 1 and must see sweep s's earlier blocks and sweep s - 1's
// later ones: sweep s goes to thread s mod `threads`, and its block b waits until
// sweep s - 1 has finished block b + 1. The thread of sweep s - 1 then works two blocks
// or more below, on rows block b neither reads nor writes, and the thread of sweep s + 1
// two blocks or more above; so every block sees what it sees in one sweep after the
// other, and the result is the same bits whatever the threads. No more threads than
// sweeps, nor than half the blocks (the most sweeps that can be under way at once). False
// when the threads could not be started (nothing was run then).
template <class Block>
bool pipelinedSweeps(int sweeps, int blocks, int threads, const Block& run_block) {
    const int workers = std::max(1, std::min({threads, sweeps, blocks / 2}));
    std::vector<std::atomic<int>> done(static_cast<std::size_t>(sweeps));  // blocks of each sweep finished
    std::atomic<int> go{0};                                                // 1: start, -1: give up
    const auto wait_for = [](const std::atomic<int>& a, int at_least) {
        // Blocks take microseconds: spin a little before sleeping on the value.
        for (int spin = 0; spin < 4096; ++spin)
            if (a.load(std::memory_order_acquire) >= at_least) return;
        for (int v = a.load(std::memory_order_acquire); v < at_least; v = a.load(std::memory_order_acquire))
            a.wait(v, std::memory_order_acquire);
    };
    const auto work = [&](int first) {
        for (int v = go.load(std::memory_order_acquire); v == 0; v = go.load(std::memory_order_acquire))
            go.wait(v, std::memory_order_acquire);
        if (go.load(std::memory_order_acquire) < 0) return;
        for (int s = first; s < sweeps; s += workers)
            for (int b = 0; b < blocks; ++b) {
                if (s > 0) wait_for(done[std::size_t(s - 1)], std::min(b + 2, blocks));
                run_block(b);
                done[std::size_t(s)].store(b + 1, std::memory_order_release);
                done[std::size_t(s)].notify_all();
            }
    };
    std::vector<std::jthread> helpers;
    try {
        helpers.reserve(std::size_t(workers - 1));
        for (int w = 1; w < workers; ++w) helpers.emplace_back(work, w);
    } catch (const std::exception&) {
        go.store(-1, std::memory_order_release);
        go.notify_all();
        return false;  // the helpers started return at once and are joined here
    }
    go.store(1, std::memory_order_release);
    go.notify_all();
    work(0);
    return true;
}

}  // namespace

void inpaint(std::vector<float>& z, const std::vector<std::uint8_t>& known, int nx, int ny, int sweeps, int threads) {
    const std::size_t n = z.size();
    std::vector<int> ring(n, -1);  // ring of each cell: 0 known, k filled in the k-th ring
    std::vector<std::size_t> layer, next_layer;
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
    // Successive over-relaxation (factor kOmega) settles in far fewer sweeps than plain
    // Gauss-Seidel; the sweep order is fixed (row by row), so the result is too.
    // A cell is computed again only when its own value or one of its four neighbours'
    // changed since its last update (bit for bit): otherwise that update would repeat the
    // last one, which left the cell as it was. Skipping it changes nothing, and a wide
    // hole that has settled (a sparse survey's empty tiles) costs a flag per cell and sweep.
    // The rows are swept kFillLanes at a time, each lane a cell behind the one above it: a
    // cell still sees its left and upper neighbours updated and its right and lower ones
    // not, as in row order, so the values are those of row order; the lanes' cells are
    // not neighbours, so the processor overlaps their updates.
    constexpr int kMaxSweeps = 100;
    constexpr double kSettled_m = 1e-3;
    // Every cell the rings reached is a hole to relax; the rings are not needed after.
    std::vector<std::uint8_t> state(n, 0);
    for (std::size_t c = 0; c < n; ++c)
        if (ring[c] > 0) state[c] = kUpdate;
    ring = {};
    layer = {};
    next_layer = {};
    float* const zp = z.data();
    std::uint8_t* const sp = state.data();
    const int blocks = (ny + kFillLanes - 1) / kFillLanes;
    if (sweeps > 0) {
        if (threads > 1 && blocks > 2 && sweeps > 1 &&
            pipelinedSweeps(sweeps, blocks, threads, [&](int b) { relaxBlock<false>(zp, sp, nx, ny, b); }))
            return;
        for (int k = 0; k < sweeps; ++k)
            for (int b = 0; b < blocks; ++b) relaxBlock<false>(zp, sp, nx, ny, b);
        return;
    }
    for (int k = 0; k < kMaxSweeps; ++k) {
        double change = 0;
        for (int b = 0; b < blocks; ++b) change = std::max(change, relaxBlock<true>(zp, sp, nx, ny, b));
        if (change < kSettled_m) break;
    }
}

RasterFit::RasterFit(double cell_m, std::size_t max_cells, const char* cell_option)
    : cell_m_(cell_m), inv_cell_(1.0 / cell_m), max_cells_(max_cells), cell_option_(cell_option) {}

void RasterFit::keepLowest(Cell& cell, float z, std::uint16_t view) {
    // The kCellLowest lowest heights, ascending, ordered by (height, view): the same
    // whatever the order the points come in, ties between views included.
    const auto below = [&](int k) { return cell.low[k] > z || (cell.low[k] == z && cell.view[k] > view); };
    if (!below(kCellLowest - 1)) return;
    int k = kCellLowest - 1;
    for (; k > 0 && below(k - 1); --k) {
        cell.low[k] = cell.low[k - 1];
        cell.view[k] = cell.view[k - 1];
    }
    cell.low[k] = z;
    cell.view[k] = view;
}

void RasterFit::keepViewLow(std::uint64_t key, const ViewLow& low) {
    if (too_many_view_blocks_) return;
    // The lowest point, ties broken by position: the same whatever the order.
    const auto lower = [](const ViewLow& a, const ViewLow& b) {
        return a.z < b.z || (a.z == b.z && (a.x < b.x || (a.x == b.x && a.y < b.y)));
    };
    // A scan's next point mostly falls in the same view's block: no lookup then (a map's
    // elements stay where they are while it grows).
    if (last_view_low_ != nullptr && key == last_view_key_) {
        if (lower(low, *last_view_low_)) *last_view_low_ = low;
        return;
    }
    auto [it, added] = view_lows_.try_emplace(key, low);
    if (!added && lower(low, it->second)) it->second = low;
    last_view_key_ = key;
    last_view_low_ = &it->second;
    if (view_lows_.size() > max_cells_) {  // bounded like the raster: no correction
        too_many_view_blocks_ = true;
        view_lows_ = {};
        last_view_low_ = nullptr;
    }
}

void RasterFit::add(std::span<const core::CloudPoint> points) {
    for (const core::CloudPoint& p : points) {
        const double fx = std::floor(double(p.position.x) * inv_cell_);
        const double fy = std::floor(double(p.position.y) * inv_cell_);
        if (!(std::abs(fx) < 1e9 && std::abs(fy) < 1e9) || !std::isfinite(p.position.z)) continue;
        const int ix = int(fx), iy = int(fy);
        Tile* tile = tileFor(ix >> kTileBits, iy >> kTileBits);
        const int c = ((iy & (kTile - 1)) << kTileBits) | (ix & (kTile - 1));
        Cell& cell = tile->dense ? tile->dense[c] : cellAt(*tile, c);
        cell.n += cell.n < std::numeric_limits<std::uint32_t>::max();
        keepLowest(cell, p.position.z, p.view);
        static_assert(kViewBlock == 4);
        keepViewLow((std::uint64_t(p.view) << 48) | (std::uint64_t(std::uint32_t(ix >> 2) & 0xffffffu) << 24) |
                        (std::uint32_t(iy >> 2) & 0xffffffu),
                    ViewLow{p.position.z, p.position.x, p.position.y});
        ix_min_ = std::min(ix_min_, ix);
        ix_max_ = std::max(ix_max_, ix);
        iy_min_ = std::min(iy_min_, iy);
        iy_max_ = std::max(iy_max_, iy);
    }
}

namespace {
// A raster that only gathers points, for addAll()'s other threads.
class Gatherer final : public RasterFit {
  public:
    using RasterFit::RasterFit;

  private:
    void fitTerrain(std::vector<float>&, const std::vector<std::uint8_t>&) override {}
};
}  // namespace

void RasterFit::addAll(std::span<const core::CloudPoint> points, int threads) {
    constexpr std::size_t kMinShare = std::size_t(1) << 16;
    const std::size_t parts = std::clamp<std::size_t>(points.size() / kMinShare, 1, std::size_t(std::max(threads, 1)));
    if (parts == 1) {
        add(points);
        return;
    }
    std::vector<std::unique_ptr<Gatherer>> others;
    for (std::size_t p = 1; p < parts; ++p)
        others.push_back(std::make_unique<Gatherer>(cell_m_, max_cells_, cell_option_));
    const auto share = [&](std::size_t p) {
        return points.subspan(points.size() * p / parts, points.size() * (p + 1) / parts - points.size() * p / parts);
    };
    Workers pool{int(parts)};
    pool.run(parts, [&](std::size_t p) {
        if (p == 0)
            add(share(0));
        else
            others[p - 1]->add(share(p));
    });
    for (const auto& other : others) merge(*other);
}

void RasterFit::merge(const RasterFit& other) {
    for (const auto& [key, index] : other.tiles_) {
        Tile* mine = tileFor(int(std::uint32_t(key >> 32)), int(std::uint32_t(key)));
        const Tile& theirs = other.tile_data_[index];
        for (int c = 0; c < kTileCells; ++c) {
            const Cell* found = findCell(theirs, c);
            if (found == nullptr || found->n == 0) continue;
            const Cell& t = *found;
            Cell& m = cellAt(*mine, c);
            m.n = std::uint32_t(
                std::min<std::uint64_t>(std::uint64_t(m.n) + t.n, std::numeric_limits<std::uint32_t>::max()));
            for (std::size_t k = 0; k < std::min<std::size_t>(t.n, kCellLowest); ++k)
                keepLowest(m, t.low[k], t.view[k]);
        }
    }
    if (other.too_many_view_blocks_) {
        too_many_view_blocks_ = true;
        view_lows_ = {};
        last_view_low_ = nullptr;
    }
    for (const auto& [key, low] : other.view_lows_) keepViewLow(key, low);
    ix_min_ = std::min(ix_min_, other.ix_min_);
    ix_max_ = std::max(ix_max_, other.ix_max_);
    iy_min_ = std::min(iy_min_, other.iy_min_);
    iy_max_ = std::max(iy_max_, other.iy_max_);
}

// Low outliers (ours, not the papers'; declared in ground_raster.hpp). A quantile, not
// the lowest, so that a cluster of low returns (multipath under a real survey, tens of
// metres low and scattered over a few hundred square metres) is judged against the
// ground around it; a low one, so that the foot of a cliff or a wall, about half of its
// neighbourhood, is not.
namespace {
constexpr int kLowOutlierReach = 5;
constexpr double kLowOutlierQuantile = 0.2;
constexpr std::size_t kLowOutlierMinCells = 8;
constexpr int kLowOutlierRounds = 4;
}  // namespace

std::vector<int> lowOutliers(const std::vector<const float*>& low, const std::vector<int>& m, int w, int h,
                             double gap_m) {
    const std::size_t n = low.size();
    std::vector<int> skip(n, 0);
    // What each cell offers its neighbours in a round: its lowest height not skipped
    // (`offers` 0 when it has none), in one raster so that a window reads rows of it.
    std::vector<float> offer(n, 0.0f);
    std::vector<std::uint8_t> offers(n, 0);
    const auto refresh = [&](std::size_t c) {
        offers[c] = skip[c] < m[c];
        offer[c] = offers[c] ? low[c][skip[c]] : 0.0f;
    };
    for (std::size_t c = 0; c < n; ++c) refresh(c);
    // The cells to test: every one in the first round; after it, only those with a cell
    // that changed within reach (themselves included). Any other cell sees what it saw in
    // the round before and was not an outlier then, so it would not be one now.
    std::vector<std::uint8_t> test(n, 1);
    std::vector<std::size_t> changed;
    std::vector<float> around;
    for (int round = 0; round < kLowOutlierRounds; ++round) {
        changed.clear();
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
                if (!test[c] || !offers[c]) continue;
                around.clear();
                const int a0 = std::max(0, i - kLowOutlierReach), a1 = std::min(w - 1, i + kLowOutlierReach);
                for (int b = std::max(0, j - kLowOutlierReach); b <= std::min(h - 1, j + kLowOutlierReach); ++b) {
                    const std::size_t row = std::size_t(b) * std::size_t(w);
                    for (int a = a0; a <= a1; ++a) {
                        const std::size_t d = row + std::size_t(a);
                        if (offers[d] && d != c) around.push_back(offer[d]);
                    }
                }
                if (around.size() < kLowOutlierMinCells) continue;
                const auto q = around.begin() + std::ptrdiff_t(double(around.size() - 1) * kLowOutlierQuantile);
                std::nth_element(around.begin(), q, around.end());
                if (double(offer[c]) < double(*q) - gap_m) changed.push_back(c);
            }
        if (changed.empty()) break;
        // Every decision of the round was made on the counts it started with.
        std::fill(test.begin(), test.end(), 0);
        for (const std::size_t c : changed) {
            ++skip[c];
            refresh(c);
            const int i = int(c % std::size_t(w)), j = int(c / std::size_t(w));
            for (int b = std::max(0, j - kLowOutlierReach); b <= std::min(h - 1, j + kLowOutlierReach); ++b)
                for (int a = std::max(0, i - kLowOutlierReach); a <= std::min(w - 1, i + kLowOutlierReach); ++a)
                    test[std::size_t(b) * std::size_t(w) + std::size_t(a)] = 1;
        }
    }
    return skip;
}

bool RasterFit::cellSpread(const Cell& cell, double& spread_m) const {
    if (cell.n < std::uint32_t(kCellLowest)) return false;
    const float top = cell.low[2] + float(kThicknessWindow_m / z_unit_m_);
    int kept = 3;
    while (kept < kCellLowest && cell.low[kept] <= top) ++kept;
    if (kept < kThicknessMinPoints) return false;
    spread_m = std::max(0.0, cellLevel(cell.low, kept, cell.n, -1).slope_sigma_m);
    return true;
}

void RasterFit::thicknessSamples(const glm::dvec2& lo, const glm::dvec2& hi, std::vector<double>& out) const {
    for (const auto& [key, index] : tiles_) {
        const int tx = int(std::int32_t(std::uint32_t(key >> 32))), ty = int(std::int32_t(std::uint32_t(key)));
        const Tile& tile = tile_data_[index];
        for (int b = 0; b < kTile; ++b)
            for (int a = 0; a < kTile; ++a) {
                const Cell* cell = findCell(tile, (b << kTileBits) | a);
                if (cell == nullptr) continue;
                const double x = (double((tx << kTileBits) + a) + 0.5) * cell_m_;
                const double y = (double((ty << kTileBits) + b) + 0.5) * cell_m_;
                double spread_m = 0;
                if (x >= lo.x && x < hi.x && y >= lo.y && y < hi.y && cellSpread(*cell, spread_m))
                    out.push_back(spread_m);
            }
    }
}

void RasterFit::setExtent(const glm::dvec2& lo, const glm::dvec2& hi) {
    // The cells whose centre (i + 0.5) * cell_m lies in [lo, hi).
    const auto first = [&](double v) { return std::clamp(std::ceil(v * inv_cell_ - 0.5), -1e9, 1e9); };
    extent_i0_ = int(first(lo.x));
    extent_i1_ = int(first(hi.x)) - 1;
    extent_j0_ = int(first(lo.y));
    extent_j1_ = int(first(hi.y)) - 1;
}

void RasterFit::fit() {
    grid_ = TerrainGrid{};
    grid_.cell_m = cell_m_;
    observed_.clear();
    if (ix_max_ < ix_min_) return;
    if (extent_i0_ <= extent_i1_ && extent_j0_ <= extent_j1_) {
        ix_min_ = std::min(ix_min_, extent_i0_);
        ix_max_ = std::max(ix_max_, extent_i1_);
        iy_min_ = std::min(iy_min_, extent_j0_);
        iy_max_ = std::max(iy_max_, extent_j1_);
    }
    const std::uint64_t nx = std::uint64_t(ix_max_ - ix_min_) + 1, ny = std::uint64_t(iy_max_ - iy_min_) + 1;
    if (nx * ny > max_cells_) {
        std::ostringstream s;
        s << "ground: " << cell_option_ << " = " << cell_m_ << ": the cloud spans " << double(nx) * cell_m_ << " x "
          << double(ny) * cell_m_ << " m, " << nx * ny << " cells; allowed at most " << max_cells_
          << " cells (raise it)";
        throw core::Error(s.str());
    }
    const int w = int(nx), h = int(ny);
    grid_.nx = w;
    grid_.ny = h;
    grid_.x0_m = (double(ix_min_) + 0.5) * cell_m_;
    grid_.y0_m = (double(iy_min_) + 0.5) * cell_m_;
    // 1) the ground thickness: the median spread of the lowest heights over the cells
    // that hold at least kCellLowest points, visited in raster order.
    std::vector<const Cell*> cells(std::size_t(w) * std::size_t(h), nullptr);
    for (const auto& [key, index] : tiles_) {
        const int tx = int(std::int32_t(std::uint32_t(key >> 32))), ty = int(std::int32_t(std::uint32_t(key)));
        const Tile& tile = tile_data_[index];
        for (int b = 0; b < kTile; ++b)
            for (int a = 0; a < kTile; ++a) {
                const Cell* cell = findCell(tile, (b << kTileBits) | a);
                if (cell == nullptr || cell->n == 0) continue;
                const int i = (tx << kTileBits) + a - ix_min_, j = (ty << kTileBits) + b - iy_min_;
                cells[std::size_t(j) * std::size_t(w) + std::size_t(i)] = cell;
            }
    }
    std::vector<double> spreads;
    for (const Cell* cell : cells) {
        double spread_m = 0;
        if (cell && cellSpread(*cell, spread_m)) spreads.push_back(spread_m);
    }
    if (!spreads.empty()) {
        const auto mid = spreads.begin() + std::ptrdiff_t(spreads.size() / 2);
        std::nth_element(spreads.begin(), mid, spreads.end());
        grid_.ground_sigma_m = *mid;
    }
    if (fixed_sigma_m_ >= 0) grid_.ground_sigma_m = fixed_sigma_m_;
    // 2) the ground-level surface: each cell's level for that thickness, then the terrain.
    // A cell's lowest heights, each less its view's error at the cell's centre when
    // `corrected` (ascending); returns how many there are.
    // Low outliers (low_outlier_m_ > 0): how many of each cell's lowest heights to skip.
    std::vector<int> skip;
    if (low_outlier_m_ > 0) {
        std::vector<const float*> low(cells.size(), nullptr);
        std::vector<int> m(cells.size(), 0);
        for (std::size_t c = 0; c < cells.size(); ++c)
            if (cells[c]) {
                low[c] = cells[c]->low;
                m[c] = int(std::min<std::uint32_t>(cells[c]->n, kCellLowest));
            }
        skip = lowOutliers(low, m, w, h, low_outlier_m_);
        for (std::size_t c = 0; c < cells.size(); ++c)
            if (cells[c] && skip[c] >= m[c]) cells[c] = nullptr;  // only outliers: interpolated
    }
    const auto lowest = [&](std::size_t c, bool corrected, float* low) {
        const Cell* cell = cells[c];
        const int first = skip.empty() ? 0 : skip[c];
        const int m = int(std::min<std::uint32_t>(cell->n, kCellLowest)) - first;
        std::copy(cell->low + first, cell->low + first + m, low);
        if (corrected) {
            const double x = grid_.x0_m + double(c % std::size_t(w)) * cell_m_;
            const double y = grid_.y0_m + double(c / std::size_t(w)) * cell_m_;
            for (int k = 0; k < m; ++k) low[k] = float(double(low[k]) - viewError(cell->view[k], x, y));
            std::sort(low, low + m);
        }
        return m;
    };
    std::vector<float> minimum(cells.size(), kNoPoint);
    const auto levels = [&](bool corrected) {
        minimum.assign(cells.size(), kNoPoint);  // fitTerrain() may have taken it
        float low[kCellLowest];
        for (std::size_t c = 0; c < cells.size(); ++c) {
            const Cell* cell = cells[c];
            if (!cell) continue;
            const int m = lowest(c, corrected, low);
            // Thin: the minimum, as SMRF and CSF have it.
            if (!corrected && grid_.ground_sigma_m < kThinGround_m / z_unit_m_) {
                minimum[c] = low[0];
                continue;
            }
            if (corrected) {  // the views line up: the third lowest (two low outliers dropped)
                minimum[c] = low[std::min(2, m - 1)];
                continue;
            }
            // Heights far above the third lowest (an object's in a cell it shares with
            // the ground) are left out; the median below rejects up to two low outliers.
            const float top =
                low[std::min(2, m - 1)] + float(kLevelWindowSigmas * grid_.ground_sigma_m + kLevelWindow_m / z_unit_m_);
            int kept = 1;
            while (kept < m && low[kept] <= top) ++kept;
            minimum[c] =
                float(cellLevel(low, kept, cell->n - std::uint32_t(skip.empty() ? 0 : skip[c]), grid_.ground_sigma_m)
                          .level_m);
        }
    };
    std::vector<std::uint8_t> observed(minimum.size());
    for (std::size_t c = 0; c < minimum.size(); ++c) observed[c] = cells[c] != nullptr;
    grid_.observed_cells = std::size_t(std::count(observed.begin(), observed.end(), 1));
    observed_.assign(observed.begin(), observed.end());
    levels(false);
    fitTerrain(minimum, observed);
    // 3) a ground thicker than kRegisterViews_m: each view's height error against that terrain; when the views were corrected,
    // the levels again from the corrected heights (a thinner ground), and the terrain.
    if (grid_.ground_sigma_m >= kRegisterViews_m / z_unit_m_ && correctViews()) {
        levels(true);
        fitTerrain(minimum, observed);
    }
}

namespace {
double median(std::vector<double> v) {
    if (v.empty()) return 0;
    const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}
}  // namespace

bool RasterFit::correctViews() {
    view_planes_.clear();
    if (too_many_view_blocks_ || view_lows_.empty() || grid_.empty()) return false;
    std::vector<std::pair<std::uint64_t, ViewLow>> lows(view_lows_.begin(), view_lows_.end());
    std::sort(lows.begin(), lows.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const std::size_t views = std::size_t(lows.back().first >> 48) + 1;
    if ((lows.front().first >> 48) == (lows.back().first >> 48)) return false;  // one view: nothing to register
    std::vector<ViewPlane> planes(views);
    std::vector<double> kept_residuals, r, dev;
    std::size_t corrected = 0;
    for (std::size_t a = 0; a < lows.size();) {
        std::size_t b = a;
        while (b < lows.size() && (lows[b].first >> 48) == (lows[a].first >> 48)) ++b;
        const std::size_t view = std::size_t(lows[a].first >> 48), n = b - a;
        ViewPlane plane;
        if (n >= 3) {
            for (std::size_t k = a; k < b; ++k) {
                plane.x0_m += lows[k].second.x / double(n);
                plane.y0_m += lows[k].second.y / double(n);
            }
            r.assign(n, 0);
            for (std::size_t k = a; k < b; ++k)
                r[k - a] = double(lows[k].second.z) - grid_.heightAt(lows[k].second.x, lows[k].second.y);
            // A plane by least squares over the blocks near the current estimate (roofs and
            // canopies that hide a block's ground lie far above it), twice.
            // The start: the median of the residuals within kViewReach_m of the terrain
            // (where most blocks' lowest point is a canopy or a roof, the median of all
            // of them lies metres up). None there: nothing to register this view by.
            dev.clear();  // the residuals within reach, until the passes reuse it
            for (const double v : r)
                if (std::abs(v) <= kViewReach_m / z_unit_m_) dev.push_back(v);
            if (dev.size() < 3) {
                planes[view] = plane;
                a = b;
                continue;
            }
            plane.offset_m = median(dev);
            for (int pass = 0; pass < 2; ++pass) {
                dev.resize(n);
                const auto at = [&](std::size_t k) {
                    return plane.offset_m + plane.dzdx * (lows[k].second.x - plane.x0_m) +
                           plane.dzdy * (lows[k].second.y - plane.y0_m);
                };
                for (std::size_t k = a; k < b; ++k) dev[k - a] = std::abs(r[k - a] - at(k));
                const double gate =
                    std::clamp(3.0 * 1.4826 * median(dev), kViewGate_m / z_unit_m_, kViewReach_m / z_unit_m_);
                double sxx = 0, sxy = 0, syy = 0, sx = 0, sy = 0, s1 = 0, sr = 0, sxr = 0, syr = 0;
                for (std::size_t k = a; k < b; ++k) {
                    if (dev[k - a] > gate) continue;
                    const double x = lows[k].second.x - plane.x0_m, y = lows[k].second.y - plane.y0_m, v = r[k - a];
                    sxx += x * x, sxy += x * y, syy += y * y, sx += x, sy += y, s1 += 1, sr += v, sxr += x * v,
                        syr += y * v;
                }
                if (s1 < 3) break;
                // Normal equations of v = c0 + c1 x + c2 y, by Cramer's rule.
                const double m[3][3] = {{s1, sx, sy}, {sx, sxx, sxy}, {sy, sxy, syy}}, rhs[3] = {sr, sxr, syr};
                const auto det3 = [](const double q[3][3]) {
                    return q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) -
                           q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
                           q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
                };
                const double d = det3(m);
                if (!(std::abs(d) > 1e-9)) {
                    plane.offset_m = sr / s1;
                    break;
                }
                double c[3];
                for (int col = 0; col < 3; ++col) {
                    double q[3][3];
                    for (int i = 0; i < 3; ++i)
                        for (int j = 0; j < 3; ++j) q[i][j] = j == col ? rhs[i] : m[i][j];
                    c[col] = det3(q) / d;
                }
                plane.offset_m = c[0];
                plane.dzdx = c[1];
                plane.dzdy = c[2];
            }
            const double gate =
                std::clamp(3.0 * 1.4826 * median(dev), kViewGate_m / z_unit_m_, kViewReach_m / z_unit_m_);
            for (std::size_t k = a; k < b; ++k) {
                const double v = r[k - a] - (plane.offset_m + plane.dzdx * (lows[k].second.x - plane.x0_m) +
                                             plane.dzdy * (lows[k].second.y - plane.y0_m));
                if (std::abs(v) <= gate) kept_residuals.push_back(v);
            }
            ++corrected;
        }
        planes[view] = plane;
        a = b;
    }
    if (kept_residuals.empty()) return false;
    for (double& v : kept_residuals) v = std::abs(v);
    grid_.ground_sigma_uncorrected_m = grid_.ground_sigma_m;
    grid_.ground_sigma_m = 1.4826 * median(kept_residuals);
    grid_.views_corrected = corrected;
    view_planes_ = std::move(planes);
    return true;
}

double RasterFit::viewError(std::size_t view, double x, double y) const {
    if (view >= view_planes_.size()) return 0;
    const ViewPlane& v = view_planes_[view];
    return v.offset_m + v.dzdx * (x - v.x0_m) + v.dzdy * (y - v.y0_m);
}

bool RasterFit::classify(const core::CloudPoint& p, float& height_m) const {
    if (view_planes_.empty()) return classify(p.position, height_m);
    const double error_m = viewError(p.view, p.position.x, p.position.y);
    return classify(glm::vec3(p.position.x, p.position.y, float(double(p.position.z) - error_m)), height_m);
}

bool RasterFit::classify(const glm::vec3& p, float& height_m) const {
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

RasterFit::Tile* RasterFit::tileFor(int tx, int ty) {
    const std::uint64_t key = (std::uint64_t(std::uint32_t(tx)) << 32) | std::uint32_t(ty);
    if (key == last_key_ && last_tile_ != nullptr) return last_tile_;
    auto [it, added] = tiles_.try_emplace(key, std::uint32_t(tiles_.size()));
    if (added) {
        if (std::uint64_t(tiles_.size()) * kTileCells > 4 * std::uint64_t(max_cells_) + kTileCells) {
            std::ostringstream s;
            s << "ground: " << cell_option_ << " = " << cell_m_ << ": the cloud covers more than " << max_cells_
              << " cells (raise it)";
            throw core::Error(s.str());
        }
        Tile& tile = tile_data_.emplace_back();
        tile.slot = std::make_unique<std::uint16_t[]>(kTileCells);  // zeroed: no cell kept
    }
    last_key_ = key;
    last_tile_ = &tile_data_[it->second];
    return last_tile_;
}

RasterFit::Cell& RasterFit::cellAt(Tile& tile, int c) {
    if (tile.dense) return tile.dense[c];
    if (const std::uint16_t s = tile.slot[c]; s != 0) return tile.few[s - 1];
    Cell empty{};
    std::fill(std::begin(empty.low), std::end(empty.low), kNoPoint);
    if (tile.few.size() < kDenseAfter) {
        tile.few.push_back(empty);
        tile.slot[c] = std::uint16_t(tile.few.size());
        return tile.few.back();
    }
    // Many cells hold a point: keep every cell, and the lookup goes.
    tile.dense = std::make_unique_for_overwrite<Cell[]>(kTileCells);
    std::fill(tile.dense.get(), tile.dense.get() + kTileCells, empty);
    for (int k = 0; k < kTileCells; ++k)
        if (tile.slot[k] != 0) tile.dense[k] = tile.few[tile.slot[k] - 1];
    tile.slot.reset();
    tile.few = {};
    return tile.dense[c];
}

const RasterFit::Cell* RasterFit::findCell(const Tile& tile, int c) {
    if (tile.dense) return &tile.dense[c];
    const std::uint16_t s = tile.slot[c];
    return s != 0 ? &tile.few[s - 1] : nullptr;
}

std::vector<std::uint8_t> classifyInMemory(TerrainFit& fit, std::span<const glm::vec3> points, TerrainGrid* surface,
                                           std::vector<float>* height_m) {
    std::vector<core::CloudPoint> chunk;
    constexpr std::size_t kChunk = 1 << 16;
    for (std::size_t i = 0; i < points.size(); i += kChunk) {
        const std::size_t n = std::min(kChunk, points.size() - i);
        chunk.assign(n, core::CloudPoint{});
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
