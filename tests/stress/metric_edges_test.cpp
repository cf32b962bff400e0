// tests/stress/metric_edges_test.cpp: the metric with a fully hidden target and
// with a target out of every view, on a scene 10^7 m from the world origin.
#include <scene_builders.hpp>

#include <metric/clouds.hpp>
#include <metric/report.hpp>
#include <metric/visibility.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <string>

namespace {

/// A 4 m cube target inside a closed 12 m hut (walls and roof), 10^7 m from the origin.
core::Scene hut(bool roof) {
    core::Scene s;
    s.source = "hut (in code)";
    s.origin = glm::dvec3(1e7, 1e7, 310.0);
    s.meshes.push_back(test_support::boxMesh({-2, -2, 0}, {2, 2, 4}, core::Role::Target, "cube"));
    test_support::addEnclosure(s, 6.0f, 0.2f, -1.0f, 5.0f, roof);
    s.meshes.push_back(test_support::quadMesh(200.0f, 0.0f, core::Role::Ground, "ground"));
    return s;
}

sim::GenerateOptions droneOptions() {
    sim::GenerateOptions g;
    g.orbit.altitude_m = 60.0;
    g.orbit.fov_deg = 25.0;
    g.orbit.xres = g.orbit.yres = 64;
    g.orbit.views = 16;
    return g;
}

metric::MetricOptions metricOptions() {
    metric::MetricOptions o;
    o.orbit.radius_m = 30.0;
    o.orbit.altitude_m = 15.0;
    o.orbit.views = 6;
    o.width = o.height = 192;
    return o;
}

}  // namespace

TEST_CASE("a target hidden from every side, 1e7 m away: metric, visible and exact are 0") {
    // The drone's clouds come from the open hut (P1 sees the target); the metric is
    // evaluated against the closed hut's environment: nothing of the target shows.
    const core::Scene open_hut = hut(false), closed_hut = hut(true);
    const metric::MetricClouds open_clouds = metric::generateClouds(open_hut, droneOptions());
    const metric::MetricClouds closed_clouds = metric::generateClouds(closed_hut, droneOptions());
    REQUIRE(!closed_clouds.p1.points.empty());
    metric::MetricClouds clouds;
    clouds.p1 = open_clouds.p1;
    clouds.p2 = closed_clouds.p2;
    clouds.p3 = closed_clouds.p3;
    metric::Evaluator evaluator(clouds, &closed_hut);
    const metric::MetricResult r = evaluator.run(metricOptions());
    REQUIRE(r.views_used == 6);
    for (const metric::ViewResult& v : r.views) {
        CAPTURE(v.view);
        CHECK(v.i1 > 0);
        CHECK(v.visible_px == 0);
        CHECK(v.visible == 0.0);
        CHECK(v.exact_target_px > 0);
        CHECK(v.exact_visible_px == 0);
        CHECK(v.exact == 0.0);
        CHECK(v.metric == double(v.i4) / double(v.i1));  // |I4| / |I1|, i1 > 0 above
    }
    CHECK(r.visible_mean == 0.0);
    CHECK(r.exact_mean == 0.0);
    // The open hut from the same orbit, for contrast: the target shows over the walls.
    metric::Evaluator open_eval(open_clouds, &open_hut);
    const metric::MetricResult o = open_eval.run(metricOptions());
    CHECK(o.exact_mean > 0.1);
    CHECK(o.visible_mean > 0.1);
}

TEST_CASE("a target out of every view, 1e7 m away: no view used, NaN means, null in the JSON") {
    const core::Scene scene = hut(false);
    const metric::MetricClouds clouds = metric::generateClouds(scene, droneOptions());
    metric::Evaluator evaluator(clouds, &scene);
    for (const bool skip : {true, false}) {
        metric::MetricOptions o = metricOptions();
        o.skip = skip;
        // Orbit 5 km east of the target, looking at a point 5 km east: the target is far
        // outside the 30 deg frustum of every view.
        o.look_at_world = scene.origin + glm::dvec3(5000.0, 0.0, 2.0);
        const metric::MetricResult r = evaluator.run(o);
        CAPTURE(skip);
        REQUIRE(r.views.size() == 6);
        CHECK(r.views_used == 0);
        for (const metric::ViewResult& v : r.views) {
            CHECK(v.i1 == 0);
            CHECK_FALSE(v.used);
            CHECK(std::isnan(v.metric));
            CHECK(v.frustum_skipped == skip);
            CHECK(v.exact_target_px == 0);
        }
        CHECK(std::isnan(r.metric_mean));
        CHECK(std::isnan(r.exact_mean));
        const std::string json = metric::summaryJson(r);
        CHECK(json.find("\"metric_mean\": null") != std::string::npos);
        CHECK(json.find("nan") == std::string::npos);
        CHECK(json.find("NaN") == std::string::npos);
    }
}
