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

namespace {

// A box's top and its four sides, l x w x h m standing on the terrain (heights = z),
// each face sampled on a grid of 20 x 20 points: the same points, whatever the size.
core::PointCloud boxSurface(double l, double w, double h) {
    core::PointCloud c;
    const auto add = [&](double x, double y, double z) {
        core::CloudPoint p;
        p.position = glm::vec3(float(x), float(y), float(z));
        c.points.push_back(p);
    };
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j) {
            const double a = (i + 0.5) / 20.0, b = (j + 0.5) / 20.0;
            add(l * (a - 0.5), w * (b - 0.5), h);  // top
            add(l * (a - 0.5), -w / 2, h * b);     // sides
            add(l * (a - 0.5), w / 2, h * b);
            add(-l / 2, w * (a - 0.5), h * b);  // ends
            add(l / 2, w * (a - 0.5), h * b);
        }
    return c;
}

std::vector<float> features(const core::PointCloud& c, detect::FeatureSet set, double density_m2) {
    std::vector<std::uint32_t> points(c.points.size());
    std::vector<float> height(c.points.size());
    for (std::uint32_t i = 0; i < points.size(); ++i) points[i] = i, height[i] = c.points[i].position.z;
    return detect::segmentFeatures(c, points, height, {7.0, 3.5, 2.5}, set, density_m2);
}

float named(const std::vector<float>& f, const char* name) {
    const auto& names = detect::segmentFeatureNames(detect::FeatureSet::kV2);
    const auto it = std::find(names.begin(), names.end(), name);
    REQUIRE(it != names.end());
    return f[std::size_t(it - names.begin())];
}

}  // namespace

TEST_CASE("the second feature set keeps the first's values and adds the box's proportions") {
    const core::PointCloud c = boxSurface(6.0, 2.0, 2.0);
    const std::vector<float> v1 = features(c, detect::FeatureSet::kV1, 0.0);
    const std::vector<float> v2 = features(c, detect::FeatureSet::kV2, 50.0);
    REQUIRE(v1.size() == detect::segmentFeatureNames(detect::FeatureSet::kV1).size());
    REQUIRE(v2.size() == detect::segmentFeatureNames(detect::FeatureSet::kV2).size());
    REQUIRE(v2.size() > v1.size());
    for (std::size_t k = 0; k < v1.size(); ++k) {
        CAPTURE(k);
        CHECK((v1[k] == v2[k] || (std::isnan(v1[k]) && std::isnan(v2[k]))));
    }
    CHECK(named(v2, "width_over_length") == doctest::Approx(1.0 / 3.0).epsilon(0.05));
    CHECK(named(v2, "height_over_length") == doctest::Approx(1.0 / 3.0).epsilon(0.05));
    CHECK(named(v2, "height_over_width") == doctest::Approx(1.0).epsilon(0.05));
    CHECK(named(v2, "top_cover") == doctest::Approx(1.0));  // the top covers every cell of the box
    CHECK(named(v2, "box_grid_fill") == doctest::Approx(1.0));
    CHECK(named(v2, "long_profile_empty") == 0.0f);
    CHECK(named(v2, "side_wall_share") > 0.3f);  // the sides hold most of the mid-height points
    CHECK(named(v2, "log_points_rel") == doctest::Approx(std::log(2000.0 / 50.0)).epsilon(1e-4));
    CHECK(std::isnan(named(features(c, detect::FeatureSet::kV2, 0.0), "log_points_rel")));  // density unknown
}

TEST_CASE("the second feature set's shape features do not change with the vehicle's size") {
    // The same box at twice its size, sampled by as many points: the shape features
    // agree, the absolute sizes of the first set do not.
    const std::vector<float> small = features(boxSurface(5.0, 2.0, 1.5), detect::FeatureSet::kV2, 40.0);
    const std::vector<float> large = features(boxSurface(10.0, 4.0, 3.0), detect::FeatureSet::kV2, 10.0);
    for (const char* name : {"width_over_length", "height_over_length", "height_over_width", "hag_max_over_length",
                             "rel_hag_p10", "rel_hag_p50", "rel_hag_p90", "gap_under_share", "long_profile_ends",
                             "long_profile_centre", "cross_profile_sides", "top_spread", "top_cover", "box_grid_fill",
                             "side_wall_share", "end_wall_share", "points_per_m2_rel"}) {
        CAPTURE(std::string(name));
        CHECK(named(small, name) == doctest::Approx(named(large, name)).epsilon(0.02));
    }
    CHECK(named(large, "length_m") > 1.9f * named(small, "length_m"));
}
