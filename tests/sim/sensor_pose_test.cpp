// tests/sim/sensor_pose_test.cpp: GNSS/INS error. Each view's points are placed with the
// logged pose while the rays left from the pose flown, so on a flat plane a position error
// e moves the whole view by -e: the views' mean heights scatter by sigma and two views
// differ by sigma * sqrt(2). An attitude error delta about the sensor's x axis moves the
// image centre's ground point, placed along the logged ray, by -h tan(alpha) delta in
// height (h: altitude, alpha: inclination), so the views' mean heights scatter by
// h tan(alpha) sigma_att.
#include <scene_builders.hpp>

#include <sim/generator.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace {

core::Scene planeScene() {
    core::Scene s;
    s.source = "plane (in code)";
    s.meshes.push_back(test_support::quadMesh(2000.0f, 0.0f, core::Role::Ground, "plane"));
    return s;
}

// Mean height of each view's points.
std::vector<double> viewHeights(const sim::SensorOptions& sensor, int views) {
    sim::GenerateOptions o;
    o.orbit.xres = 16;
    o.orbit.yres = 16;
    o.orbit.views = views;
    o.white = true;
    o.centre = glm::dvec3(0.0);
    o.sensor = sensor;
    const core::PointCloud cloud = sim::generateCloud(planeScene(), o);
    std::vector<double> sum(std::size_t(views), 0.0), n(std::size_t(views), 0.0);
    for (const auto& p : cloud.points) {
        sum[p.view] += p.position.z;
        n[p.view] += 1.0;
    }
    for (std::size_t v = 0; v < sum.size(); ++v) sum[v] /= n[v];
    return sum;
}

double rms(const std::vector<double>& x) {
    double s = 0.0;
    for (double v : x) s += v * v;
    return std::sqrt(s / double(x.size()));
}

}  // namespace

TEST_CASE("sensor: a position error of sigma misregisters views by sigma, view to view by sigma * sqrt(2)") {
    const int views = 400;
    CHECK(rms(viewHeights(sim::SensorOptions{}, views)) < 1e-3);  // ideal: every view on the plane
    sim::SensorOptions s;
    s.pose_noise_m = 0.1;
    const std::vector<double> z = viewHeights(s, views);
    CHECK(rms(z) == doctest::Approx(0.1).epsilon(0.12).scale(0.0));  // relative (doctest's default scale is 1.0)
    std::vector<double> step;
    for (std::size_t v = 1; v < z.size(); ++v) step.push_back(z[v] - z[v - 1]);
    CHECK(rms(step) == doctest::Approx(0.1 * std::sqrt(2.0)).epsilon(0.12).scale(0.0));
    // A per-flight bias moves every view alike: no misregistration, one common offset.
    sim::SensorOptions b;
    b.pose_bias_m = 0.1;
    const std::vector<double> zb = viewHeights(b, 50);
    for (double x : zb) CHECK(x == doctest::Approx(zb[0]).epsilon(1e-9).scale(1e-4));
    CHECK(std::abs(zb[0]) > 1e-3);
}

TEST_CASE("sensor: an attitude error of sigma misregisters views by altitude * tan(alpha) * sigma") {
    sim::SensorOptions s;
    s.attitude_noise_deg = 0.05;
    const double expected_m = 300.0 * std::tan(45.0 * std::numbers::pi / 180.0) * 0.05 * std::numbers::pi / 180.0;
    CHECK(rms(viewHeights(s, 400)) == doctest::Approx(expected_m).epsilon(0.15).scale(0.0));
}
