// tests/viewer/tools/pointer_tool_test.cpp: where the pointer's ray comes from
// (viewer/src/tools/pointer_tool.cpp, pointerRayOf): a script's aim, the controller, the
// desktop cursor, and nothing from the cursor in a replay.
#include "tools/pointer_tool.hpp"

#include <doctest/doctest.h>

using namespace viewer;

TEST_CASE("the desktop cursor casts the pointer's ray, except in a replay") {
    PointerSources p;
    p.cursor_px = glm::dvec2(320.0, 180.0);  // the window's centre: straight ahead
    p.window_w = 640;
    p.window_h = 360;
    const std::optional<LocalRay> ray = pointerRayOf(p);
    REQUIRE(ray);
    CHECK(ray->direction.z == doctest::Approx(-1.0));
    // A replay shows the recorded pointer: the live cursor picks nothing.
    p.replay = true;
    CHECK_FALSE(pointerRayOf(p));
    // A script's aim still points (from the head to its point).
    p.aim_local = glm::dvec3(0.0, 10.0, 0.0);
    REQUIRE(pointerRayOf(p));
    CHECK(pointerRayOf(p)->direction.y == doctest::Approx(1.0));
}
