// tests/sim/sensor_footprint_test.cpp: the beam footprint and its returns. The sub-ray
// pattern is HELIOS++'s (1 + 6 + 12 = 19 rays at q = 3); a beam straddling a step edge
// gives two returns, one on each surface, at their own ranges; the modes keep the
// returns they name.
#include <scene_builders.hpp>

#include <sim/generator.hpp>
#include <sim/orbit.hpp>
#include <sim/sensor.hpp>

#include <generate_options.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

namespace {

constexpr float kStep_m = 5.0f;

// Ground at z = 0 and, over y > 0, a platform whose top is kStep_m higher: one straight
// step edge along the x axis.
core::Scene stepScene() {
    core::Scene s;
    s.source = "step (in code)";
    s.meshes.push_back(test_support::quadMesh(1000.0f, 0.0f, core::Role::Ground, "ground"));
    s.meshes.push_back(test_support::boxMesh({-1000.0f, 0.0f, -1.0f}, {1000.0f, 1000.0f, kStep_m},
                                             core::Role::Environment, "platform"));
    return s;
}

// One nadir view from 100 m over the edge (alpha 0, CO 0: the drone sits at y = 0, so the
// platform's wall is seen edge-on and only its top and the ground can be hit).
sim::GenerateOptions nadirOptions() {
    sim::GenerateOptions o = test_support::nadirView();
    o.sensor.beam_divergence_mrad = 3.0;  // 0.3 m wide at 100 m, pixels 0.18 m apart
    o.sensor.footprint_quality = 3;
    o.sensor.returns = sim::ReturnMode::All;
    o.sensor.intensity_reference_range_m = 30.0;  // intensities well below full scale at 100 m
    return o;
}

}  // namespace

TEST_CASE("sensor: the footprint is sampled as HELIOS++ does, circular or elliptical") {
    sim::SensorOptions o;
    CHECK(sim::footprintPattern(o).size() == 1);  // no divergence: the axis alone
    o.beam_divergence_mrad = 0.5;
    for (auto [q, n] : {std::pair{1, 1}, {2, 7}, {3, 19}, {4, 37}}) {
        o.footprint_quality = q;
        const auto p = sim::footprintPattern(o);
        CHECK(p.size() == std::size_t(n));
        double w = 0.0;
        for (const auto& s : p) w += s.weight;
        CHECK(w == doctest::Approx(1.0));
    }
    o.footprint_quality = 3;
    o.beam_divergence_y_mrad = 1.6;  // elliptical 0.5 x 1.6 mrad
    double max_x = 0.0, max_y = 0.0;
    for (const auto& s : sim::footprintPattern(o)) {
        max_x = std::max(max_x, std::abs(s.dx_rad));
        max_y = std::max(max_y, std::abs(s.dy_rad));
    }
    CHECK(max_x == doctest::Approx(0.25e-3));
    CHECK(max_y == doctest::Approx(0.8e-3));
    // Sub-ray directions: the axis unchanged, the others at their angle from it.
    const glm::dvec3 axis = glm::normalize(glm::dvec3(0.1, -0.05, 1.0));
    CHECK(sim::subRayDirection(axis, sim::SubRay{}) == axis);
    const glm::dvec3 d = sim::subRayDirection(axis, sim::SubRay{1e-3, 0.0, 1.0});
    CHECK(std::acos(glm::dot(d, axis)) == doctest::Approx(1e-3).epsilon(1e-6));
}

TEST_CASE("sensor: a beam across a step edge gives two returns, on the two surfaces at their ranges") {
    const core::Scene scene = stepScene();
    sim::GenerateOptions o = nadirOptions();
    sim::Generator g(scene, o);
    const glm::dvec3 origin = sim::sensorPose(o.orbit, glm::dvec3(0.0), 0).translation;
    const core::PointCloud cloud = g.run();
    CHECK(cloud.fields.returns);
    CHECK(cloud.fields.intensity);
    std::size_t mixed = 0, single = 0, bad = 0;
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const core::CloudPoint& p = cloud.points[i];
        // Every return lies on its own sub-ray at its range, on one of the two surfaces.
        const double range = glm::length(glm::dvec3(p.position) - origin);
        bad += std::abs(range - double(p.range_m)) > 2e-3;
        const bool top = std::abs(p.position.z - kStep_m) < 1e-3f, ground = std::abs(p.position.z) < 1e-3f;
        bad += !(top || ground);
        if (p.returns == 1) {
            ++single;
            continue;
        }
        if (p.return_number != 1) continue;
        ++mixed;
        REQUIRE(i + 1 < cloud.points.size());
        const core::CloudPoint& q = cloud.points[i + 1];
        // The first return on the platform's top (y >= 0), the second on the ground
        // (y <= 0), kStep_m farther: each placed on the sub-ray hit that made it.
        CHECK(p.returns == 2);
        CHECK(q.return_number == 2);
        CHECK(q.returns == 2);
        CHECK(top);
        CHECK(std::abs(q.position.z) < 1e-3f);
        CHECK(p.position.y >= -1e-3f);
        CHECK(q.position.y <= 1e-3f);
        CHECK(double(q.range_m - p.range_m) == doctest::Approx(kStep_m).epsilon(2e-3));
        // Both within the beam's footprint of the edge (0.15 m radius at 100 m).
        CHECK(std::abs(p.position.y) < 0.16f);
        CHECK(std::abs(q.position.y) < 0.16f);
    }
    CHECK(bad == 0);
    // The edge crosses the 64-pixel image: at least a row of mixed pixels, at most a few.
    CHECK(mixed >= 64);
    CHECK(mixed <= 4 * 64);
    CHECK(single + mixed == 64 * 64);

    // The modes: first keeps the platform, last the ground, one return per pulse.
    o.sensor.returns = sim::ReturnMode::First;
    const core::PointCloud first = sim::generateCloud(scene, o);
    o.sensor.returns = sim::ReturnMode::Last;
    const core::PointCloud last = sim::generateCloud(scene, o);
    REQUIRE(first.points.size() == 64 * 64);
    REQUIRE(last.points.size() == 64 * 64);
    std::size_t first_top = 0, last_ground = 0;
    for (std::size_t i = 0; i < first.points.size(); ++i) {
        const auto& f = first.points[i];
        const auto& l = last.points[i];
        if (f.returns == 2) {
            first_top += std::abs(f.position.z - kStep_m) < 1e-3f && f.return_number == 1;
            last_ground += std::abs(l.position.z) < 1e-3f && l.return_number == 2;
        }
    }
    CHECK(first_top == mixed);
    CHECK(last_ground == mixed);
    // Echoes closer than the range resolution merge: a 5 m step inside a 10 m resolution
    // gives one return per pulse.
    o.sensor.returns = sim::ReturnMode::All;
    o.sensor.range_resolution_m = 10.0;
    const core::PointCloud merged = sim::generateCloud(scene, o);
    CHECK(merged.points.size() == 64 * 64);
}

TEST_CASE("sensor: the strongest return is the surface that fills more of the footprint") {
    const core::Scene scene = stepScene();
    sim::GenerateOptions o = nadirOptions();
    o.sensor.returns = sim::ReturnMode::All;
    const core::PointCloud all = sim::generateCloud(scene, o);
    o.sensor.returns = sim::ReturnMode::Strongest;
    const core::PointCloud strongest = sim::generateCloud(scene, o);
    REQUIRE(strongest.points.size() == 64 * 64);
    // Walk the pixels of `all` (returns of one pixel are consecutive) alongside `strongest`.
    std::size_t k = 0, checked = 0, wrong = 0;
    for (const auto& s : strongest.points) {
        const auto& a = all.points[k];
        if (a.returns == 2) {
            const auto& b = all.points[k + 1];
            const auto& expect = a.intensity >= b.intensity ? a : b;
            wrong += s.position != expect.position;
            ++checked;
        }
        k += a.returns;
    }
    CHECK(k == all.points.size());
    CHECK(checked > 0);
    CHECK(wrong == 0);
}

TEST_CASE("sensor: beams on one plane are not sub-sampled, and give the returns of the exact footprint") {
    const core::Scene scene = test_support::townScene(120.0, 1.0);
    sim::GenerateOptions o;
    o.orbit.xres = 48;
    o.orbit.yres = 40;
    o.orbit.views = 6;
    o.white = true;
    o.sensor.beam_divergence_mrad = 0.5;
    o.sensor.returns = sim::ReturnMode::All;
    sim::GenerateStats st_adaptive, st_exact;
    const core::PointCloud adaptive = sim::generateCloud(scene, o, &st_adaptive);
    o.sensor.footprint_exact = true;
    const core::PointCloud exact = sim::generateCloud(scene, o, &st_exact);
    REQUIRE(adaptive.points.size() == exact.points.size());
    std::size_t moved = 0, dimmer = 0;
    for (std::size_t i = 0; i < exact.points.size(); ++i) {
        const auto& a = adaptive.points[i];
        const auto& e = exact.points[i];
        moved += a.position != e.position || a.return_number != e.return_number || a.returns != e.returns;
        dimmer += std::abs(double(a.intensity) - double(e.intensity)) > 0.01 * double(e.intensity) + 1.0;
    }
    CHECK(moved == 0);
    CHECK(dimmer == 0);
    // The same run, for a fraction of the sub-rays (the houses' and target's edges only).
    CHECK(st_exact.sub_rays_traced == 19 * st_exact.rays_traced);
}
