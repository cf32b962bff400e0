// tests/sim/sensor_noise_test.cpp: the range error model on a flat plane (known answer),
// the maximum range, and bit-identical clouds whatever the thread count with every model on.
#include <scene_builders.hpp>

#include <sim/generator.hpp>
#include <sim/orbit.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace {

// A flat ground plane at z = 0 far wider than any footprint.
core::Scene planeScene() {
    core::Scene s;
    s.source = "plane (in code)";
    s.meshes.push_back(test_support::quadMesh(2000.0f, 0.0f, core::Role::Ground, "plane"));
    return s;
}

// Range error of each point of `cloud`: the point lies on its ray at the measured range
// t'; the ray meets z = 0 at t = -o.z / d.z with d = (p - o) / t', so t' - t = p.z t' / (p.z - o.z).
std::vector<double> rangeErrors(const core::PointCloud& cloud, const sim::GenerateOptions& o,
                                const glm::dvec3& centre_local) {
    std::vector<double> e;
    for (const core::CloudPoint& p : cloud.points) {
        const glm::dvec3 origin = sim::sensorPose(o.orbit, centre_local, p.view).translation;
        const double t = p.range_m, z = p.position.z;
        e.push_back(z * t / (z - origin.z));
    }
    return e;
}

}  // namespace

TEST_CASE("sensor: range noise of sigma on a flat plane measures sigma within 5 % over 10^5 returns") {
    const core::Scene scene = planeScene();
    sim::GenerateOptions o;
    o.orbit.xres = 64;
    o.orbit.yres = 64;
    o.orbit.views = 25;  // 102,400 returns
    o.white = true;
    const glm::dvec3 centre(0.0);
    o.centre = centre;

    // The measure itself: the ideal sensor's errors are float rounding only.
    {
        const core::PointCloud ideal = sim::generateCloud(scene, o);
        double worst = 0.0;
        for (double e : rangeErrors(ideal, o, centre)) worst = std::max(worst, std::abs(e));
        CHECK(worst < 2e-3);
    }
    const double sigma_m = 0.05;
    o.sensor.range_noise_m = sigma_m;
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(scene, o, &st);
    REQUIRE(cloud.points.size() == 102400);
    CHECK(st.misses == 0);
    const std::vector<double> e = rangeErrors(cloud, o, centre);
    double sum = 0.0, sum2 = 0.0;
    for (double x : e) sum += x;
    const double mean = sum / double(e.size());
    for (double x : e) sum2 += (x - mean) * (x - mean);
    const double sd = std::sqrt(sum2 / double(e.size() - 1));
    CHECK(std::abs(mean) < 5.0 * sigma_m / std::sqrt(double(e.size())));
    CHECK(sd ==
          doctest::Approx(sigma_m).epsilon(0.05).scale(0.0));  // relative: doctest adds 1.0 to the scale by default
    // Noise is along the beam: range_m is the noisy range of the placed point.
    CHECK(cloud.fields.scan_angle);
}

TEST_CASE("sensor: echoes beyond --max-range-m are lost") {
    const core::Scene scene = planeScene();
    sim::GenerateOptions o;
    o.orbit.xres = 32;
    o.orbit.yres = 32;
    o.orbit.views = 4;
    o.white = true;
    // The paper's orbit sees the plane from 400 to 452 m (alpha +- fov/2 at 300 m).
    const core::PointCloud all = sim::generateCloud(scene, o);
    o.sensor.max_range_m = 430.0;
    sim::GenerateStats st;
    const core::PointCloud near = sim::generateCloud(scene, o, &st);
    CHECK(near.points.size() < all.points.size());
    CHECK(near.points.size() > all.points.size() / 4);
    CHECK(st.misses == all.points.size() - near.points.size());
    std::size_t beyond = 0, expected = 0;
    for (const auto& p : near.points) beyond += p.range_m > 430.0f;
    for (const auto& p : all.points) expected += p.range_m <= 430.0f;
    CHECK(beyond == 0);
    CHECK(near.points.size() == expected);
}

TEST_CASE("sensor: with every model on, 1 and 3 threads give the same bytes, and a new seed other bytes") {
    const core::Scene scene = test_support::townScene(120.0, 1.0);
    sim::GenerateOptions o;
    o.orbit.xres = 48;
    o.orbit.yres = 40;
    o.orbit.views = 10;
    o.white = true;
    sim::SensorOptions& s = o.sensor;
    s.range_noise_m = 0.03;
    s.pose_noise_m = 0.05;
    s.attitude_noise_deg = 0.05;
    s.pose_bias_m = 0.02;
    s.attitude_bias_deg = 0.01;
    s.max_range_m = 445.0;
    s.intensity = true;
    s.min_intensity = 200.0;
    s.beam_divergence_mrad = 3.0;
    s.beam_divergence_y_mrad = 5.0;
    s.footprint_quality = 2;
    s.returns = sim::ReturnMode::All;
    s.max_returns = 4;
    o.threads = 1;
    const core::PointCloud one = sim::generateCloud(scene, o);
    o.threads = 3;
    const core::PointCloud three = sim::generateCloud(scene, o);
    REQUIRE(one.points.size() == three.points.size());
    CHECK(one.points.size() > 10000);
    CHECK(std::memcmp(one.points.data(), three.points.data(), one.points.size() * sizeof(core::CloudPoint)) == 0);
    std::size_t multiple = 0;
    for (const auto& p : one.points) multiple += p.returns > 1;
    CHECK(multiple > 0);  // the houses' edges give mixed pixels
    o.seed = 2;
    const core::PointCloud other = sim::generateCloud(scene, o);
    CHECK((other.points.size() != one.points.size() ||
           std::memcmp(one.points.data(), other.points.data(), one.points.size() * sizeof(core::CloudPoint)) != 0));
}
