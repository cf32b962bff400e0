// viewer/src/points/lod.cpp: level-of-detail order, culling and point budget for the viewer
// (paper §IV-A asks for an immersive viewer; the budget keeps it at HMD rates).
#include <viewer/lod.hpp>

#include <core/random.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace viewer {

namespace {
/// Spreads the low 16 bits of v to the even bits of the result.
std::uint32_t spreadBits(std::uint32_t v) {
    v &= 0xFFFFu;
    v = (v | (v << 8)) & 0x00FF00FFu;
    v = (v | (v << 4)) & 0x0F0F0F0Fu;
    v = (v | (v << 2)) & 0x33333333u;
    v = (v | (v << 1)) & 0x55555555u;
    return v;
}
}  // namespace

std::uint32_t spreadOrderKey(const glm::dvec3& p, const core::Bounds& box) {
    const glm::dvec3 size = box.size();
    auto unit = [](double v, double lo, double extent) {
        if (!(extent > 0.0)) return std::uint32_t{0};
        return static_cast<std::uint32_t>(std::clamp((v - lo) / extent, 0.0, 1.0) * 65535.0);
    };
    const std::uint32_t morton =
        spreadBits(unit(p.x, box.lo.x, size.x)) | (spreadBits(unit(p.y, box.lo.y, size.y)) << 1);
    // The top 6 bits name one of 8 x 8 blocks; reversed, consecutive blocks lie far apart,
    // so any run of whole blocks covers the box evenly.
    std::uint32_t block = morton >> 26, reversed = 0;
    for (int b = 0; b < 6; ++b) reversed |= ((block >> b) & 1u) << (5 - b);
    return (reversed << 26) | (morton & ((1u << 26) - 1u));
}

std::vector<LodCell> buildLodOrder(std::vector<core::CloudPoint>& points, const LodOptions& options) {
    std::vector<LodCell> cells;
    const std::size_t n = points.size();
    if (n == 0) return cells;
    core::Bounds all;
    for (const auto& p : points) all.extend(glm::dvec3(p.position));
    const std::size_t per_cell = std::max<std::size_t>(options.cell_points, 1);
    const auto side = static_cast<std::size_t>(std::max(1.0, std::ceil(std::sqrt(double(n) / double(per_cell)))));
    const glm::dvec3 size = all.size();
    auto axisCell = [side](double v, double lo, double extent) {
        if (extent <= 0.0) return std::size_t{0};
        const auto c = static_cast<std::size_t>((v - lo) / extent * double(side));
        return std::min(c, side - 1);
    };
    // Counting sort by cell (stable), then a seeded shuffle inside each cell.
    std::vector<std::uint32_t> cell_of(n);
    std::vector<std::size_t> start(side * side + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 p(points[i].position);
        const std::size_t c = axisCell(p.y, all.lo.y, size.y) * side + axisCell(p.x, all.lo.x, size.x);
        cell_of[i] = static_cast<std::uint32_t>(c);
        ++start[c + 1];
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<core::CloudPoint> sorted(n);
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted[next[cell_of[i]]++] = points[i];
    std::mt19937_64 rng(options.seed);
    std::vector<std::uint32_t> keys;
    std::vector<std::uint32_t> order;
    std::vector<core::CloudPoint> layer;
    for (std::size_t c = 0; c < side * side; ++c) {
        const std::size_t first = start[c], count = start[c + 1] - start[c];
        if (count == 0) continue;
        const auto cell_begin = sorted.begin() + static_cast<std::ptrdiff_t>(first);
        core::shuffle(cell_begin, cell_begin + static_cast<std::ptrdiff_t>(count), rng);
        LodCell cell{first, count, {}};
        for (std::size_t i = first; i < first + count; ++i) cell.bounds.extend(glm::dvec3(sorted[i].position));
        // Layers of the shuffled cell: [0, n/64), [n/64, n/32), ... [n/2, n). Each is a
        // uniform random subsample; ordering each one by place (spreadOrderKey) lets the GPU
        // write neighbouring pixels together without changing which points a prefix holds
        // beyond the one layer it ends in.
        std::size_t lo = 0;
        for (int k = kLodLayers - 1; k >= 0; --k) {
            const std::size_t hi = count >> k;
            if (hi > lo + 1) {
                const std::size_t m = hi - lo;
                keys.resize(m);
                order.resize(m);
                for (std::size_t i = 0; i < m; ++i) {
                    keys[i] = spreadOrderKey(glm::dvec3(sorted[first + lo + i].position), cell.bounds);
                    order[i] = static_cast<std::uint32_t>(i);
                }
                std::stable_sort(order.begin(), order.end(),
                                 [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
                layer.assign(cell_begin + static_cast<std::ptrdiff_t>(lo),
                             cell_begin + static_cast<std::ptrdiff_t>(hi));
                for (std::size_t i = 0; i < m; ++i) sorted[first + lo + i] = layer[order[i]];
            }
            lo = std::max(lo, hi);
        }
        cells.push_back(cell);
    }
    points = std::move(sorted);
    return cells;
}

std::vector<bool> visibleInAny(std::span<const render::Frustum> frusta, std::span<const core::Bounds> boxes) {
    std::vector<bool> visible(boxes.size(), false);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        if (boxes[i].empty()) continue;
        for (const auto& f : frusta)
            if (f.intersects(boxes[i])) {
                visible[i] = true;
                break;
            }
    }
    return visible;
}

double screenImportance(const core::Bounds& box, const glm::dvec3& eye) {
    if (box.empty()) return 0.0;
    const double r = std::max(0.5 * glm::length(box.size()), 1e-6);
    const double d = std::max(glm::length(box.centre() - eye), r);
    return (r / d) * (r / d);
}

std::vector<std::size_t> allocateBudget(std::span<const double> importance, std::span<const std::size_t> sizes,
                                        std::size_t budget) {
    const std::size_t n = std::min(importance.size(), sizes.size());
    std::vector<std::size_t> counts(n, 0);
    std::vector<std::size_t> order;
    double weight = 0.0;
    std::size_t total = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!(importance[i] > 0.0) || sizes[i] == 0) continue;
        order.push_back(i);
        weight += importance[i];
        total += sizes[i];
    }
    if (budget == 0 || total <= budget) {
        for (std::size_t i : order) counts[i] = sizes[i];
        return counts;
    }
    // Water filling: cells saturate in order of sizes / importance (the lambda at which
    // they would be full); the rest share what is left in proportion to their importance.
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return double(sizes[a]) * importance[b] < double(sizes[b]) * importance[a];
    });
    double left = double(budget);
    std::size_t k = 0;
    for (; k < order.size(); ++k) {
        const std::size_t i = order[k];
        if (double(sizes[i]) > left / weight * importance[i]) break;
        counts[i] = sizes[i];
        left -= double(sizes[i]);
        weight -= importance[i];
    }
    const double lambda = weight > 0.0 ? left / weight : 0.0;
    for (; k < order.size(); ++k) {
        const std::size_t i = order[k];
        counts[i] = std::min(sizes[i], static_cast<std::size_t>(std::floor(lambda * importance[i])));
    }
    // Rounding guard: floating-point lambda can overshoot by a point here and there; take
    // the excess back from the least important cells.
    std::size_t sum = std::accumulate(counts.begin(), counts.end(), std::size_t{0});
    if (sum > budget) {
        std::vector<std::size_t> by_importance(order);
        std::sort(by_importance.begin(), by_importance.end(),
                  [&](std::size_t a, std::size_t b) { return importance[a] < importance[b]; });
        for (std::size_t i : by_importance) {
            const std::size_t take = std::min(counts[i], sum - budget);
            counts[i] -= take;
            sum -= take;
            if (sum == budget) break;
        }
    }
    return counts;
}

bool LodFocus::touches(const core::Bounds& box) const {
    if (box.empty()) return false;
    for (const FocusSphere& s : spheres) {
        const glm::dvec3 nearest = glm::clamp(s.centre_local, box.lo, box.hi);
        if (glm::length(nearest - s.centre_local) <= s.radius_m) return true;
    }
    return false;
}

std::vector<std::size_t> allocateFocusedBudget(std::span<const double> importance, std::span<const std::size_t> sizes,
                                               const std::vector<bool>& focused, std::size_t budget) {
    const std::size_t n = std::min(importance.size(), sizes.size());
    std::vector<double> rest(importance.begin(), importance.begin() + static_cast<std::ptrdiff_t>(n));
    std::size_t taken = 0;
    bool any = false;
    for (std::size_t i = 0; i < n && i < focused.size(); ++i)
        if (focused[i] && importance[i] > 0.0) {
            taken += sizes[i];
            rest[i] = 0.0;
            any = true;
        }
    if (!any) return allocateBudget(importance, sizes, budget);
    std::vector<std::size_t> counts;
    if (budget != 0 && taken >= budget)
        counts.assign(n, 0);  // the focus takes the whole budget: the rest gives way
    else
        counts = allocateBudget(rest, sizes, budget == 0 ? 0 : budget - taken);
    for (std::size_t i = 0; i < n && i < focused.size(); ++i)
        if (focused[i] && importance[i] > 0.0) counts[i] = sizes[i];
    return counts;
}

}  // namespace viewer
