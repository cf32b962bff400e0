// tests/detect/oversized_segments_test.cpp: the segmentation's step 5
// (detect/src/oversized_segments.hpp): a vehicle touching a low sheet of boxes 30 m long,
// or standing in a raised strip of noisy ground, comes out as a segment of its own; an
// ordinary scene, where nothing is larger than a vehicle, keeps its segments; the split
// does not depend on the thread count; the plan extents follow the principal axes.
#include <core/error.hpp>
#include <detect/segmentation.hpp>

#include "labelled_scenes.hpp"
#include "oversized_segments.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <string>

namespace {

// Flat ground of side 40 m every 0.2 m with Gaussian noise of sigma_m; points for which
// `skip(x, y)` holds are left out (the ground under something).
template <class Skip>
core::PointCloud flatGround(double sigma_m, std::uint32_t seed, Skip&& skip) {
    core::PointCloud c;
    c.origin = {100.0, 200.0, 30.0};
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma_m);
    for (double x = -20; x <= 20; x += 0.2)
        for (double y = -20; y <= 20; y += 0.2)
            if (!skip(x, y)) test_support::addPoint(c, {x, y, noise(rng)}, core::Role::Ground);
    c.fields.rgb = c.fields.label = true;
    return c;
}

// A car of 4.8 x 1.9 x 1.5 m at the origin, its long side along x, and beside it a field
// of 0.5 m boxes 0.5 to 1.1 m high (drawn) 0.25 m apart, 30 m by 4 m, whose near edge is 0.05 m from the
// car's side (a real place's hedges and low clutter as `scene from-cloud` makes them).
core::PointCloud carBesideLowBoxes() {
    core::PointCloud c = flatGround(0.02, 3, [](double, double) { return false; });
    std::mt19937 rng(4);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {4.8, 1.9, 1.5}, 0.0, 0.1, core::Role::Target);
    std::uniform_real_distribution<double> box_height_m(0.5, 1.1);
    const double near_y = 0.95 + 0.05;
    for (double x = -15.0; x < 15.0; x += 0.75)
        for (double y = near_y; y < near_y + 4.0; y += 0.75)
            test_support::addBoxSurface(c, rng, {x + 0.25, y + 0.25}, {0.5, 0.5, box_height_m(rng)}, 0.0, 0.1,
                                        core::Role::Environment);
    return c;
}

}  // namespace

TEST_CASE("oversized segments: a car touching a 30 m low sheet of boxes is a segment of its own") {
    const core::PointCloud c = carBesideLowBoxes();
    detect::SegmentOptions o;
    o.max_vehicle_length_m = 0;  // step 5 off: the car joins the sheet
    const detect::Segmentation whole = detect::segmentCloud(c, o);
    CHECK(whole.oversized_segments == 0);
    CHECK(test_support::targetSegment(c, whole).first > 0.75);  // less its rows under the height threshold
    CHECK(test_support::targetSegment(c, whole).second < 0.2);

    const detect::Segmentation split = detect::segmentCloud(c, detect::SegmentOptions{});
    CHECK(split.oversized_segments == 1);
    const auto [found, purity] = test_support::targetSegment(c, split);
    INFO(found << " of the car in a segment " << purity << " car");
    CHECK(found > 0.75);
    CHECK(purity > 0.8);  // with the nearest boxes' points inside its hull's margin
    // The sheet stays one segment, none of it lost.
    CHECK(split.segments.size() == whole.segments.size() + 1);
}

TEST_CASE("oversized segments: a vehicle in a raised strip of noisy ground is a segment of its own") {
    // A strip 30 m by 3 m of ground 0.6 m up (a misregistered view's ground the terrain fit
    // passed under), noisy, with a pickup-sized vehicle standing on the true ground inside
    // it: the strip's points touch the vehicle on both sides.
    const auto in_strip = [](double x, double y) { return std::abs(x) < 15.0 && std::abs(y) < 1.5; };
    const auto under_vehicle = [](double x, double y) { return std::abs(x) < 2.8 && std::abs(y) < 1.1; };
    core::PointCloud c = flatGround(0.02, 5, in_strip);
    std::mt19937 rng(6);
    std::normal_distribution<double> noise(0.0, 0.06);
    for (double x = -15; x < 15; x += 0.2)
        for (double y = -1.5; y < 1.5; y += 0.2)
            if (!under_vehicle(x, y)) test_support::addPoint(c, {x, y, 0.6 + noise(rng)}, core::Role::Ground);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {5.4, 2.0, 1.8}, 0.0, 0.1, core::Role::Target);

    detect::SegmentOptions o;
    o.max_vehicle_length_m = 0;
    const detect::Segmentation whole = detect::segmentCloud(c, o);
    INFO("without step 5: " << test_support::targetSegment(c, whole).second
                            << " of the target's segment is the vehicle");
    CHECK(test_support::targetSegment(c, whole).second < 0.7);

    const detect::Segmentation split = detect::segmentCloud(c, detect::SegmentOptions{});
    CHECK(split.oversized_segments == 1);
    const auto [found, purity] = test_support::targetSegment(c, split);
    INFO(found << " of the vehicle in a segment " << purity << " vehicle");
    CHECK(found > 0.75);  // less its lowest rows, within the terrain's tolerance and the strip's
    CHECK(purity > 0.9);
}

TEST_CASE("oversized segments: an ordinary scene, nothing larger than a vehicle, keeps its segments") {
    // The labelled scene's target (7 x 3.5 m), trees and house (tall): nothing is split.
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
        core::PointCloud c = test_support::labelledScene(seed, 3);
        detect::SegmentOptions off;
        off.max_vehicle_length_m = 0;
        const detect::Segmentation before = detect::segmentCloud(c, off);
        const detect::Segmentation after = detect::segmentCloud(c, detect::SegmentOptions{});
        CHECK(after.oversized_segments == 0);
        CHECK(after.segments == before.segments);
    }
}

TEST_CASE("oversized segments: a long low wall with no vehicle-sized part stays whole") {
    core::PointCloud c = flatGround(0.02, 7, [](double, double) { return false; });
    std::mt19937 rng(8);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {20.0, 0.4, 1.0}, 0.3, 0.1, core::Role::Environment);
    const detect::Segmentation s = detect::segmentCloud(c, detect::SegmentOptions{});
    CHECK(s.oversized_segments == 0);
    REQUIRE(s.segments.size() == 1);
}

TEST_CASE("oversized segments: the same whatever the thread count") {
    const core::PointCloud c = carBesideLowBoxes();
    const detect::Segmentation one = detect::segmentCloud(c, detect::SegmentOptions{}, 1);
    const detect::Segmentation four = detect::segmentCloud(c, detect::SegmentOptions{}, 4);
    CHECK(one.oversized_segments == 1);
    CHECK(one.segments == four.segments);
}

TEST_CASE("oversized segments: plan extents along the principal axes") {
    core::PointCloud c;
    const double yaw = 0.5, cs = std::cos(yaw), sn = std::sin(yaw);
    for (double u = -5.0; u <= 5.0; u += 0.1)
        for (double v = -1.0; v <= 1.0; v += 0.1)
            test_support::addPoint(c, {cs * u - sn * v, sn * u + cs * v, 0.0}, core::Role::Environment);
    std::vector<std::uint32_t> idx(c.points.size());
    std::iota(idx.begin(), idx.end(), 0u);
    const detect::detail::PlanExtent e = detect::detail::planExtent(c, idx);
    CHECK(e.length_m == doctest::Approx(10.0).epsilon(0.01));
    CHECK(e.width_m == doctest::Approx(2.0).epsilon(0.02));
    CHECK(detect::detail::planExtent(c, {}).length_m == 0.0);
}

TEST_CASE("oversized segments: options out of range are one line naming the option") {
    detect::SegmentOptions o;
    o.max_vehicle_length_m = 1.0;
    CHECK_THROWS_WITH_AS(detect::validate(o), "detect: max_vehicle_length_m = 1: allowed 0 (no split) or [2, 100] m",
                         core::Error);
    o.max_vehicle_length_m = 14.0;
    o.max_vehicle_width_m = 20.0;
    CHECK_THROWS_WITH_AS(detect::validate(o), "detect: max_vehicle_width_m = 20: allowed [1, max_vehicle_length_m] m",
                         core::Error);
    o.max_vehicle_length_m = 0.0;  // no split: the width is not read
    CHECK_NOTHROW(detect::validate(o));
}
