// detect/src/point_spacing.cpp: the median nearest-neighbour distance of
// detect/src/point_spacing.hpp, on a grid of cells sorted by key: a sample point's
// nearest neighbour within one cell's side lies in its own cell or one of the 26 around it.
#include "point_spacing.hpp"

#include "voxel_clusters.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace detect::detail {
namespace {

// The distance from each sample point to its kSpacingNeighbour-th nearest other point, or
// infinity where that lies beyond one cell of side `cell_m`. `keyed` is a buffer kept
// between calls.
std::vector<double> nearestWithin(const core::PointCloud& cloud, std::span<const std::uint32_t> idx,
                                  std::span<const std::uint32_t> samples, const glm::dvec3& lo, double cell_m,
                                  KeyedPoints& keyed) {
    const auto cellOf = [&](std::uint32_t i) {
        const glm::dvec3 p = (glm::dvec3(cloud.points[i].position) - lo) / cell_m;
        return glm::i64vec3(std::int64_t(std::floor(p.x)), std::int64_t(std::floor(p.y)),
                            std::int64_t(std::floor(p.z)));
    };
    keyed.resize(idx.size());
    for (std::size_t k = 0; k < idx.size(); ++k) {
        const glm::i64vec3 c = cellOf(idx[k]);
        keyed[k] = {packKey(c.x, c.y, c.z), idx[k]};
    }
    sortByKey(keyed, 1);
    std::vector<double> nearest(samples.size(), std::numeric_limits<double>::infinity());
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const std::uint32_t i = samples[s];
        const glm::dvec3 p(cloud.points[i].position);
        const glm::i64vec3 c = cellOf(i);
        // The k smallest squared distances so far, ascending; infinity where none yet.
        std::array<double, kSpacingNeighbour> best2;
        best2.fill(std::numeric_limits<double>::infinity());
        for (std::int64_t dx = -1; dx <= 1; ++dx)
            for (std::int64_t dy = -1; dy <= 1; ++dy)
                for (std::int64_t dz = -1; dz <= 1; ++dz) {
                    const std::int64_t x = c.x + dx, y = c.y + dy, z = c.z + dz;
                    if (std::min({x, y, z}) < -kKeyOffset || std::max({x, y, z}) > kKeyMax - kKeyOffset) continue;
                    const std::uint64_t key = packKey(x, y, z);
                    auto it = std::lower_bound(keyed.begin(), keyed.end(), key,
                                               [](const auto& e, std::uint64_t k) { return e.first < k; });
                    for (; it != keyed.end() && it->first == key; ++it) {
                        if (it->second == i) continue;
                        const glm::dvec3 d = glm::dvec3(cloud.points[it->second].position) - p;
                        const double d2 = glm::dot(d, d);
                        if (d2 < best2.back()) {
                            std::size_t at = best2.size() - 1;
                            for (; at > 0 && best2[at - 1] > d2; --at) best2[at] = best2[at - 1];
                            best2[at] = d2;
                        }
                    }
                }
        if (best2.back() <= cell_m * cell_m) nearest[s] = std::sqrt(best2.back());
    }
    return nearest;
}

}  // namespace

double medianSpacing(const core::PointCloud& cloud, std::span<const std::uint32_t> idx) {
    if (idx.size() < 2) return 0.0;
    std::vector<std::uint32_t> samples;
    const std::size_t count = std::min(idx.size(), kSpacingSamples);
    samples.reserve(count);
    for (std::size_t k = 0; k < count; ++k) samples.push_back(idx[k * idx.size() / count]);
    glm::dvec3 lo(std::numeric_limits<double>::infinity());
    for (std::uint32_t i : idx) lo = glm::min(lo, glm::dvec3(cloud.points[i].position));
    KeyedPoints keyed;
    // The cell doubles from 0.125 m to kSpacingMaxM; the keys' 21 bits per axis cover
    // about 262 km at the smallest cell, and a wider cloud starts at a larger cell.
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    for (std::uint32_t i : idx) hi = glm::max(hi, glm::dvec3(cloud.points[i].position));
    const double extent_m = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    double cell_m = 0.125;
    while (extent_m / cell_m >= double(kKeyMax - kKeyOffset) && cell_m < kSpacingMaxM) cell_m *= 2.0;
    for (;; cell_m *= 2.0) {
        std::vector<double> nearest = nearestWithin(cloud, idx, samples, lo, cell_m, keyed);
        const auto mid = nearest.begin() + std::ptrdiff_t(nearest.size() / 2);
        std::nth_element(nearest.begin(), mid, nearest.end());
        if (std::isfinite(*mid)) return std::min(*mid, kSpacingMaxM);
        if (cell_m >= kSpacingMaxM) return kSpacingMaxM;
    }
}

double coveredDensity(const core::PointCloud& cloud) {
    if (cloud.points.empty()) return 0.0;
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (const core::CloudPoint& p : cloud.points) {
        const glm::dvec2 q(p.position.x, p.position.y);
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    double cell_m = kCoverCell_m;
    const auto across = [&](double extent_m) { return std::size_t(extent_m / cell_m) + 1; };
    while (double(across(hi.x - lo.x)) * double(across(hi.y - lo.y)) > double(kCoverMaxCells)) cell_m *= 2.0;
    const std::size_t nx = across(hi.x - lo.x), ny = across(hi.y - lo.y);
    std::vector<std::uint8_t> occupied(nx * ny, 0);
    for (const core::CloudPoint& p : cloud.points) {
        const std::size_t i = std::min(nx - 1, std::size_t((double(p.position.x) - lo.x) / cell_m));
        const std::size_t j = std::min(ny - 1, std::size_t((double(p.position.y) - lo.y) / cell_m));
        occupied[j * nx + i] = 1;
    }
    const auto cells = double(std::count(occupied.begin(), occupied.end(), std::uint8_t(1)));
    return double(cloud.points.size()) / (cells * cell_m * cell_m);
}

}  // namespace detect::detail
