// tests/viewer/mode_controller_test.cpp: the modes' camera maths with known answers.
#include <viewer/mode_controller.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

using namespace viewer;

namespace {
constexpr double kPi = std::numbers::pi;
double distance(const glm::dvec3& a, const glm::dvec3& b) { return glm::length(a - b); }
glm::dvec3 gaze(const RigPose& p) { return p.rotation * glm::dvec3(0, 0, -1); }
RigPose compose(const RigPose& a, const RigPose& b) {
    return {a.rotation * b.rotation, a.rotation * b.position + a.position};
}
RigPose headYawed(double yaw_rad, const glm::dvec3& position) {
    return {glm::mat3_cast(lookOrientation(yaw_rad, 0.0)), position};
}
}  // namespace

TEST_CASE("camera-relative chunks keep millimetres 10^6 m from the origin") {
    // A point 1e6 m out, stored as a float offset from its chunk centre; the camera is 12 m away.
    const glm::dvec3 chunk_centre(1.0e6, 2.0e6, 0.0);
    const glm::dvec3 point(1.0e6 + 0.123, 2.0e6 - 0.456, 10.789);
    render::CameraPose camera;
    camera.eye = point + glm::dvec3(5.0, 5.0, 9.0);
    camera.look_at = point;
    const glm::dmat4 view = viewFromPose(rigFromCamera(camera));
    const glm::dvec3 exact = glm::dvec3(view * glm::dvec4(point, 1.0));

    const glm::vec3 rel(point - chunk_centre);
    const glm::vec3 ours = glm::vec3(chunkModelView(view, chunk_centre) * glm::vec4(rel, 1.0f));
    CHECK(distance(glm::dvec3(ours), exact) < 1e-4);

    // The naive path (float world coordinates, float view) is off by centimetres: why chunks exist.
    const glm::vec3 naive = glm::vec3(glm::mat4(view) * glm::vec4(glm::vec3(point), 1.0f));
    CHECK(distance(glm::dvec3(naive), exact) > 1e-2);
}

TEST_CASE("the automatic rig sits on the shared orbit camera and looks at the centre") {
    ModeOptions o;  // render::OrbitCameraOptions defaults: radius 60 m, altitude 40 m
    const glm::dvec3 centre(10.0, -5.0, 2.0);
    const RigPose rig = rigFromCamera(render::orbitPose(o.orbit, centre, 0.0));
    CHECK(distance(rig.position, centre + glm::dvec3(60.0, 0.0, 40.0)) < 1e-9);
    CHECK(distance(gaze(rig), glm::normalize(centre - rig.position)) < 1e-9);
    // Tracking up (y) has a positive world z: the horizon stays level in the HMD.
    CHECK((rig.rotation * glm::dvec3(0, 1, 0)).z > 0.8);
    CHECK(std::abs(glm::determinant(rig.rotation) - 1.0) < 1e-12);
}

TEST_CASE("automatic mode turns at the orbit period and cannot translate") {
    ModeOptions o;
    o.orbit_period_s = 1.0;
    const glm::dvec3 centre(0.0);
    ModeController modes(o, centre);
    modes.update(0.25, {}, RigPose{});  // a quarter turn
    CHECK(distance(modes.rig().position, glm::dvec3(0.0, 60.0, 40.0)) < 1e-9);
    // Motion requests do not translate in automatic mode.
    Motion push;
    push.forward = 1.0;
    modes.update(1e-9, push, RigPose{});
    CHECK(distance(modes.rig().position, glm::dvec3(0.0, 60.0, 40.0)) < 1e-6);
    // A stalled frame is clamped to 0.25 s: the user is not thrown around the orbit.
    modes.update(10.0, {}, RigPose{});
    CHECK(distance(modes.rig().position, glm::dvec3(-60.0, 0.0, 40.0)) < 1e-6);
}

TEST_CASE("switching modes keeps the head where it is and the gaze heading") {
    ModeOptions o;
    ModeController modes(o, glm::dvec3(3.0, 4.0, 1.0));
    modes.update(0.2, {}, RigPose{});
    const RigPose head = headYawed(0.35, glm::dvec3(0.1, 0.2, -0.3));
    const RigPose before = compose(modes.rig(), head);

    CHECK(modes.toggle(head) == ViewMode::Free);
    const RigPose after = compose(modes.rig(), head);
    CHECK(distance(after.position, before.position) < 1e-9);
    const glm::dvec3 g0 = gaze(before), g1 = gaze(after);
    CHECK(std::abs(std::atan2(g0.y, g0.x) - std::atan2(g1.y, g1.x)) < 1e-9);
    CHECK(distance(modes.rig().rotation * glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)) < 1e-12);  // level

    // Free mode flies along the gaze: 1 s forward at 15 m/s (in 0.2 s steps).
    const glm::dvec3 start = compose(modes.rig(), head).position;
    Motion forward;
    forward.forward = 1.0;
    for (int i = 0; i < 5; ++i) modes.update(0.2, forward, head);
    const glm::dvec3 end = compose(modes.rig(), head).position;
    CHECK(distance(end - start, 15.0 * g1) < 1e-9);

    // Back to automatic: the orbit resumes at the angle it had.
    const double angle = modes.orbitAngleRad();
    CHECK(modes.toggle(head) == ViewMode::Automatic);
    CHECK(modes.orbitAngleRad() == angle);
    CHECK(distance(modes.rig().position, render::orbitPose(o.orbit, modes.centre(), angle).eye) < 1e-9);
}

TEST_CASE("the desktop switch keeps the exact view direction and position") {
    ModeController modes(ModeOptions{}, glm::dvec3(0.0));
    double yaw = 0.3, pitch = -0.2;
    const RigPose before = compose(modes.rig(), {glm::mat3_cast(lookOrientation(yaw, pitch)), glm::dvec3(0.0)});
    modes.toggleDesktop(yaw, pitch);
    CHECK(modes.mode() == ViewMode::Free);
    const RigPose after = compose(modes.rig(), {glm::mat3_cast(lookOrientation(yaw, pitch)), glm::dvec3(0.0)});
    CHECK(distance(gaze(before), gaze(after)) < 1e-9);
    CHECK(distance(before.position, after.position) < 1e-9);
    modes.toggleDesktop(yaw, pitch);
    CHECK(modes.mode() == ViewMode::Automatic);
    CHECK(yaw == 0.0);
    CHECK(pitch == 0.0);
}

TEST_CASE("a symmetric OpenXR FoV gives the usual perspective") {
    const double half = 30.0 * kPi / 180.0;
    const double aspect = 4.0 / 3.0;
    const double half_x = std::atan(std::tan(half) * aspect);
    const glm::dmat4 a = projectionFromFov(-half_x, half_x, half, -half, 0.1, 100.0);
    const glm::dmat4 b = render::projectionMatrix(60.0, aspect, 0.1, 100.0);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) CHECK(a[c][r] == doctest::Approx(b[c][r]).epsilon(1e-9));
    // An asymmetric eye: the centre of projection shifts, the edges land on the NDC border.
    const glm::dmat4 p = projectionFromFov(-0.9, 0.6, 0.7, -0.8, 0.1, 100.0);
    const glm::dvec4 edge = p * glm::dvec4(std::tan(0.6), std::tan(0.7), -1.0, 1.0);
    CHECK(edge.x / edge.w == doctest::Approx(1.0));
    CHECK(edge.y / edge.w == doctest::Approx(1.0));
}

TEST_CASE("the eyes' depth is what XR_KHR_composition_layer_depth reads with nearZ and farZ") {
    // The eyes' depth goes to the compositor with minDepth 0, maxDepth 1, nearZ = near and
    // farZ = far (viewer/src/xr/xr_session.cpp): that holds while projectionFromFov keeps OpenGL's
    // convention (window depth = (NDC z + 1) / 2, not reversed, far finite), where a point
    // d metres in front has window depth far (d - near) / (d (far - near)).
    const double near_m = 0.1, far_m = 20000.0;
    const glm::dmat4 p = projectionFromFov(-0.9, 0.6, 0.7, -0.8, near_m, far_m);
    for (double d : {near_m, 0.5, 3.0, 120.0, 4000.0, far_m}) {
        const glm::dvec4 clip = p * glm::dvec4(0.2 * d, -0.1 * d, -d, 1.0);
        const double window = 0.5 * (clip.z / clip.w + 1.0);
        CHECK(window == doctest::Approx(far_m * (d - near_m) / (d * (far_m - near_m))).epsilon(1e-9));
    }
    const glm::dvec4 at_near = p * glm::dvec4(0.0, 0.0, -near_m, 1.0), at_far = p * glm::dvec4(0.0, 0.0, -far_m, 1.0);
    CHECK(0.5 * (at_near.z / at_near.w + 1.0) == doctest::Approx(0.0));
    CHECK(0.5 * (at_far.z / at_far.w + 1.0) == doctest::Approx(1.0));
}

TEST_CASE("mode options are validated at the boundary") {
    ModeOptions o;
    CHECK_NOTHROW(validate(o));
    o.orbit_period_s = 0.0;
    CHECK_THROWS_WITH_AS(validate(o), doctest::Contains("orbit_period_s"), core::Error);
    o = {};
    o.orbit.radius_m = -1.0;
    CHECK_THROWS_AS(validate(o), core::Error);
    CHECK(std::string(modeName(ViewMode::Automatic)) == "automatic");
    CHECK(std::string(modeName(ViewMode::Free)) == "free");
}

TEST_CASE("a cloud's extent sets the orbit, the start pose and the free speed when fitting is on") {
    ModeOptions o;  // today's 60 m radius, 40 m height, 15 m/s
    const ModeOptions f = fittedToExtent(o, glm::dvec3(300.0, 400.0, 50.0));
    CHECK(f.orbit.radius_m == doctest::Approx(250.0));  // half the horizontal diagonal
    CHECK(f.orbit.altitude_m == doctest::Approx(250.0 * 40.0 / 60.0));
    CHECK(f.free_speed_mps == doctest::Approx(15.0 * 250.0 / 60.0));
    CHECK(f.orbit.far_m >= o.orbit.far_m);
    CHECK(fittedToExtent(o, glm::dvec3(0.0)).orbit.radius_m == doctest::Approx(1.0));

    // The start pose follows: the rig sits on the fitted orbit, above the cloud's edge.
    o.fit_to_cloud = true;
    ModeController fitted(o, glm::dvec3(0.0));
    fitted.setCloudBounds(glm::dvec3(1000.0, 2000.0, 0.0), glm::dvec3(1300.0, 2400.0, 50.0));
    const glm::dvec3 centre(1150.0, 2200.0, 25.0);
    CHECK(distance(fitted.centre(), centre) < 1e-9);
    const RigPose start = fitted.rig();
    CHECK(glm::length(glm::dvec2(start.position - centre)) == doctest::Approx(250.0));
    CHECK(start.position.z - centre.z == doctest::Approx(250.0 * 40.0 / 60.0));
    CHECK(fitted.options().orbit.radius_m == doctest::Approx(250.0));  // refits from the given values
    fitted.setCloudBounds(glm::dvec3(0.0), glm::dvec3(30.0, 40.0, 5.0));
    CHECK(fitted.options().orbit.radius_m == doctest::Approx(25.0));

    // Off (a generated cloud, or --orbit-radius given): today's orbit whatever the cloud.
    o.fit_to_cloud = false;
    ModeController fixed(o, glm::dvec3(0.0));
    fixed.setCloudBounds(glm::dvec3(0.0), glm::dvec3(3000.0, 4000.0, 50.0));
    CHECK(fixed.options().orbit.radius_m == 60.0);
    CHECK(fixed.options().orbit.altitude_m == 40.0);
    CHECK(distance(fixed.centre(), glm::dvec3(1500.0, 2000.0, 25.0)) < 1e-9);
}
