// tests/stress/threads_test.cpp: "results bit-identical with 1 thread and with N
// threads" for the generator (RANSAC seeds per view, fusion in view order) on a bundled
// scene, with packets and single rays; and the metric evaluated twice in one process.
#include <generate_options.hpp>
#include <scene_builders.hpp>
#include <test_paths.hpp>

#include <io/scene_file.hpp>
#include <metric/clouds.hpp>
#include <metric/visibility.hpp>
#include <sim/generator.hpp>

#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>

namespace {

bool identical(const core::PointCloud& a, const core::PointCloud& b) {
    if (a.points.size() != b.points.size() || a.origin != b.origin) return false;
    for (std::size_t i = 0; i < a.points.size(); ++i) {
        const auto &p = a.points[i], &q = b.points[i];
        if (std::memcmp(&p.position, &q.position, sizeof p.position) != 0 || p.rgb != q.rgb ||
            std::memcmp(&p.range_m, &q.range_m, sizeof p.range_m) != 0 || p.view != q.view || p.label != q.label)
            return false;
    }
    return true;
}

}  // namespace

TEST_CASE("generator: bit-identical clouds with 1, 2, 5 and 16 threads on the hilly scene") {
    const std::filesystem::path hilly = std::filesystem::path(test_support::assetsDir()) / "hilly" / "scene.json";
    const core::Scene scene = io::loadScene(hilly);
    sim::GenerateOptions o;
    o.orbit.xres = o.orbit.yres = 64;
    o.orbit.views = 24;
    o.threads = 1;
    sim::GenerateStats st1;
    const core::PointCloud one = sim::generateCloud(scene, o, &st1);
    REQUIRE(one.points.size() > 90000);
    REQUIRE(st1.ground_found > 0);
    for (const int threads : {2, 5, 16}) {
        for (const bool packets : {true, false}) {
            o.threads = threads;
            o.packet_rays = packets;
            sim::GenerateStats st;
            const core::PointCloud many = sim::generateCloud(scene, o, &st);
            CAPTURE(threads);
            CAPTURE(packets);
            CHECK(st.threads == threads);
            CHECK(identical(one, many));
            CHECK(st.ground_found == st1.ground_found);
            CHECK(st.planes_accepted == st1.planes_accepted);
        }
    }
}

TEST_CASE("metric: the same evaluation twice gives bit-identical counts") {
    // metric::Evaluator has no thread option; its exact reference may use several threads.
    // Two runs (and a second evaluator) must agree to the pixel.
    const core::Scene scene = test_support::basicScene({0, 0, 0}, {0, 0, 0});
    const metric::MetricClouds clouds = metric::generateClouds(scene, test_support::smallOrbit());
    metric::MetricOptions mo;
    mo.orbit.radius_m = 25.0;
    mo.orbit.altitude_m = 12.0;
    mo.orbit.views = 6;
    mo.width = mo.height = 192;
    metric::Evaluator a(clouds, &scene);
    const metric::MetricResult r1 = a.run(mo), r2 = a.run(mo);
    metric::Evaluator b(clouds, &scene);
    const metric::MetricResult r3 = b.run(mo);
    REQUIRE(r1.views.size() == 6);
    for (std::size_t k = 0; k < r1.views.size(); ++k) {
        for (const metric::MetricResult* r : {&r2, &r3}) {
            const metric::ViewResult &x = r1.views[k], &y = r->views[k];
            CHECK(x.i1 == y.i1);
            CHECK(x.i2 == y.i2);
            CHECK(x.i3 == y.i3);
            CHECK(x.i4 == y.i4);
            CHECK(x.exact_target_px == y.exact_target_px);
            CHECK(x.exact_visible_px == y.exact_visible_px);
        }
    }
}
