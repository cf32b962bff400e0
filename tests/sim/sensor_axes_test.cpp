// tests/sim/sensor_axes_test.cpp: the footprint's planar test (sim/src/sensor_axes.cpp).
// Each thread keeps the pixel axes of the rows it last traced, so a row's axes serve the
// rows above and below; the returns must not depend on that: any order of the calls and
// any thread give the same slots as rows traced in order. And the planar test's one
// assumption, shown both ways: a wire between the pixel axes is missed by the default
// footprint and caught by --footprint-exact, which traces every sub-ray.
#include <scene_builders.hpp>

#include <sim/generator.hpp>
#include <sim/orbit.hpp>
#include <sim/raycaster.hpp>
#include <sim/sensor.hpp>

#include <generate_options.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <thread>
#include <vector>

namespace {

// Two views of the town (houses' edges give mixed pixels, the ground planar beams) traced
// by a footprint sensor, pixel by pixel through Sensor::trace.
struct Town {
    core::Scene scene = test_support::townScene(120.0, 1.0);
    sim::OrbitOptions orbit;
    sim::SensorOptions options;
    std::vector<glm::dvec3> dirs;  // per pixel, row-major

    Town() {
        orbit.xres = 48;
        orbit.yres = 40;
        orbit.views = 6;
        options.beam_divergence_mrad = 0.5;
        options.returns = sim::ReturnMode::All;
        options.intensity = true;
        for (int y = 0; y < orbit.yres; ++y)
            for (int x = 0; x < orbit.xres; ++x) dirs.push_back(sim::pixelDirection(orbit, double(x), double(y)));
    }
    std::size_t pixels() const { return dirs.size(); }
};

// A call of Sensor::trace: a whole row of a view (0 or 1) by one of the sensors.
struct Call {
    int sensor, view, row;
};

// Per sensor of `options`, the slots of both views (view-major); thread t makes the calls
// calls[t] (thread 0 is the caller, the others new threads).
std::vector<std::vector<core::CloudPoint>> traceCalls(const Town& town, const std::vector<sim::SensorOptions>& options,
                                                      const std::vector<std::vector<Call>>& calls) {
    const sim::RayCaster caster(town.scene);
    const glm::dvec3 centre = sim::defaultCentre(town.scene) - town.scene.origin;
    const core::Pose poses[2] = {sim::sensorPose(town.orbit, centre, 0), sim::sensorPose(town.orbit, centre, 3)};
    std::vector<std::unique_ptr<sim::Sensor>> sensors;
    std::vector<std::vector<core::CloudPoint>> out;
    for (const sim::SensorOptions& o : options) {
        sensors.push_back(std::make_unique<sim::Sensor>(o, town.orbit, town.scene, 7));
        out.emplace_back(2 * town.pixels() * sensors.back()->slotsPerPixel());
    }
    const std::size_t xres = std::size_t(town.orbit.xres);
    const auto run = [&](const std::vector<Call>& list) {
        for (const Call& c : list) {
            const sim::Sensor& sensor = *sensors[std::size_t(c.sensor)];
            const std::size_t slots = sensor.slotsPerPixel(), first = std::size_t(c.row) * xres;
            sensor.trace(caster, sensor.view(c.view, poses[c.view]), first, std::span(town.dirs).subspan(first, xres),
                         std::span(out[std::size_t(c.sensor)])
                             .subspan((std::size_t(c.view) * town.pixels() + first) * slots, xres * slots),
                         true);
        }
    };
    std::vector<std::thread> threads;
    for (std::size_t t = 1; t < calls.size(); ++t) threads.emplace_back(run, std::cref(calls[t]));
    run(calls[0]);
    for (auto& t : threads) t.join();
    return out;
}

// Slots of `a` and `b` that differ (in any field, for slots with a return).
std::size_t differing(const std::vector<core::CloudPoint>& a, const std::vector<core::CloudPoint>& b) {
    REQUIRE(a.size() == b.size());
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const core::CloudPoint &p = a[i], &q = b[i];
        if (p.range_m == sim::kNoReturn || q.range_m == sim::kNoReturn) {
            n += p.range_m != q.range_m;
            continue;
        }
        n += p.position != q.position || p.range_m != q.range_m || p.view != q.view || p.label != q.label ||
             p.intensity != q.intensity || p.return_number != q.return_number || p.returns != q.returns ||
             p.incidence_deg != q.incidence_deg || p.scan_angle_deg != q.scan_angle_deg;
    }
    return n;
}

}  // namespace

TEST_CASE("sensor: the footprint's returns do not depend on the order or threads of the calls") {
    const Town town;
    const int yres = town.orbit.yres;

    // In order: each view's rows top to bottom (the axes of a row are reused).
    std::vector<Call> in_order;
    for (int v = 0; v < 2; ++v)
        for (int y = 0; y < yres; ++y) in_order.push_back({0, v, y});
    const auto reference = traceCalls(town, {town.options}, {in_order})[0];

    // Scattered: rows in a stride-7 permutation, the views alternating call by call, so
    // that no call finds the axes it needs kept. (Runs stay whole rows: Embree's hit of a
    // ray may differ in the last bit with the other rays of its packet, so the sub-rays'
    // packets must start at the same beams.)
    std::vector<Call> scattered;
    for (int j = 0; j < yres; ++j)
        for (int v = 0; v < 2; ++v) scattered.push_back({0, v, (7 * j + 3) % yres});
    // Three threads, rows bottom to top, each thread every third row (its neighbours'
    // axes traced by itself, never kept from the row before).
    std::vector<std::vector<Call>> threaded(3);
    for (int v = 0; v < 2; ++v)
        for (int y = yres - 1; y >= 0; --y) threaded[std::size_t(y % 3)].push_back({0, v, y});

    std::size_t returns = 0, multiple = 0;
    for (const auto& p : reference) {
        returns += p.range_m != sim::kNoReturn;
        multiple += p.range_m != sim::kNoReturn && p.returns > 1;
    }
    CHECK(returns > town.pixels());  // both views see the town
    CHECK(multiple > 0);             // some beams are sub-sampled (mixed pixels)
    CHECK(differing(reference, traceCalls(town, {town.options}, {scattered})[0]) == 0);
    CHECK(differing(reference, traceCalls(town, {town.options}, threaded)[0]) == 0);
}

TEST_CASE("sensor: sensors of every kind traced in turn on one thread give the slots each gives alone") {
    // The per-thread buffers and axes are shared by every sensor a thread traces with.
    const Town town;
    std::vector<sim::SensorOptions> kinds(5);
    kinds[1] = town.options;  // footprint, planar beams not sub-sampled
    kinds[2] = town.options;
    kinds[2].footprint_exact = true;  // every sub-ray
    kinds[3].range_noise_m = 0.05;    // one ray per pixel, not ideal
    kinds[3].intensity = true;
    kinds[4] = town.options;
    kinds[4].beam_divergence_y_mrad = 1.6;  // another footprint, same rows
    kinds[4].footprint_quality = 2;
    // Rows from the middle (few beams to sub-sample: buffers of every size), in turn.
    std::vector<Call> in_turn;
    const int yres = town.orbit.yres;
    for (int j = 0; j < yres; ++j)
        for (int v = 0; v < 2; ++v)
            for (int k = 0; k < int(kinds.size()); ++k) in_turn.push_back({k, v, (yres / 2 + 7 * j) % yres});
    const auto together = traceCalls(town, kinds, {in_turn});
    for (std::size_t k = 0; k < kinds.size(); ++k) {
        std::vector<Call> own;
        for (const Call& c : in_turn)
            if (c.sensor == int(k)) own.push_back({0, c.view, c.row});
        // Alone: on a new thread, whose buffers no other sensor has used.
        const auto alone = traceCalls(town, {kinds[k]}, {{}, own})[0];
        CAPTURE(k);
        CHECK(differing(together[k], alone) == 0);
    }
}

TEST_CASE("sensor: a wire between the pixel axes is missed by the default footprint, caught by --footprint-exact") {
    // One nadir view from 100 m over flat ground; image rows run along world x there.
    sim::GenerateOptions o = test_support::nadirView();
    o.sensor.beam_divergence_mrad = 3.0;  // 0.28 m wide at 95 m; axes 0.17 m apart there
    o.sensor.returns = sim::ReturnMode::All;
    constexpr double kWireZ_m = 5.0, kWireWidth_m = 0.05;

    // Where the axes of rows 31 and 32 cross the wire's height: the wire lies midway.
    const core::Pose pose = sim::sensorPose(o.orbit, glm::dvec3(0.0), 0);
    const auto crossing = [&](int row) {
        const glm::dvec3 d = pose.rotation * sim::pixelDirection(o.orbit, 32.0, double(row));
        return pose.translation + (kWireZ_m - pose.translation.z) / d.z * d;
    };
    const glm::dvec3 a = crossing(31), b = crossing(32);
    REQUIRE(std::abs(a.y - b.y) < 1e-9);  // rows along x: a wire along y lies between them
    REQUIRE(b.x - a.x > 3.0 * kWireWidth_m);
    const float mid = float(0.5 * (a.x + b.x)), half = float(0.5 * kWireWidth_m);

    core::Scene scene;
    scene.source = "wire (in code)";
    scene.meshes.push_back(test_support::quadMesh(1000.0f, 0.0f, core::Role::Ground, "ground"));
    scene.meshes.push_back(test_support::boxMesh({mid - half, -50.0f, float(kWireZ_m) - half},
                                                 {mid + half, 50.0f, float(kWireZ_m) + half}, core::Role::Environment,
                                                 "wire"));
    const auto on_wire = [&](const core::PointCloud& c) {
        return std::count_if(c.points.begin(), c.points.end(),
                             [](const core::CloudPoint& p) { return p.position.z > 4.0f; });
    };
    const core::PointCloud adaptive = sim::generateCloud(scene, o);
    o.sensor.footprint_exact = true;
    const core::PointCloud exact = sim::generateCloud(scene, o);
    // The default: only the beams at both ends of the two rows (their neighbourhood leaves
    // the image, so they are always sub-sampled); exact: every beam of both rows.
    CHECK(on_wire(adaptive) == 4);
    CHECK(on_wire(exact) >= 2 * 64);
}
