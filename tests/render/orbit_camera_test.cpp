// Orbit camera maths with known answers.
#include <render/orbit_camera.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <cmath>

using doctest::Approx;

TEST_CASE("orbit views are equally spaced on a circle at the given radius and altitude") {
    render::OrbitCameraOptions o;
    o.radius_m = 10.0;
    o.altitude_m = 5.0;
    o.views = 4;
    const glm::dvec3 centre{100.0, 200.0, 3.0};
    const render::CameraPose p0 = render::orbitView(o, centre, 0);
    CHECK(p0.eye.x == Approx(110.0));
    CHECK(p0.eye.y == Approx(200.0));
    CHECK(p0.eye.z == Approx(8.0));
    const render::CameraPose p1 = render::orbitView(o, centre, 1);
    CHECK(p1.eye.x == Approx(100.0));
    CHECK(p1.eye.y == Approx(210.0));
    CHECK(p1.look_at == centre);
    // up is orthogonal to the view axis and points to +z
    CHECK(glm::dot(p1.up, p1.look_at - p1.eye) == Approx(0.0).epsilon(1e-12));
    CHECK(p1.up.z > 0.0);
}

TEST_CASE("orbit camera options are validated with the field and range") {
    render::OrbitCameraOptions o;
    o.radius_m = -1.0;
    CHECK_THROWS_WITH_AS(render::validate(o), "orbit-camera: radius_m = -1: allowed > 0 metres", core::Error);
    o = {};
    o.vfov_deg = 180.0;
    CHECK_THROWS_AS(render::validate(o), core::Error);
    o = {};
    o.views = 0;
    CHECK_THROWS_AS(render::validate(o), core::Error);
    CHECK_NOTHROW(render::validate(render::OrbitCameraOptions{}));
}

TEST_CASE("pixel centre rays agree with the GL projection") {
    render::CameraPose pose;
    pose.eye = {0.0, -20.0, 5.0};
    pose.look_at = {1.0, 0.0, 0.0};
    pose.up = glm::normalize(glm::dvec3(0.0, 0.0, 1.0));
    const glm::dvec3 f = glm::normalize(pose.look_at - pose.eye);
    pose.up = glm::normalize(pose.up - glm::dot(pose.up, f) * f);
    const int w = 64, h = 48;
    const glm::dmat4 vp = render::projectionMatrix(30.0, double(w) / h, 0.1, 1000.0) * render::viewMatrix(pose);
    for (int px : {0, 17, 63})
        for (int py : {0, 30, 47}) {
            const glm::dvec3 point = pose.eye + 37.0 * render::pixelCentreDirection(pose, 30.0, w, h, px, py);
            const glm::dvec4 clip = vp * glm::dvec4(point, 1.0);
            CHECK((clip.x / clip.w * 0.5 + 0.5) * w == Approx(px + 0.5));
            CHECK((clip.y / clip.w * 0.5 + 0.5) * h == Approx(py + 0.5));
        }
}

TEST_CASE("bounds project to a screen rectangle, a box behind the camera to none") {
    render::CameraPose pose;
    pose.eye = {0.0, 0.0, 0.0};
    pose.look_at = {0.0, 1.0, 0.0};
    pose.up = {0.0, 0.0, 1.0};
    const int w = 100, h = 100;
    const glm::dmat4 vp = render::projectionMatrix(90.0, 1.0, 0.1, 1000.0) * render::viewMatrix(pose);
    core::Bounds box;
    box.extend(glm::dvec3(-1.0, 10.0, -1.0));
    box.extend(glm::dvec3(1.0, 10.0, 1.0));
    const render::PixelRect r = render::projectBounds(vp, box, w, h, 0.0);
    CHECK(r.x0 == 45);
    CHECK(r.x1 == 55);
    CHECK(r.y0 == 45);
    CHECK(r.y1 == 55);
    core::Bounds behind;
    behind.extend(glm::dvec3(-1.0, -10.0, -1.0));
    behind.extend(glm::dvec3(1.0, -9.0, 1.0));
    CHECK(render::projectBounds(vp, behind, w, h, 2.0).empty());
    CHECK_FALSE(render::Frustum::fromMatrix(vp).intersects(behind));
    CHECK(render::Frustum::fromMatrix(vp).intersects(box));
}

TEST_CASE("sub-rectangle projection maps the rect's pixels onto the whole viewport") {
    const glm::dmat4 p = render::projectionMatrix(40.0, 2.0, 0.1, 100.0);
    const render::PixelRect rect{20, 10, 60, 30};
    const glm::dmat4 crop = render::subRectProjection(p, 200, 100, rect);
    const glm::dvec4 point{1.3, -0.7, -10.0, 1.0};
    const glm::dvec4 a = p * point, b = crop * point;
    const double full_x = (a.x / a.w * 0.5 + 0.5) * 200, full_y = (a.y / a.w * 0.5 + 0.5) * 100;
    const double sub_x = (b.x / b.w * 0.5 + 0.5) * rect.width(), sub_y = (b.y / b.w * 0.5 + 0.5) * rect.height();
    CHECK(sub_x == Approx(full_x - rect.x0));
    CHECK(sub_y == Approx(full_y - rect.y0));
}
