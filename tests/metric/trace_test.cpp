// tests/metric/trace_test.cpp: the metric along an operator's head trace (metric/trace.hpp):
// a trace that retraces the orbit gives the orbit's figures, the camera of a head row, and
// subsampling in time. Reading the CSV: tests/io/trace_file_test.cpp.
#include <scene_builders.hpp>

#include <metric/clouds.hpp>
#include <metric/trace.hpp>
#include <metric/visibility.hpp>

#include <io/trace_file.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstdio>
#include <string>

using doctest::Approx;

namespace {

constexpr const char* kHeader =
    "t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,mode,scale,hit_x,hit_y,hit_z\n";

// The head orientation whose -z looks along the camera's axis with the camera's up as y.
glm::dquat headOrientation(const render::CameraPose& pose) {
    const glm::dvec3 back = glm::normalize(pose.eye - pose.look_at);
    const glm::dvec3 right = glm::normalize(glm::cross(pose.up, back));
    return glm::normalize(glm::quat_cast(glm::dmat3(right, glm::cross(back, right), back)));
}

std::string row(double t, const glm::dvec3& p, const glm::dquat& q) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,automatic,1,,,\n", t, p.x,
                  p.y, p.z, q.w, q.x, q.y, q.z);
    return buffer;
}

metric::MetricOptions orbitOptions() {
    metric::MetricOptions o;
    o.orbit.radius_m = 20.0;
    o.orbit.altitude_m = 3.0;
    o.orbit.views = 6;
    o.width = 128;
    o.height = 128;
    o.splat_px = 3.0;
    return o;
}

}  // namespace

TEST_CASE("trace: a trace that retraces the orbit gives the orbit's metric, and looking away sees nothing") {
    const core::Scene scene = test_support::boxBehindWall(2.0f, 6.0f, 0.5f);
    const metric::MetricClouds clouds = metric::generateClouds(scene);
    metric::Evaluator evaluator(clouds, &scene);
    const metric::MetricOptions o = orbitOptions();
    const metric::MetricResult orbit = evaluator.run(o);
    REQUIRE(orbit.views_used == 6);

    std::string along = kHeader, away = kHeader;
    for (const metric::ViewResult& v : orbit.views) {
        const glm::dvec3 eye_world = orbit.origin + v.pose.eye;
        const glm::dquat q = headOrientation(v.pose);
        along += row(0.1 * v.view, eye_world, q);
        // Turned 180 deg about world z: the target is behind the head.
        away += row(0.1 * v.view, eye_world, glm::angleAxis(M_PI, glm::dvec3(0, 0, 1)) * q);
    }
    metric::MetricOptions t = o;
    for (const io::TraceRow& h : io::parseTrace(along, "along.csv").rows)
        t.poses_world.push_back(metric::cameraFromHead(h));
    const metric::MetricResult traced = evaluator.run(t);
    REQUIRE(traced.views.size() == orbit.views.size());
    for (std::size_t k = 0; k < orbit.views.size(); ++k) {
        CAPTURE(k);
        CHECK(traced.views[k].i1 == orbit.views[k].i1);
        CHECK(traced.views[k].i2 == orbit.views[k].i2);
        CHECK(traced.views[k].i3 == orbit.views[k].i3);
        CHECK(traced.views[k].i4 == orbit.views[k].i4);
        CHECK(traced.views[k].exact_visible_px == orbit.views[k].exact_visible_px);
    }
    CHECK(traced.metric_mean == Approx(orbit.metric_mean));
    CHECK(traced.visible_mean == Approx(orbit.visible_mean));
    CHECK(orbit.visible_mean > 0.1);  // the test means something: the target is seen

    metric::MetricOptions a = o;
    for (const io::TraceRow& h : io::parseTrace(away, "away.csv").rows)
        a.poses_world.push_back(metric::cameraFromHead(h));
    const metric::MetricResult looked_away = evaluator.run(a);
    CHECK(looked_away.views_used == 0);
    for (const metric::ViewResult& v : looked_away.views) CHECK(v.i1 == 0);
}

TEST_CASE("trace: subsampling in time, and the camera of a head row") {
    const glm::dquat q = glm::angleAxis(0.3, glm::normalize(glm::dvec3(1, 2, 3)));
    std::string text = std::string(kHeader) + row(0.0, {1, 2, 3}, q) + row(0.05, {1, 2, 3}, q) + row(0.1, {4, 5, 6}, q);
    const auto samples = io::parseTrace(text, "t.csv").rows;
    REQUIRE(samples.size() == 3);
    CHECK(metric::everyStep(samples, 0.1).size() == 2);
    CHECK(metric::everyStep(samples, 0.1)[1].head_world.y == 5.0);
    CHECK(metric::everyStep(samples, 0.0).size() == 3);
    // The camera looks along the head's -z: identity looks down world -z (straight down).
    io::TraceRow identity;
    identity.head_world = {1, 2, 3};
    const render::CameraPose pose = metric::cameraFromHead(identity);
    CHECK(pose.eye == glm::dvec3(1, 2, 3));
    CHECK(pose.look_at.z == Approx(2.0));
    CHECK(pose.up.y == Approx(1.0));
}
