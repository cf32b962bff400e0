// tests/viewer/ui/panel_quad_test.cpp: the headset panel's place and the controller ray's hit
// on it (known answers: rays through its centre and corners, misses beside, behind,
// parallel and from the back).
#include "ui/panel_quad.hpp"

#include <doctest/doctest.h>

#include <glm/geometric.hpp>

using viewer::PanelQuad;
using viewer::TrackingRay;

namespace {
TrackingRay towards(const glm::dvec3& from, const glm::dvec3& to) { return {from, glm::normalize(to - from)}; }
}  // namespace

TEST_CASE("the headset panel: 0.8 m wide, 1.1 m ahead and 0.6 m below the origin, the texture's aspect") {
    const PanelQuad q = viewer::headsetPanelQuad(1600, 900);
    CHECK(q.centre == glm::dvec3(0.0, -0.6, -1.1));
    CHECK(q.width_m == doctest::Approx(0.8));
    CHECK(q.height_m == doctest::Approx(0.45));
    const auto c = viewer::panelCorners(q);
    CHECK(c[0].x == doctest::Approx(-0.4));  // bottom left
    CHECK(c[0].y == doctest::Approx(-0.825));
    CHECK(c[2].x == doctest::Approx(0.4));  // top right
    CHECK(c[2].y == doctest::Approx(-0.375));
    CHECK(c[3].z == doctest::Approx(-1.1));
    CHECK(viewer::headsetPanelQuad(0, 0).height_m == 0.0);  // no texture yet: no area
}

TEST_CASE("a ray meets the panel where it points, as ImGui's coordinates from the top left") {
    const PanelQuad q = viewer::headsetPanelQuad(1600, 900);
    const glm::dvec3 hand(0.2, -0.3, -0.2);
    auto hit = viewer::panelHit(q, towards(hand, q.centre));
    REQUIRE(hit);
    CHECK(hit->x == doctest::Approx(0.5));
    CHECK(hit->y == doctest::Approx(0.5));
    // A quarter across from the left, a tenth down from the top.
    const glm::dvec3 p = q.centre + glm::dvec3(-0.2, 0.45 * 0.4, 0.0);
    hit = viewer::panelHit(q, towards(glm::dvec3(0.0), p));
    REQUIRE(hit);
    CHECK(hit->x == doctest::Approx(0.25));
    CHECK(hit->y == doctest::Approx(0.1));
    // Just inside each corner is on the panel, at that corner of the image.
    const double expected[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    const auto corners = viewer::panelCorners(q);
    for (int k = 0; k < 4; ++k) {
        hit = viewer::panelHit(q, towards(hand, q.centre + 0.999 * (corners[std::size_t(k)] - q.centre)));
        REQUIRE(hit);
        CHECK(hit->x == doctest::Approx(expected[k][0]).epsilon(0.002));
        CHECK(hit->y == doctest::Approx(expected[k][1]).epsilon(0.002));
    }
}

TEST_CASE("misses: beside the panel, pointing away, parallel, from behind") {
    const PanelQuad q = viewer::headsetPanelQuad(1600, 900);
    CHECK_FALSE(viewer::panelHit(q, towards(glm::dvec3(0.0), q.centre + glm::dvec3(0.41, 0.0, 0.0))));
    CHECK_FALSE(viewer::panelHit(q, towards(glm::dvec3(0.0), q.centre + glm::dvec3(0.0, 0.23, 0.0))));
    CHECK_FALSE(viewer::panelHit(q, {glm::dvec3(0.0, -0.6, 0.0), glm::dvec3(0.0, 0.0, 1.0)}));   // away
    CHECK_FALSE(viewer::panelHit(q, {glm::dvec3(0.0, -0.6, 0.0), glm::dvec3(1.0, 0.0, 0.0)}));   // parallel
    CHECK_FALSE(viewer::panelHit(q, {glm::dvec3(0.0, -0.6, -2.0), glm::dvec3(0.0, 0.0, 1.0)}));  // from behind
    CHECK_FALSE(viewer::panelHit(q, {glm::dvec3(0.0, -0.6, -0.5), glm::dvec3(0.0, 0.0, 0.0)}));  // no direction
}
