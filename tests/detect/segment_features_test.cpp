// tests/detect/segment_features_test.cpp: the per-segment features on clouds whose answer
// is known: footprint fill (the occupied 0.5 m cells of the box's footprint, counted
// here with a set of cells as the oracle) for a filled slab, a hollow outline, and each
// with a point far out that makes the cells' range too wide for the bitmap.
#include <detect/cluster_detector.hpp>
#include <detect/segment_features.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <utility>

namespace {

std::size_t feature(const char* name) {
    const auto& names = detect::segmentFeatureNames();
    const auto it = std::find(names.begin(), names.end(), name);
    REQUIRE(it != names.end());
    return std::size_t(it - names.begin());
}

core::PointCloud slab(bool hollow, bool far_point) {
    core::PointCloud c;
    // An 8 x 3 m slab 1 m up, turned by 30 degrees, on a 0.1 m grid; hollow keeps its rim.
    const double yaw = std::numbers::pi / 6.0;
    for (int i = 0; i <= 80; ++i)
        for (int j = 0; j <= 30; ++j) {
            if (hollow && i > 1 && i < 79 && j > 1 && j < 29) continue;
            const double u = 0.1 * i - 4.0, v = 0.1 * j - 1.5;
            core::CloudPoint p;
            p.position = glm::vec3(float(std::cos(yaw) * u - std::sin(yaw) * v),
                                   float(std::sin(yaw) * u + std::cos(yaw) * v), 1.0f);
            c.points.push_back(p);
        }
    if (far_point) {
        core::CloudPoint p;
        p.position = glm::vec3(9000.0f, -7000.0f, 1.0f);
        c.points.push_back(p);
    }
    return c;
}

// The fill as the features define it, counted with a set.
float expectedFill(const core::PointCloud& c, const std::vector<std::uint32_t>& points) {
    const detect::OrientedBox box = detect::fitBox(c, points, 0.01);
    const double a = box.yaw_deg * 3.14159265358979323846 / 180.0, cs = std::cos(a), sn = std::sin(a);
    std::set<std::pair<long long, long long>> cells;
    for (const std::uint32_t i : points) {
        const glm::dvec3 p = glm::dvec3(c.points[i].position) - box.centre;
        cells.emplace(static_cast<long long>(std::floor((cs * p.x + sn * p.y) / 0.5)),
                      static_cast<long long>(std::floor((-sn * p.x + cs * p.y) / 0.5)));
    }
    const double footprint = std::max(1.0, std::ceil(box.size_m.x / 0.5) * std::ceil(box.size_m.y / 0.5));
    return float(std::min(1.0, double(cells.size()) / footprint));
}

float fill(const core::PointCloud& c) {
    std::vector<std::uint32_t> points(c.points.size());
    for (std::uint32_t i = 0; i < points.size(); ++i) points[i] = i;
    const std::vector<float> height(c.points.size(), 1.0f);
    const std::vector<float> f = detect::segmentFeatures(c, points, height, {7.0, 3.5, 2.5});
    CHECK(f[feature("footprint_fill")] == expectedFill(c, points));
    return f[feature("footprint_fill")];
}

}  // namespace

TEST_CASE("footprint fill counts the occupied cells of the box's footprint, near or far") {
    const float filled = fill(slab(false, false)), hollow = fill(slab(true, false));
    CHECK(filled > 0.9f);
    CHECK(hollow < 0.8f);
    CHECK(hollow > 0.3f);
    // A point 11 km out turns the box (its principal axis) and spreads the cells over
    // tens of thousands: they are counted by sorting, and still match.
    CHECK(fill(slab(true, true)) < fill(slab(false, true)));
}
