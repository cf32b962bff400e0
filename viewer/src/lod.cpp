// viewer/src/lod.cpp: level-of-detail order, culling and point budget for the viewer
// (paper §IV-A asks for an immersive viewer; the budget keeps it at HMD rates).
#include <viewer/lod.hpp>

#include <core/random.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace viewer {

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
    for (std::size_t c = 0; c < side * side; ++c) {
        const std::size_t first = start[c], count = start[c + 1] - start[c];
        if (count == 0) continue;
        const auto cell_begin = sorted.begin() + static_cast<std::ptrdiff_t>(first);
        core::shuffle(cell_begin, cell_begin + static_cast<std::ptrdiff_t>(count), rng);
        LodCell cell{first, count, {}};
        for (std::size_t i = first; i < first + count; ++i) cell.bounds.extend(glm::dvec3(sorted[i].position));
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

}  // namespace viewer
