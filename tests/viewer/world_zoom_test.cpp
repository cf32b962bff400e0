// tests/viewer/world_zoom_test.cpp: the zoom similarity and the two-handed grab.
#include <viewer/world_zoom.hpp>

#include <doctest/doctest.h>

using namespace viewer;

namespace {
double distance(const glm::dvec3& a, const glm::dvec3& b) { return glm::length(a - b); }
}  // namespace

TEST_CASE("the scale gesture keeps the point under the hands fixed") {
    WorldZoom zoom;
    zoom.scaleAbout(glm::dvec3(3.0, 1.0, -2.0), 2.0);  // some zoom already
    const glm::dvec3 left0(-0.2, 1.2, -0.5), right0(0.2, 1.2, -0.5);
    const glm::dvec3 under = zoom.apply(0.5 * (left0 + right0));  // what the hands hold
    zoom.beginGrab(left0, right0);
    // Hands move apart to three times their distance, and their midpoint moves.
    const glm::dvec3 left1(-0.7, 1.0, -0.3), right1(0.5, 1.0, -0.3);
    zoom.updateGrab(left1, right1);
    CHECK(zoom.scale() == doctest::Approx(2.0 * 3.0));
    // The point held is now between the hands where they are.
    CHECK(distance(zoom.apply(0.5 * (left1 + right1)), under) < 1e-12);
    // A point held by the left hand scales about the midpoint: its distance to the held
    // point in the zoomed frame is the hand's distance / scale.
    CHECK(glm::length(zoom.apply(left1) - under) == doctest::Approx(0.6 / 6.0));
    zoom.endGrab();
    CHECK_FALSE(zoom.grabbing());
    zoom.updateGrab(glm::dvec3(0.0), glm::dvec3(5.0, 0, 0));  // ignored after the end
    CHECK(zoom.scale() == doctest::Approx(6.0));
}

TEST_CASE("scaling about a pivot keeps it fixed, the scale is clamped, reset goes back") {
    WorldZoom zoom;
    const glm::dvec3 pivot(10.0, -4.0, 2.0);
    const glm::dvec3 before = zoom.apply(pivot);
    zoom.scaleAbout(pivot, 8.0);
    CHECK(distance(zoom.apply(pivot), before) < 1e-12);
    CHECK(distance(zoom.unapply(zoom.apply(glm::dvec3(1, 2, 3))), glm::dvec3(1, 2, 3)) < 1e-12);
    // The eye at the tracking origin moved towards the pivot by 1 - 1/8 of the way.
    CHECK(distance(zoom.apply(glm::dvec3(0.0)), pivot * (1.0 - 1.0 / 8.0)) < 1e-12);
    zoom.scaleAbout(pivot, 1e9);
    CHECK(zoom.scale() == ZoomOptions{}.max_scale);
    zoom.scaleAbout(pivot, -1.0);  // refused
    CHECK(zoom.scale() == ZoomOptions{}.max_scale);
    zoom.reset();
    CHECK(zoom.scale() == 1.0);
    CHECK(distance(zoom.apply(pivot), pivot) == 0.0);
    // Hands closer than 1 cm do not start a grab.
    zoom.beginGrab(glm::dvec3(0.0), glm::dvec3(0.001, 0, 0));
    CHECK_FALSE(zoom.grabbing());
}
