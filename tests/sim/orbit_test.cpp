// tests/sim/orbit_test.cpp: paper §III-A geometry with the paper's numbers.
#include <sim/orbit.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace {

double round2(double v) { return std::round(v * 100.0) / 100.0; }

std::string errorOf(const sim::OrbitOptions& o) {
    try {
        sim::validate(o);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

// Where a world-frame ray from `origin` along `d` meets the plane z = 0.
glm::dvec3 groundHit(const glm::dvec3& origin, const glm::dvec3& d) { return origin + (-origin.z / d.z) * d; }

}  // namespace

TEST_CASE("paper numbers: drone radius 326.12 m, length sensed 68.36 m, covered diameter ~125 m") {
    const sim::OrbitOptions paper;  // 300 m, CO 10 m, alpha 45, FoV 6.5, 128x128, NoV 100
    CHECK(round2(sim::droneRadius(paper)) == doctest::Approx(326.12));
    CHECK(round2(sim::lengthSensed(paper)) == doctest::Approx(68.36));
    // The paper rounds to 125 m; the corner rays give 125.0 +- 1.
    CHECK(sim::coverageDiameter(paper) == doctest::Approx(125.0).epsilon(0.008));
    CHECK(paper.xres * paper.yres * paper.views == 1638400);
}

TEST_CASE("sensor pose: the top image edge reaches O = C + CO past C, the axis hits P") {
    sim::OrbitOptions o;
    const glm::dvec3 centre(12.0, -7.0, 0.0);
    for (int view : {0, 13, 50, 99}) {
        const core::Pose T_world_sensor = sim::sensorPose(o, centre, view);
        const double theta = 2.0 * std::numbers::pi * view / o.views;
        const glm::dvec3 outward(std::cos(theta), std::sin(theta), 0.0);
        CHECK(T_world_sensor.translation.z == doctest::Approx(300.0));
        CHECK(glm::length(glm::dvec3(T_world_sensor.translation.x, T_world_sensor.translation.y, 0.0) - centre) ==
              doctest::Approx(326.1245).epsilon(1e-5));
        // Top edge, middle column (pixel corner row 0): lands CO = 10 m past C.
        const glm::dvec3 top = T_world_sensor.applyDirection(sim::pixelDirection(o, 0.5 * o.xres - 0.5, -0.5));
        const glm::dvec3 o_point = groundHit(T_world_sensor.translation, top);
        CHECK(glm::dot(o_point - centre, -outward) == doctest::Approx(10.0).epsilon(1e-6));
        CHECK(std::abs(glm::dot(o_point - centre, glm::dvec3(-outward.y, outward.x, 0.0))) < 1e-6);
        // Bottom edge: length sensed before O.
        const glm::dvec3 bottom =
            T_world_sensor.applyDirection(sim::pixelDirection(o, 0.5 * o.xres - 0.5, o.yres - 0.5));
        const glm::dvec3 near_point = groundHit(T_world_sensor.translation, bottom);
        CHECK(glm::length(o_point - near_point) == doctest::Approx(sim::lengthSensed(o)).epsilon(1e-6));
        // Optical axis inclined alpha from the vertical.
        const glm::dvec3 axis = T_world_sensor.applyDirection({0.0, 0.0, 1.0});
        CHECK(std::acos(-axis.z) * 180.0 / std::numbers::pi == doctest::Approx(45.0));
        // Right-handed sensor frame: x right, y down, z forward.
        CHECK(glm::determinant(T_world_sensor.rotation) == doctest::Approx(1.0));
        CHECK(T_world_sensor.applyDirection({0.0, 1.0, 0.0}).z < 0.0);  // image down = towards the ground
    }
}

TEST_CASE("pixel directions: pixel centres, vertical FoV, horizontal FoV from the aspect") {
    sim::OrbitOptions o;
    o.xres = 3;
    o.yres = 3;
    const glm::dvec3 centre = sim::pixelDirection(o, 1, 1);
    CHECK(centre.x == doctest::Approx(0.0));
    CHECK(centre.y == doctest::Approx(0.0));
    CHECK(centre.z == doctest::Approx(1.0));
    o.xres = 200;
    o.yres = 100;
    o.fov_deg = 10.0;
    // The centres of the top row sit half a pixel inside the vertical FoV.
    const glm::dvec3 top_edge = sim::pixelDirection(o, 99.5, -0.5);
    CHECK(std::atan2(-top_edge.y, top_edge.z) * 180.0 / std::numbers::pi == doctest::Approx(5.0));
    const glm::dvec3 right_edge = sim::pixelDirection(o, 199.5, 49.5);
    CHECK(std::atan2(right_edge.x, right_edge.z) ==
          doctest::Approx(std::atan(std::tan(5.0 * std::numbers::pi / 180.0) * 2.0)));
    CHECK(glm::length(sim::pixelDirection(o, 17, 3)) == doctest::Approx(1.0));
}

TEST_CASE("impossible parameters: the error names the parameter and the allowed range") {
    const auto bad = [](auto change, const char* parameter, const char* allowed) {
        sim::OrbitOptions o;
        change(o);
        const std::string message = errorOf(o);
        INFO(message);
        CHECK(message.rfind("orbit: ", 0) == 0);
        CHECK(message.find(parameter) != std::string::npos);
        CHECK(message.find(allowed) != std::string::npos);
        CHECK_THROWS_AS(sim::droneRadius(o), core::Error);
    };
    bad([](auto& o) { o.inclination_deg = 87.0; }, "inclination_deg + fov_deg/2", "89.99");
    bad([](auto& o) { o.inclination_deg = 90.0; }, "inclination_deg", "[0, 90)");
    bad([](auto& o) { o.fov_deg = 0.0; }, "fov_deg", "(0, 170]");
    bad([](auto& o) { o.fov_deg = -3.0; }, "fov_deg", "(0, 170]");
    bad([](auto& o) { o.xres = 0; }, "xres", "[1, 65536]");
    bad([](auto& o) { o.yres = -5; }, "yres", "[1, 65536]");
    bad([](auto& o) { o.views = 0; }, "views", "[1, 65535]");
    bad([](auto& o) { o.views = 70000; }, "views", "[1, 65535]");
    bad([](auto& o) { o.altitude_m = 0.0; }, "altitude_m", "(0, 10000000]");
    // Drone positions are float ray origins: beyond 1e7 m they step by metres.
    bad([](auto& o) { o.altitude_m = 1e12; }, "(--altitude-m) = 1e+12", "(0, 10000000]");
    bad([](auto& o) { o.overlap_m = -1e300; }, "(--overlap-m) = -1e+300", "[-10000000, 10000000]");
    bad(
        [](auto& o) {
            o.altitude_m = 1e6;
            o.inclination_deg = 86.0;
        },
        "drone radius", "<= 10000000");
    bad([](auto& o) { o.altitude_m = std::nan(""); }, "altitude_m", "finite");
    bad([](auto& o) { o.overlap_m = INFINITY; }, "overlap_m", "finite");
    bad([](auto& o) { o.overlap_m = 400.0; }, "overlap_m", "drone radius");
    CHECK(errorOf(sim::OrbitOptions{}).empty());
}

TEST_CASE("validatePlacement: every drone position within 1e7 m of the local origin") {
    sim::OrbitOptions o;  // radius 326.12 m, altitude 300 m
    CHECK_NOTHROW(sim::validatePlacement(o, glm::dvec3(0.0)));
    CHECK_NOTHROW(sim::validatePlacement(o, glm::dvec3(1e7 - 327.0, 0.0, 0.0)));
    CHECK_NOTHROW(sim::validatePlacement(o, glm::dvec3(0.0, 0.0, 1e7 - 300.0)));
    for (const glm::dvec3 c : {glm::dvec3(1e7 - 326.0, 0, 0), glm::dvec3(0, -1e7, 0), glm::dvec3(0, 0, 1e7 - 299.0)}) {
        CAPTURE(c.x);
        CAPTURE(c.z);
        CHECK_THROWS_WITH_AS(
            sim::validatePlacement(o, c),
            doctest::Contains("m from the scene's origin around C (--centre, --altitude-m, --overlap-m): "
                              "allowed <= 10000000 m"),
            core::Error);
    }
}

TEST_CASE("derived geometry stays finite up to the grazing bound") {
    sim::OrbitOptions o;
    o.inclination_deg = sim::kMaxGrazingDeg - 0.5 * o.fov_deg - 1e-6;
    CHECK(std::isfinite(sim::droneRadius(o)));
    CHECK(std::isfinite(sim::lengthSensed(o)));
    CHECK(std::isfinite(sim::coverageDiameter(o)));
    o.inclination_deg = 0.0;  // nadir: the footprint straddles the drone
    CHECK(sim::lengthSensed(o) == doctest::Approx(2.0 * 300.0 * std::tan(3.25 * std::numbers::pi / 180.0)));
}
