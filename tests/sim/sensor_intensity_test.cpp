// tests/sim/sensor_intensity_test.cpp: intensity by the lidar equation,
// I = 65535 min(1, rho cos(theta) (R0 / R)^2), with rho from the scene's per-mesh
// 'reflectance', theta the incidence on the surface, R the range; and --min-intensity
// dropouts.
#include <scene_builders.hpp>
#include <test_files.hpp>

#include <sim/generator.hpp>
#include <sim/orbit.hpp>

#include <core/error.hpp>
#include <io/scene_file.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

namespace {

// Two ground halves side by side: x < 0 of reflectance `left`, x > 0 of `right`.
core::Scene halvesScene(double left, double right) {
    core::Scene s;
    s.source = "halves (in code)";
    s.meshes.push_back(test_support::gridMesh(-500.0, 0.0, 0.0, 1, 1000.0, core::Role::Ground, "left"));
    s.meshes.push_back(test_support::gridMesh(500.0, 0.0, 0.0, 1, 1000.0, core::Role::Ground, "right"));
    s.meshes[0].reflectance = left;
    s.meshes[1].reflectance = right;
    return s;
}

sim::GenerateOptions intensityOptions(double alpha_deg) {
    sim::GenerateOptions o;
    o.orbit.inclination_deg = alpha_deg;
    o.orbit.xres = 32;
    o.orbit.yres = 32;
    o.orbit.views = 8;
    o.white = true;
    o.centre = glm::dvec3(0.0);
    o.sensor.intensity = true;
    o.sensor.intensity_reference_range_m = 100.0;
    return o;
}

}  // namespace

TEST_CASE("sensor: intensity falls with incidence and range as the lidar equation says") {
    const core::Scene scene = halvesScene(0.5, 0.5);
    std::size_t checked = 0, wrong_angle = 0, wrong_intensity = 0;
    double lowest_deg = 90.0, highest_deg = 0.0;
    for (const double alpha : {10.0, 45.0, 70.0}) {
        const sim::GenerateOptions o = intensityOptions(alpha);
        const core::PointCloud cloud = sim::generateCloud(scene, o);
        CHECK(cloud.fields.intensity);
        CHECK(cloud.fields.incidence);
        for (const auto& p : cloud.points) {
            const glm::dvec3 origin = sim::sensorPose(o.orbit, glm::dvec3(0.0), p.view).translation;
            const glm::dvec3 beam = glm::dvec3(p.position) - origin;
            // The plane's normal is z: cos(theta) = |beam.z| / |beam|.
            const double cos_theta = std::abs(beam.z) / glm::length(beam);
            const double theta_deg = std::acos(cos_theta) * 180.0 / std::numbers::pi;
            wrong_angle += std::abs(theta_deg - double(p.incidence_deg)) > 0.01;
            const double q = 100.0 / double(p.range_m);
            const double expected = 65535.0 * std::min(1.0, 0.5 * cos_theta * q * q);
            wrong_intensity += std::abs(expected - double(p.intensity)) > 1.0;
            lowest_deg = std::min(lowest_deg, theta_deg);
            highest_deg = std::max(highest_deg, theta_deg);
            ++checked;
        }
    }
    CHECK(checked == 3 * 8 * 32 * 32);
    CHECK(wrong_angle == 0);
    CHECK(wrong_intensity == 0);
    CHECK(lowest_deg < 10.0);
    CHECK(highest_deg > 70.0);
}

TEST_CASE("sensor: intensity scales with the mesh's reflectance, and --min-intensity drops weak echoes") {
    const core::Scene scene = halvesScene(0.2, 0.8);
    sim::GenerateOptions o = intensityOptions(20.0);
    const core::PointCloud cloud = sim::generateCloud(scene, o);
    // Normalised by cos(theta) / R^2, the two halves read 0.2 and 0.8 of full scale at R0.
    double norm[2] = {0.0, 0.0}, n[2] = {0.0, 0.0};
    std::uint16_t dim_max = 0, bright_min = 65535;
    for (const auto& p : cloud.points) {
        const int half = p.position.x > 0.0f;
        const double cos_theta = std::cos(double(p.incidence_deg) * std::numbers::pi / 180.0);
        const double q = 100.0 / double(p.range_m);
        norm[half] += double(p.intensity) / (65535.0 * cos_theta * q * q);
        n[half] += 1.0;
        if (half == 0)
            dim_max = std::max(dim_max, p.intensity);
        else
            bright_min = std::min(bright_min, p.intensity);
    }
    REQUIRE(n[0] > 100);
    REQUIRE(n[1] > 100);
    CHECK(norm[0] / n[0] == doctest::Approx(0.2).epsilon(1e-3));
    CHECK(norm[1] / n[1] == doctest::Approx(0.8).epsilon(1e-3));
    REQUIRE(dim_max < bright_min);

    // A threshold between the two halves keeps the bright half only.
    o.sensor.min_intensity = 0.5 * (double(dim_max) + double(bright_min));
    sim::GenerateStats st;
    const core::PointCloud kept = sim::generateCloud(scene, o, &st);
    CHECK(kept.points.size() == std::size_t(n[1]));
    CHECK(st.misses == std::size_t(n[0]));
    for (const auto& p : kept.points) CHECK(p.position.x > 0.0f);
}

TEST_CASE("scene: 'reflectance' is read per mesh, 0.5 by default, and must lie in [0, 1]") {
    const std::filesystem::path file = test_support::basicDir() / "virtual.json";
    const core::Scene s = io::loadSceneJson(
        R"({"meshes": [{"file": "box.obj", "role": "target", "reflectance": 0.12},
                       {"file": "box.obj", "role": "ground", "position": [5, 0, 0]}]})",
        file);
    REQUIRE(s.meshes.size() == 2);
    CHECK(s.meshes[0].reflectance == 0.12);
    CHECK(s.meshes[1].reflectance == 0.5);
    CHECK_THROWS_WITH_AS(
        io::loadSceneJson(R"({"meshes": [{"file": "box.obj", "role": "target", "reflectance": 1.5}]})", file),
        doctest::Contains("meshes[0] ('box.obj'): 'reflectance' is 1.5; allowed: a number in [0, 1]"), core::Error);
    CHECK_THROWS_WITH_AS(
        io::loadSceneJson(R"({"meshes": [{"file": "box.obj", "role": "target", "reflectance": "high"}]})", file),
        doctest::Contains("'reflectance' must be a number in [0, 1], not a string"), core::Error);
}
