// detect/src/terrain_level.cpp: the terrain levelled on the ground's own points
// (detect/src/terrain_level.hpp).
#include "terrain_level.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace detect::detail {

void levelTerrain(const core::PointCloud& cloud, double level_cell_m, std::vector<float>& height_m) {
    const core::Bounds b = cloud.bounds();
    const double extent = std::max(b.hi.x - b.lo.x, b.hi.y - b.lo.y);
    const double cell = std::max(level_cell_m, extent / kLevelMaxSquares);
    const std::size_t nx = std::size_t(std::floor((b.hi.x - b.lo.x) / cell)) + 1,
                      ny = std::size_t(std::floor((b.hi.y - b.lo.y) / cell)) + 1;
    constexpr int kBins = int((kLevelHigh_m - kLevelLow_m) / kLevelBin_m + 0.5);
    // Per square and bin: the points and the sum of their heights.
    std::vector<std::uint32_t> hist(nx * ny * kBins, 0);
    std::vector<double> sums(nx * ny * kBins, 0.0);
    const auto cellOf = [&](const core::CloudPoint& p, double& fx, double& fy) {
        fx = (double(p.position.x) - b.lo.x) / cell;
        fy = (double(p.position.y) - b.lo.y) / cell;
        return std::min(ny - 1, std::size_t(std::max(0.0, fy))) * nx + std::min(nx - 1, std::size_t(std::max(0.0, fx)));
    };
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const double h = height_m[i];
        if (!(h >= kLevelLow_m && h < kLevelHigh_m)) continue;
        double fx, fy;
        const std::size_t bin = cellOf(cloud.points[i], fx, fy) * kBins +
                                std::min(std::size_t(kBins - 1), std::size_t((h - kLevelLow_m) / kLevelBin_m));
        ++hist[bin];
        sums[bin] += h;
    }
    std::vector<double> offset(nx * ny, 0.0);
    std::vector<std::uint8_t> known(nx * ny, 0);
    for (std::size_t c = 0; c < nx * ny; ++c) {
        const std::uint32_t* hc = &hist[c * kBins];
        std::size_t total = 0, best = 0;
        int at = 0;
        for (int k = 0; k < kBins; ++k) total += hc[k];
        if (total < kLevelMinPoints) continue;
        for (int k = 1; k + 1 < kBins; ++k)
            if (const std::size_t w = std::size_t(hc[k - 1]) + hc[k] + hc[k + 1]; w > best) best = w, at = k;
        double sum = 0;
        for (int k = at - 1; k <= at + 1; ++k) sum += sums[c * kBins + std::size_t(k)];
        offset[c] = sum / double(std::max<std::size_t>(best, 1));
        known[c] = 1;
    }
    // Squares without enough points take their levelled neighbours' mean, ring by ring.
    for (bool grew = true; grew;) {
        grew = false;
        std::vector<std::uint8_t> next = known;
        for (std::size_t y = 0; y < ny; ++y)
            for (std::size_t x = 0; x < nx; ++x) {
                if (known[y * nx + x]) continue;
                double sum = 0;
                int count = 0;
                for (std::size_t yy = y ? y - 1 : 0; yy <= std::min(ny - 1, y + 1); ++yy)
                    for (std::size_t xx = x ? x - 1 : 0; xx <= std::min(nx - 1, x + 1); ++xx)
                        if (known[yy * nx + xx]) sum += offset[yy * nx + xx], ++count;
                if (count) offset[y * nx + x] = sum / count, next[y * nx + x] = 1, grew = true;
            }
        known = std::move(next);
    }
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        double fx, fy;
        cellOf(cloud.points[i], fx, fy);
        // Bilinear between the centres of the four nearest squares (clamped at the edges).
        const double gx = std::clamp(fx - 0.5, 0.0, double(nx - 1)), gy = std::clamp(fy - 0.5, 0.0, double(ny - 1));
        const std::size_t x0 = std::size_t(gx), y0 = std::size_t(gy);
        const std::size_t x1 = std::min(nx - 1, x0 + 1), y1 = std::min(ny - 1, y0 + 1);
        const double tx = gx - double(x0), ty = gy - double(y0);
        const double v = (1 - ty) * ((1 - tx) * offset[y0 * nx + x0] + tx * offset[y0 * nx + x1]) +
                         ty * ((1 - tx) * offset[y1 * nx + x0] + tx * offset[y1 * nx + x1]);
        height_m[i] = float(double(height_m[i]) - v);
    }
}

}  // namespace detect::detail
