// tests/detect/point_spacing_test.cpp: the segmentation at any point density
// (detect/src/point_spacing.hpp, detect/segmentation.hpp step 2): the measured spacing of
// known grids (with a survey's twin first and last returns too), the scaled options, a
// thinned scene whose vehicle forms a segment only with the scaling, a dense scene left
// exactly as it was, and a real airborne survey (tests/data/real/FSite8) that forms
// segments; the covered density and the terrain cell it sets (step 1).
#include <test_paths.hpp>
#include "point_spacing.hpp"

#include <detect/segmentation.hpp>
#include <io/cloud_io.hpp>

#include "labelled_scenes.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <set>
#include <vector>

namespace {

// A vertical wall of points every step_m (x along, z up), each twice when `twins` (a
// first and a last return 1 cm apart, across the wall).
core::PointCloud wall(double step_m, bool twins) {
    core::PointCloud c;
    for (double x = 0; x <= 40; x += step_m)
        for (double z = 0; z <= 10; z += step_m) {
            core::CloudPoint p;
            p.position = glm::vec3(float(x), 0.0f, float(z));
            c.points.push_back(p);
            if (twins) {
                p.position.y += 0.01f;
                c.points.push_back(p);
            }
        }
    return c;
}

std::vector<std::uint32_t> allOf(const core::PointCloud& c) {
    std::vector<std::uint32_t> idx(c.points.size());
    std::iota(idx.begin(), idx.end(), 0u);
    return idx;
}

// The share of the target's points above the height threshold that the segment holding
// most target points holds, and that segment's share of target points.
std::pair<double, double> targetSegment(const core::PointCloud& c, const detect::Segmentation& s) {
    std::size_t targets = 0;
    for (std::size_t i = 0; i < c.points.size(); ++i)
        targets += c.points[i].label == core::Role::Target && s.height_m[i] > s.min_height_m;
    std::size_t best = 0, best_size = 1;
    for (const auto& seg : s.segments) {
        std::size_t t = 0;
        for (const std::uint32_t i : seg) t += c.points[i].label == core::Role::Target;
        if (t > best) best = t, best_size = seg.size();
    }
    return {double(best) / double(std::max<std::size_t>(targets, 1)), double(best) / double(best_size)};
}

// The cloud thinned to its first point in each cube of side cell_m (a survey thinned on a
// grid, as PDAL's voxel filters do).
core::PointCloud thinned(const core::PointCloud& c, double cell_m) {
    core::PointCloud out = c;
    out.points.clear();
    std::set<std::array<std::int64_t, 3>> taken;
    for (const core::CloudPoint& p : c.points) {
        const std::array<std::int64_t, 3> key{std::int64_t(std::floor(p.position.x / cell_m)),
                                              std::int64_t(std::floor(p.position.y / cell_m)),
                                              std::int64_t(std::floor(p.position.z / cell_m))};
        if (taken.insert(key).second) out.points.push_back(p);
    }
    return out;
}

}  // namespace

TEST_CASE("point spacing: a grid's step, whether or not each point has a twin return") {
    for (const double step : {0.1, 0.5, 1.3}) {
        for (const bool twins : {false, true}) {
            const core::PointCloud c = wall(step, twins);
            const std::vector<std::uint32_t> idx = allOf(c);
            CHECK(detect::detail::medianSpacing(c, idx) == doctest::Approx(step).epsilon(0.02));
        }
    }
    core::PointCloud one = wall(1.0, false);
    one.points.resize(1);
    CHECK(detect::detail::medianSpacing(one, allOf(one)) == 0.0);
    // Points farther apart than the search reaches: the largest spacing.
    const core::PointCloud far = wall(20.0, false);
    CHECK(detect::detail::medianSpacing(far, allOf(far)) == detect::detail::kSpacingMaxM);
}

TEST_CASE("point spacing: the options are kept on a dense cloud and scaled on a sparse one") {
    const detect::SegmentOptions o;  // voxel 0.25 m, tolerance 0.5 m, 20 points
    double scale = 0;
    detect::SegmentOptions e = detect::scaledForSpacing(o, 0.5, &scale);
    CHECK(scale == 1.0);
    CHECK(e.voxel_m == o.voxel_m);
    CHECK(e.cluster_tolerance_m == o.cluster_tolerance_m);
    CHECK(e.min_points == o.min_points);
    e = detect::scaledForSpacing(o, 1.0, &scale);  // join distance 3 x 1 - 2 x 0.5 = 2 m
    CHECK(scale == doctest::Approx(4.0));
    CHECK(e.voxel_m == doctest::Approx(1.0));
    CHECK(e.cluster_tolerance_m == doctest::Approx(2.0));
    CHECK(e.min_points == detect::kMinScaledPoints);  // 20 / 16 rounds below the bar
    e = detect::scaledForSpacing(o, 0.6, &scale);
    CHECK(scale == doctest::Approx(1.6));
    CHECK(e.min_points == 8);  // 20 / 2.56
    e = detect::scaledForSpacing(o, 50.0, &scale);
    CHECK(scale == detect::kMaxSpacingScale);
    detect::SegmentOptions fixed;
    fixed.scale_with_spacing = false;
    e = detect::scaledForSpacing(fixed, 2.0, &scale);
    CHECK(scale == 1.0);
    CHECK(e.voxel_m == fixed.voxel_m);
    fixed.min_points = 2;  // a bar already under kMinScaledPoints stays
    fixed.scale_with_spacing = true;
    CHECK(detect::scaledForSpacing(fixed, 2.0).min_points == 2);
}

TEST_CASE("point spacing: a dense scene is segmented with the options as given") {
    const core::PointCloud c = test_support::labelledScene(11, 3);
    const detect::SegmentOptions o;
    const detect::Segmentation s = detect::segmentCloud(c, o);
    CHECK(s.spacing_m > 0.0);
    CHECK(s.spacing_m <= o.cluster_tolerance_m / 2);  // twice as dense as where the scaling starts
    CHECK(s.spacing_scale == 1.0);
    CHECK(s.used.voxel_m == o.voxel_m);
    CHECK(s.used.cluster_tolerance_m == o.cluster_tolerance_m);
    CHECK(s.terrain_cell_m == o.terrain.cell_m);
    // The same segments as with the scaling off.
    detect::SegmentOptions fixed = o;
    fixed.scale_with_spacing = false;
    const detect::Segmentation f = detect::segmentCloud(c, fixed);
    CHECK(f.spacing_m == 0.0);
    CHECK(f.segments == s.segments);
}

TEST_CASE("point spacing: a thinned scene's vehicle forms one segment once the lengths follow the spacing") {
    // A 0.2 m scene thinned to a point per 1.2 m cube.
    const core::PointCloud c = thinned(test_support::labelledScene(12, 3), 1.2);
    detect::SegmentOptions fixed;
    fixed.scale_with_spacing = false;
    const detect::Segmentation f = detect::segmentCloud(c, fixed);
    CHECK(targetSegment(c, f).first < 0.2);  // the fixed lengths lose the vehicle
    const detect::Segmentation s = detect::segmentCloud(c, detect::SegmentOptions{});
    INFO("spacing " << s.spacing_m << " m, scale " << s.spacing_scale);
    CHECK(s.spacing_m > 0.6);
    CHECK(s.spacing_scale > 2.0);
    const auto [share, purity] = targetSegment(c, s);
    CHECK(share > 0.8);
    CHECK(purity > 0.9);
}

TEST_CASE("point spacing: a real airborne survey at about 2.5 m between points forms segments") {
    const core::PointCloud c =
        io::readCloud(std::filesystem::path(test_support::realDataDir()) / "FSite8_orig-utm.laz");
    const detect::Segmentation s = detect::segmentCloud(c, detect::SegmentOptions{}, 2);
    INFO("spacing " << s.spacing_m << " m, scale " << s.spacing_scale << ", above " << s.above_points);
    CHECK(s.spacing_m > 1.0);
    CHECK(s.spacing_scale > 1.0);
    CHECK(s.segments.size() >= 10);
    // About 0.3 points per square metre: the terrain's cells grow from 1 m to hold two.
    CHECK(s.terrain_cell_m > 2.0);
    CHECK(s.terrain_cell_m < 3.5);
}

TEST_CASE("point spacing: the covered density and the terrain cell it sets") {
    // A grid every 0.5 m (4 points per square metre) in an L shape: the empty corner of
    // its bounds is not counted as covered.
    core::PointCloud c;
    for (double x = 0; x < 64; x += 0.5)
        for (double y = 0; y < 64; y += 0.5) {
            if (x >= 32 && y >= 32) continue;
            core::CloudPoint p;
            p.position = glm::vec3(float(x), float(y), 0.0f);
            c.points.push_back(p);
        }
    CHECK(detect::detail::coveredDensity(c) == doctest::Approx(4.0).epsilon(0.01));
    CHECK(detect::detail::coveredDensity(core::PointCloud{}) == 0.0);
    const sim::SmrfOptions o;  // a 1 m cell, an 18 m window
    CHECK(detect::terrainForDensity(o, 4.0).cell_m == o.cell_m);
    CHECK(detect::terrainForDensity(o, 2.0).cell_m == o.cell_m);
    CHECK(detect::terrainForDensity(o, 0.0).cell_m == o.cell_m);  // unknown
    CHECK(detect::terrainForDensity(o, 0.5).cell_m == doctest::Approx(2.0));
    CHECK(detect::terrainForDensity(o, 0.3).cell_m == doctest::Approx(2.6));  // sqrt(2 / 0.3) = 2.58, rounded up
    CHECK(detect::terrainForDensity(o, 1e-6).cell_m == o.window_m);           // one opening remains
}
