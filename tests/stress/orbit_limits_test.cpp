// tests/stress/orbit_limits_test.cpp: the orbit at the edges of its documented
// range: alpha + FoV/2 close to 90 deg (finite huge radius, then the error past
// sim::kMaxGrazingDeg), FoV 0.01 and 170 deg, a 1 x 1 sensor, NoV = 1.
#include <scene_builders.hpp>

#include <core/error.hpp>
#include <sim/generator.hpp>
#include <sim/orbit.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// A flat ground quad of half-size `half` m at z = 0 and a small target at the centre.
core::Scene flatScene(float half) {
    core::Scene s;
    s.source = "flat (in code)";
    s.meshes.push_back(test_support::quadMesh(half, 0.0f, core::Role::Ground, "ground"));
    s.meshes.push_back(test_support::boxMesh({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 0.5f}, core::Role::Target, "target"));
    return s;
}

}  // namespace

TEST_CASE("alpha + FoV/2 up to the grazing bound: finite, huge radius, past it a clear error") {
    sim::OrbitOptions o;
    o.fov_deg = 6.5;
    // Just under the bound: eq. (1) gives tan(89.99 deg - 1e-9) * 300 - 10 = ~1.72e6 m.
    o.inclination_deg = sim::kMaxGrazingDeg - 0.5 * o.fov_deg - 1e-9;
    CHECK_NOTHROW(sim::validate(o));
    const double r = sim::droneRadius(o);
    CHECK(std::isfinite(r));
    CHECK(r == doctest::Approx(std::tan(sim::kMaxGrazingDeg * kDeg) * 300.0 - 10.0).epsilon(1e-6));
    CHECK(r > 1e6);
    CHECK(std::isfinite(sim::lengthSensed(o)));
    CHECK(sim::lengthSensed(o) > 0.0);
    CHECK(std::isfinite(sim::coverageDiameter(o)));
    // The sensor pose is still a rotation (orthonormal) and points at the ground.
    const core::Pose pose = sim::sensorPose(o, glm::dvec3(0.0), 0);
    const glm::dmat3 rtr = glm::transpose(pose.rotation) * pose.rotation;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) CHECK(rtr[i][j] == doctest::Approx(i == j ? 1.0 : 0.0).epsilon(1e-12));
    CHECK(pose.applyDirection({0, 0, 1}).z < 0.0);
    // At and past the bound: one line naming the parameter and the allowed range.
    for (const double alpha : {sim::kMaxGrazingDeg - 0.5 * o.fov_deg, 86.8, 89.999, 90.0, 120.0}) {
        o.inclination_deg = alpha;
        CAPTURE(alpha);
        CHECK_THROWS_AS(sim::validate(o), core::Error);
        try {
            sim::validate(o);
        } catch (const core::Error& e) {
            const std::string what = e.what();
            CHECK(what.rfind("orbit: ", 0) == 0);
            CHECK(what.find("inclination") != std::string::npos);
            CHECK(what.find('\n') == std::string::npos);
        }
    }
}

TEST_CASE("the generator near grazing (alpha + FoV/2 = 89 deg): every hit lies on the ground") {
    // Radius 300 tan(89 deg) - 10 = 17,178 m: the top row's rays run 1 degree below the
    // horizon for ~17 km and land on a 60 km ground quad; the bottom row's at ~2.3 km.
    sim::GenerateOptions g;
    g.orbit.inclination_deg = 89.0 - 0.5 * g.orbit.fov_deg;
    g.orbit.xres = g.orbit.yres = 16;
    g.orbit.views = 4;
    g.white = true;
    const core::Scene scene = flatScene(30000.0f);
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(scene, g, &st);
    CHECK(st.drone_radius_m == doctest::Approx(300.0 * std::tan(89.0 * kDeg) - 10.0));
    CHECK(st.misses == 0);
    REQUIRE(cloud.points.size() == 16u * 16u * 4u);
    double worst_z = 0.0;
    for (const auto& p : cloud.points) {
        worst_z = std::max(worst_z, double(std::abs(p.position.z)));
        CHECK(std::isfinite(p.range_m));
        CHECK(p.range_m > 2000.0f);
    }
    // Hits are origin + t dir with t ~ 17 km in float: a few centimetres of rounding.
    MESSAGE("grazing 89 deg: worst |z| of a ground hit " << worst_z << " m at range ~17 km");
    CHECK(worst_z < 0.1);
}

TEST_CASE("the generator at the grazing bound (alpha + FoV/2 = 89.98 deg): 859 km out, hits exact") {
    // Radius 300 tan(89.98 deg) - 10 = 859 km: the drone (a float ray origin, 6 cm steps at
    // that distance) sees from 2.6 km to the horizon-grazing top edge at C. With 8 rows the
    // top row's centre ray runs at alpha + atan(tan(3.25 deg) 7/8) = 89.57 deg from the
    // vertical and lands 300 tan(89.57 deg) = 40 km out; every hit must be on the plane.
    sim::GenerateOptions g;
    g.orbit.inclination_deg = 89.98 - 0.5 * g.orbit.fov_deg;
    g.orbit.xres = g.orbit.yres = 8;
    g.orbit.views = 2;
    g.white = true;
    const core::Scene scene = flatScene(2.0e6f);
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(scene, g, &st);
    CHECK(st.drone_radius_m == doctest::Approx(300.0 * std::tan(89.98 * kDeg) - 10.0));
    CHECK(st.misses == 0);
    REQUIRE(cloud.points.size() == 8u * 8u * 2u);
    double worst_z = 0.0, farthest_m = 0.0;
    for (std::size_t i = 0; i < 64; ++i) {  // view 0: the drone at (r, 0, 300) looks towards -x
        const auto& p = cloud.points[i];
        worst_z = std::max(worst_z, double(std::abs(p.position.z)));
        farthest_m = std::max(farthest_m, st.drone_radius_m - double(p.position.x));
    }
    const double top_row_rad = g.orbit.inclination_deg * kDeg + std::atan(std::tan(3.25 * kDeg) * 7.0 / 8.0);
    MESSAGE("grazing 89.98 deg: radius " << st.drone_radius_m << " m, worst |z| " << worst_z << " m, farthest hit "
                                         << farthest_m << " m from the drone's foot");
    CHECK(farthest_m == doctest::Approx(300.0 * std::tan(top_row_rad)).epsilon(1e-3));
    CHECK(worst_z < 0.01);
}

TEST_CASE("FoV 0.01 deg, 1 x 1 sensor, NoV = 1: one point where the optical axis meets the ground") {
    sim::GenerateOptions g;
    g.orbit.fov_deg = 0.01;
    g.orbit.xres = g.orbit.yres = 1;
    g.orbit.views = 1;
    g.white = true;
    const core::Scene scene = flatScene(1000.0f);
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(scene, g, &st);
    REQUIRE(cloud.points.size() == 1);
    CHECK(st.rays == 1);
    // The default centre: the target's x, y at the ground height beneath it, z = 0.
    CHECK(st.centre.z == doctest::Approx(0.0));
    // The drone at (r, 0, 300) looks down at alpha = 45 deg towards -x: the axis meets the
    // ground at x = r - 300 tan(45 deg), r = 300 tan(45.005 deg) - 10.
    const double r = 300.0 * std::tan(45.005 * kDeg) - 10.0;
    const double x = r - 300.0 * std::tan(45.0 * kDeg);
    const auto& p = cloud.points[0];
    CHECK(p.view == 0);
    CHECK(double(p.position.x) == doctest::Approx(x).epsilon(1e-4));
    CHECK(std::abs(p.position.y) < 1e-3);
    CHECK(std::abs(p.position.z) < 1e-4);
    CHECK(double(p.range_m) == doctest::Approx(300.0 / std::cos(45.0 * kDeg)).epsilon(1e-5));
}

TEST_CASE("FoV 0.01 deg on 64 x 64 pixels: distinct points ~1 mm apart") {
    sim::GenerateOptions g;
    g.orbit.fov_deg = 0.01;
    g.orbit.xres = g.orbit.yres = 64;
    g.orbit.views = 1;
    g.white = true;
    const core::Scene scene = flatScene(1000.0f);
    const core::PointCloud cloud = sim::generateCloud(scene, g);
    REQUIRE(cloud.points.size() == 64u * 64u);
    // Pixel pitch on the ground: range 424 m x 0.01 deg / 64 = 1.2 mm across, more along
    // the slant. Along a row the points must move monotonically (no float collapse).
    int collapsed = 0;
    for (int row = 0; row < 64; ++row)
        for (int col = 1; col < 64; ++col) {
            const auto& a = cloud.points[std::size_t(row * 64 + col - 1)].position;
            const auto& b = cloud.points[std::size_t(row * 64 + col)].position;
            collapsed += glm::length(b - a) < 1e-4f;
        }
    CHECK(collapsed == 0);
}

TEST_CASE("FoV 170 deg, alpha 2 deg: the footprint reaches ~5.7 km from the drone, all on the ground") {
    sim::GenerateOptions g;
    g.orbit.fov_deg = 170.0;
    g.orbit.inclination_deg = 2.0;  // alpha + FoV/2 = 87 deg < 89.99
    g.orbit.overlap_m = 0.0;
    g.orbit.xres = g.orbit.yres = 32;
    g.orbit.views = 1;
    g.white = true;
    REQUIRE_NOTHROW(sim::validate(g));
    const core::Scene scene = flatScene(100000.0f);
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(scene, g, &st);
    CHECK(st.misses == 0);
    REQUIRE(cloud.points.size() == 32u * 32u);
    // Drone at (r, 0, 300), r = 300 tan(87 deg); the image's vertical half-FoV is 85 deg, so
    // the top row's centre is alpha + atan(tan(85 deg) 15.5/16) from the vertical.
    const double r = 300.0 * std::tan(87.0 * kDeg);
    CHECK(st.drone_radius_m == doctest::Approx(r));
    double far_m = 0.0;
    for (const auto& p : cloud.points) {
        CHECK(std::abs(p.position.z) < 0.01f);
        far_m = std::max(far_m, glm::length(glm::dvec2(p.position.x - r, p.position.y)));
    }
    const double top_row_rad = 2.0 * kDeg + std::atan(std::tan(85.0 * kDeg) * 15.5 / 16.0);
    CHECK(far_m > 300.0 * std::tan(top_row_rad) * 0.99);
    MESSAGE("FoV 170: farthest point " << far_m << " m from the drone's foot");
    g.orbit.fov_deg = 170.001;
    CHECK_THROWS_AS(sim::validate(g), core::Error);
}

// alpha = 0 is accepted by validate() ([0, 90)): the optical axis is vertical, and the
// sensor's x axis is the orbit's tangent (-sin theta, cos theta, 0), not a NaN.
TEST_CASE("nadir (alpha = 0): a valid pose and every ray on the ground") {
    sim::OrbitOptions o;
    o.inclination_deg = 0.0;
    const core::Pose pose = sim::sensorPose(o, glm::dvec3(0.0), 3);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) CHECK(std::isfinite(pose.rotation[i][j]));
    CHECK(pose.applyDirection({0, 0, 1}).z == doctest::Approx(-1.0));
    sim::GenerateOptions g;
    g.orbit.inclination_deg = 0.0;
    g.orbit.xres = g.orbit.yres = 16;
    g.orbit.views = 2;
    g.white = true;
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(flatScene(1000.0f), g, &st);
    CHECK(st.misses == 0);
    CHECK(cloud.points.size() == 512u);
}

TEST_CASE("NoV = 1 and NoV = 65535 are valid, 0 and 65536 are not") {
    sim::OrbitOptions o;
    o.views = 1;
    CHECK_NOTHROW(sim::validate(o));
    const core::Pose p = sim::sensorPose(o, glm::dvec3(0.0), 0);
    CHECK(p.translation.x == doctest::Approx(sim::droneRadius(o)));
    CHECK(std::abs(p.translation.y) < 1e-9);
    o.views = 65535;
    CHECK_NOTHROW(sim::validate(o));
    // The last view is one step short of a full turn.
    const core::Pose last = sim::sensorPose(o, glm::dvec3(0.0), 65534);
    CHECK(last.translation.y < 0.0);
    CHECK(std::abs(last.translation.y) < sim::droneRadius(o) * 2.0 * std::numbers::pi / 65535.0 * 1.001);
    for (int bad : {0, -1, 65536}) {
        o.views = bad;
        CHECK_THROWS_AS(sim::validate(o), core::Error);
    }
}
