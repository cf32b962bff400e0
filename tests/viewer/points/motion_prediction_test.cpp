// tests/viewer/points/motion_prediction_test.cpp: the head's predicted motion (constant linear
// and angular velocity over the look-ahead) with known answers, and the selection frusta
// widened by it: a box just outside the view is seen once the head turns or moves
// towards it, and a still head adds no frustum.
#include <viewer/motion_prediction.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace viewer;

namespace {

glm::dquat yaw(double rad) { return glm::angleAxis(rad, glm::dvec3(0.0, 0.0, 1.0)); }

bool near(const glm::dvec3& a, const glm::dvec3& b, double eps = 1e-9) { return glm::length(a - b) < eps; }

core::Bounds box(const glm::dvec3& centre, double half_m) {
    core::Bounds b;
    b.lo = centre - glm::dvec3(half_m);
    b.hi = centre + glm::dvec3(half_m);
    return b;
}

bool seen(const std::vector<render::Frustum>& frusta, const core::Bounds& b) {
    for (const render::Frustum& f : frusta)
        if (f.intersects(b)) return true;
    return false;
}

}  // namespace

TEST_CASE("predicted motion: constant velocity over the look-ahead") {
    // 1 m/s along x, no turn: over 0.25 s the head moves 0.25 m.
    const std::vector<HeadSample> line = {{0.0, {0, 0, 0}, {}}, {0.1, {0.1, 0, 0}, {}}, {0.2, {0.2, 0, 0}, {}}};
    const glm::dmat4 m = predictedMotion(line, 0.25);
    CHECK(near(glm::dvec3(m * glm::dvec4(3, 4, 5, 1)), {3.25, 4, 5}));
    CHECK(moves(m));
    // 90 deg/s about z, standing at (10, 0, 0): over 0.5 s a quarter turn of 45 deg about
    // the head, so a point 1 m ahead along x ends up 1 m ahead along the diagonal.
    const std::vector<HeadSample> turn = {{1.0, {10, 0, 0}, yaw(0.0)}, {1.2, {10, 0, 0}, yaw(0.1 * std::numbers::pi)}};
    const glm::dmat4 r = predictedMotion(turn, 0.5);
    const double d = std::sqrt(0.5);
    CHECK(near(glm::dvec3(r * glm::dvec4(11, 0, 0, 1)), {10 + d, d, 0}));
    CHECK(near(glm::dvec3(r * glm::dvec4(10, 0, 0, 1)), {10, 0, 0}));
    // Nothing to go on, or no motion: the identity.
    CHECK_FALSE(moves(predictedMotion(std::vector<HeadSample>{}, 0.25)));
    CHECK_FALSE(moves(predictedMotion(std::vector<HeadSample>{line[0]}, 0.25)));
    CHECK_FALSE(moves(predictedMotion(std::vector<HeadSample>{line[0], line[0]}, 0.25)));  // no time between
    const std::vector<HeadSample> still = {{0.0, {1, 2, 3}, yaw(0.3)}, {0.5, {1, 2, 3}, yaw(0.3)}};
    CHECK_FALSE(moves(predictedMotion(still, 0.25)));
    // Rounding in a still head's pose is not motion.
    const std::vector<HeadSample> jitter = {{0.0, {1, 2, 3}, yaw(0.3)}, {0.5, {1, 2, 3 + 1e-12}, yaw(0.3 + 1e-12)}};
    CHECK_FALSE(moves(predictedMotion(jitter, 0.25)));
}

TEST_CASE("the widened frusta see what a turning head will see, and a still head adds nothing") {
    // An eye at the origin looking along -y (OpenGL: -z of the eye), 60 deg vertical fov.
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));
    const glm::dmat4 projection = glm::perspective(glm::radians(60.0), 1.0, 0.1, 1000.0);
    const std::vector<glm::dmat4> views = {view}, projections = {projection};
    // Boxes 100 m away, 60 deg to the left (+x: looking along -y with z up, the right hand
    // is -x) and to the right, outside the 30 deg half view.
    const double a = glm::radians(60.0);
    const core::Bounds left = box(glm::dvec3(100 * std::sin(a), -100 * std::cos(a), 0), 1.0);
    const core::Bounds right = box(glm::dvec3(-100 * std::sin(a), -100 * std::cos(a), 0), 1.0);
    const std::vector<render::Frustum> now = widenedFrusta(views, projections, glm::dmat4(1.0));
    CHECK(now.size() == 1);
    CHECK_FALSE(seen(now, left));
    CHECK_FALSE(seen(now, right));
    // Turning at 60 deg/s to the left (a positive yaw about z), then to the right: over a
    // look-ahead of 0.6 s the head turns 36 deg, bringing that side's box 24 deg off axis.
    const HeadSample h0 = headOfView(view, 0.0);
    CHECK(near(h0.position, glm::dvec3(0.0)));
    for (double sign : {1.0, -1.0}) {
        const glm::dquat turned = yaw(sign * glm::radians(6.0)) * h0.orientation;
        const std::vector<HeadSample> history = {h0, {0.1, h0.position, turned}};
        const std::vector<render::Frustum> wide = widenedFrusta(views, projections, predictedMotion(history, 0.6));
        CHECK(wide.size() == 2);
        CHECK(seen(wide, sign > 0 ? left : right));
        CHECK_FALSE(seen(wide, sign > 0 ? right : left));
    }
    // Moving forward fast: a box behind the far plane comes into the widened set.
    const core::Bounds far_box = box(glm::dvec3(0, -1100, 0), 1.0);
    CHECK_FALSE(seen(now, far_box));
    const std::vector<HeadSample> forward = {{0.0, {0, 0, 0}, h0.orientation}, {0.1, {0, -50, 0}, h0.orientation}};
    CHECK(seen(widenedFrusta(views, projections, predictedMotion(forward, 0.25)), far_box));
}

TEST_CASE("headOfView undoes a zoom's uniform scale") {
    const glm::dmat4 rigid = glm::lookAt(glm::dvec3(5, 6, 7), glm::dvec3(5, 0, 7), glm::dvec3(0, 0, 1));
    const glm::dmat4 scaled = glm::scale(glm::dmat4(1.0), glm::dvec3(4.0)) * rigid;
    const HeadSample a = headOfView(rigid, 1.0), b = headOfView(scaled, 1.0);
    CHECK(near(a.position, {5, 6, 7}));
    CHECK(near(b.position, {5, 6, 7}, 1e-6));
    CHECK(std::abs(glm::dot(a.orientation, b.orientation)) == doctest::Approx(1.0));
    CHECK(near(a.orientation * glm::dvec3(0, 0, -1), {0, -1, 0}));
}
