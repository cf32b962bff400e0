// tests/stress/georef_test.cpp: "a scene georeferenced 10^6 m and 10^7 m from the
// origin gives the same cloud as the same scene at the origin, within 1 mm per point; the
// metric behaves the same there". World coordinates = cloud origin (double) + local (float).
#include <generate_options.hpp>
#include <scene_builders.hpp>

#include <metric/clouds.hpp>
#include <metric/visibility.hpp>
#include <sim/generator.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

namespace {

struct Compared {
    double max_error_m = 0.0;
    std::size_t label_mismatches = 0, view_mismatches = 0;
};

/// Point-by-point world distance between `far` and `near` moved by `offset`.
Compared compareWorld(const core::PointCloud& near, const core::PointCloud& far, glm::dvec3 offset) {
    Compared c;
    for (std::size_t i = 0; i < near.points.size(); ++i) {
        const glm::dvec3 a = near.origin + glm::dvec3(near.points[i].position) + offset;
        const glm::dvec3 b = far.origin + glm::dvec3(far.points[i].position);
        c.max_error_m = std::max(c.max_error_m, glm::length(a - b));
        c.label_mismatches += near.points[i].label != far.points[i].label;
        c.view_mismatches += near.points[i].view != far.points[i].view;
    }
    return c;
}

}  // namespace

TEST_CASE("georeferenced 1e6 m and 1e7 m away: the same cloud within 1 mm per point") {
    const sim::GenerateOptions options = test_support::smallOrbit();
    const core::Scene home = test_support::basicScene({0, 0, 0}, {0, 0, 0});
    sim::GenerateStats home_stats;
    const core::PointCloud reference = sim::generateCloud(home, options, &home_stats);
    REQUIRE(reference.points.size() > 20000);  // 27,648 rays, most on the 200 m ground
    for (const double d : {1e6, 1e7}) {
        const glm::dvec3 offset(d, -0.5 * d, 250.0);
        // (a) the local origin on the scene (what the scene file's default does) and (b) an
        // origin 37 m off in every axis, so the local floats differ from the reference's.
        for (const glm::dvec3 origin_shift : {glm::dvec3(0.0), glm::dvec3(37.3, -41.7, 5.9)}) {
            const core::Scene far = test_support::basicScene(offset, offset + origin_shift);
            CAPTURE(d);
            CAPTURE(origin_shift.x);
            sim::GenerateStats far_stats;
            const core::PointCloud cloud = sim::generateCloud(far, options, &far_stats);
            CHECK(cloud.origin == far.origin);
            CHECK(std::abs(far_stats.centre.x - home_stats.centre.x - offset.x) < 1e-6);
            CHECK(std::abs(far_stats.centre.y - home_stats.centre.y - offset.y) < 1e-6);
            CHECK(std::abs(far_stats.centre.z - home_stats.centre.z - offset.z) < 1e-6);
            REQUIRE(cloud.points.size() == reference.points.size());
            const Compared c = compareWorld(reference, cloud, offset);
            MESSAGE("offset " << d << " m, origin shift " << origin_shift.x << ": max world error "
                              << c.max_error_m * 1000.0 << " mm over " << cloud.points.size() << " points");
            CHECK(c.max_error_m <= 1e-3);
            CHECK(c.label_mismatches == 0);
            CHECK(c.view_mismatches == 0);
            CHECK(far_stats.ground_found == home_stats.ground_found);
            if (origin_shift == glm::dvec3(0.0)) {
                // Same local floats as the reference: the local clouds are bit-identical.
                bool identical = true;
                for (std::size_t i = 0; i < cloud.points.size() && identical; ++i)
                    identical =
                        std::memcmp(&cloud.points[i].position, &reference.points[i].position, sizeof(glm::vec3)) == 0 &&
                        cloud.points[i].rgb == reference.points[i].rgb;
                CHECK(identical);
            }
        }
    }
}

TEST_CASE("georeferenced 1e7 m away: the same visibility metric, view by view") {
    sim::GenerateOptions options = test_support::smallOrbit();
    metric::MetricOptions mo;
    mo.orbit.radius_m = 25.0;
    mo.orbit.altitude_m = 12.0;
    mo.orbit.views = 8;
    mo.width = 256;
    mo.height = 256;
    const core::Scene home = test_support::basicScene({0, 0, 0}, {0, 0, 0});
    metric::Evaluator home_eval(metric::generateClouds(home, options), &home);
    const metric::MetricResult a = home_eval.run(mo);
    REQUIRE(a.views_used > 0);
    REQUIRE(a.has_exact);
    for (const double d : {1e6, 1e7}) {
        const glm::dvec3 offset(d, -0.5 * d, 250.0);
        const core::Scene far = test_support::basicScene(offset, offset + glm::dvec3(37.3, -41.7, 5.9));
        metric::Evaluator far_eval(metric::generateClouds(far, options), &far);
        const metric::MetricResult b = far_eval.run(mo);
        CAPTURE(d);
        REQUIRE(b.views.size() == a.views.size());
        CHECK(b.views_used == a.views_used);
        // The camera in world coordinates is the same.
        const glm::dvec3 eye_a = a.origin + a.views[0].pose.eye + offset, eye_b = b.origin + b.views[0].pose.eye;
        CHECK(glm::length(eye_a - eye_b) < 1e-3);
        for (std::size_t k = 0; k < a.views.size(); ++k) {
            const metric::ViewResult &va = a.views[k], &vb = b.views[k];
            CAPTURE(k);
            // Splats of points that agree within a millimetre land on the same pixels, up
            // to a pixel-edge tie: allow 0.5 % of |I1| (a few pixels at 256 px).
            const double tol = 0.005 * double(std::max<std::int64_t>(va.i1, 1)) + 2.0;
            CHECK(std::abs(double(va.i1 - vb.i1)) <= tol);
            CHECK(std::abs(double(va.i4 - vb.i4)) <= tol);
            CHECK(va.exact_target_px == vb.exact_target_px);
            CHECK(va.exact_visible_px == vb.exact_visible_px);
        }
        CHECK(std::abs(b.metric_mean - a.metric_mean) < 0.01);
        CHECK(b.exact_mean == doctest::Approx(a.exact_mean).epsilon(1e-12));
        MESSAGE("offset " << d << " m: metric " << b.metric_mean << " vs " << a.metric_mean << ", exact "
                          << b.exact_mean << " vs " << a.exact_mean);
    }
}
