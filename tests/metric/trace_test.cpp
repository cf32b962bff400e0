// tests/metric/trace_test.cpp: the metric along an operator's head trace (metric/trace.hpp):
// strict reading of the CSV, and a trace that retraces the orbit gives the orbit's figures.
#include <scene_builders.hpp>

#include <metric/clouds.hpp>
#include <metric/trace.hpp>
#include <metric/visibility.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <cstdio>
#include <string>

using doctest::Approx;

namespace {

constexpr const char* kHeader = "t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,mode,scale,hit_x,hit_y,hit_z\n";

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
    for (const metric::HeadSample& h : metric::parseTrace(along, "along.csv"))
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
    for (const metric::HeadSample& h : metric::parseTrace(away, "away.csv"))
        a.poses_world.push_back(metric::cameraFromHead(h));
    const metric::MetricResult looked_away = evaluator.run(a);
    CHECK(looked_away.views_used == 0);
    for (const metric::ViewResult& v : looked_away.views) CHECK(v.i1 == 0);
}

TEST_CASE("trace: samples, extra columns, CRLF and subsampling in time") {
    const glm::dquat q = glm::angleAxis(0.3, glm::normalize(glm::dvec3(1, 2, 3)));
    std::string text = std::string(kHeader) + row(0.0, {1, 2, 3}, q) + row(0.05, {1, 2, 3}, q) + row(0.1, {4, 5, 6}, q);
    const auto samples = metric::parseTrace(text, "t.csv");
    REQUIRE(samples.size() == 3);
    CHECK(samples[2].head_world.y == 5.0);
    CHECK(samples[1].t_s == 0.05);
    CHECK(std::abs(glm::dot(samples[0].head_orientation, q)) == Approx(1.0));
    CHECK(metric::everyStep(samples, 0.1).size() == 2);
    CHECK(metric::everyStep(samples, 0.0).size() == 3);
    // CRLF line ends and only the eight needed columns.
    const std::string crlf = "t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz\r\n0,1,2,3,1,0,0,0\r\n";
    CHECK(metric::parseTrace(crlf, "crlf.csv").size() == 1);
    // The camera looks along the head's -z: identity looks down world -z (straight down).
    const render::CameraPose pose = metric::cameraFromHead(metric::parseTrace(crlf, "crlf.csv")[0]);
    CHECK(pose.look_at.z == Approx(2.0));
    CHECK(pose.up.y == Approx(1.0));
}

TEST_CASE("trace: malformed files give one line naming the line and the column") {
    const std::string good = "0,1,2,3,1,0,0,0,automatic,1,,,\n";
    auto error = [](const std::string& text) {
        try {
            metric::parseTrace(text, "bad.csv");
        } catch (const core::Error& e) {
            const std::string m = e.what();
            CHECK(m.find('\n') == std::string::npos);
            CHECK(m.rfind("trace: bad.csv: line ", 0) == 0);
            return m;
        }
        FAIL("no error for: " << text);
        return std::string();
    };
    CHECK(error("").find("empty file") != std::string::npos);
    CHECK(error(kHeader).find("no samples") != std::string::npos);
    CHECK(error("t_s,head_x,head_y\n0,1,2\n").find("header column 4") != std::string::npos);
    CHECK(error("t,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz\n").find("header column 1 is 't'") !=
          std::string::npos);
    CHECK(error(std::string(kHeader) + good + "0.1,1,2,x3,1,0,0,0,automatic,1,,,\n")
              .find("line 3, column head_z: 'x3' is not a finite number") != std::string::npos);
    CHECK(error(std::string(kHeader) + "0,1,2,nan,1,0,0,0,automatic,1,,,\n").find("column head_z") != std::string::npos);
    CHECK(error(std::string(kHeader) + "0,1,2,3 ,1,0,0,0,automatic,1,,,\n").find("column head_z") != std::string::npos);
    CHECK(error(std::string(kHeader) + "0,1,2,3,1,0,0,0\n").find("line 2: 8 fields; allowed 13") != std::string::npos);
    CHECK(error(std::string(kHeader) + "0,1,2,3,2,0,0,0,automatic,1,,,\n").find("quaternion norm") != std::string::npos);
    CHECK(error(std::string(kHeader) + "1,1,2,3,1,0,0,0,automatic,1,,,\n" + good).find("line 3, column t_s: decreases") !=
          std::string::npos);
    CHECK(error(std::string(kHeader) + "-1,1,2,3,1,0,0,0,automatic,1,,,\n").find("negative") != std::string::npos);
    CHECK(error(std::string(kHeader) + good + "\n" + good).find("line 3: empty line") != std::string::npos);
    CHECK(error(std::string(kHeader) + "0,1e300,2,3,1,0,0,0,automatic,1,,,\n").find("out of range") != std::string::npos);
}
