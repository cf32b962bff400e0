// spatial_hash: binning points into cubic cells (see spatial_hash.hpp).
#include <core/spatial_hash.hpp>

#include <core/error.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <unordered_map>

namespace core {

CellKey cellOf(const glm::vec3& p, double cell_m) {
    return {static_cast<std::int64_t>(std::floor(p.x / cell_m)), static_cast<std::int64_t>(std::floor(p.y / cell_m)),
            static_cast<std::int64_t>(std::floor(p.z / cell_m))};
}

std::size_t CellKeyHash::operator()(const CellKey& k) const {
    return std::hash<std::int64_t>()((k.x * 73856093) ^ (k.y * 19349663) ^ (k.z * 83492791));
}

CellBins binByCell(std::span<const CloudPoint> points, double cell_m) {
    if (!(cell_m > 0.0)) throw Error("spatial hash: cell size " + std::to_string(cell_m) + " m: allowed > 0");
    if (points.size() >= std::numeric_limits<std::uint32_t>::max())
        throw Error("spatial hash: " + std::to_string(points.size()) + " points: allowed fewer than 2^32 - 1");
    CellBins bins;
    // Pass 1: a cell number per point, numbered in order of first appearance.
    std::unordered_map<CellKey, std::uint32_t, CellKeyHash> number;
    std::vector<std::uint32_t> cell_of(points.size());
    std::vector<std::size_t> counts;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const CellKey k = cellOf(points[i].position, cell_m);
        const auto [it, added] = number.try_emplace(k, static_cast<std::uint32_t>(bins.keys.size()));
        if (added) {
            bins.keys.push_back(k);
            counts.push_back(0);
        }
        cell_of[i] = it->second;
        ++counts[it->second];
    }
    // Pass 2: a stable counting sort by cell number.
    bins.starts.assign(bins.keys.size() + 1, 0);
    for (std::size_t c = 0; c < counts.size(); ++c) bins.starts[c + 1] = bins.starts[c] + counts[c];
    std::vector<std::size_t> next(bins.starts.begin(), bins.starts.end() - 1);
    bins.order.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) bins.order[next[cell_of[i]]++] = static_cast<std::uint32_t>(i);
    return bins;
}

}  // namespace core
