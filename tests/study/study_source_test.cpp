// tests/study/study_source_test.cpp: the generator's options of a plan's scene trials
// (study/study_source.hpp): the plan's generate block, its ground filter included, reaches
// the cloud a scene trial shows.
#include <study/plan.hpp>
#include <study/study_source.hpp>

#include <core/error.hpp>
#include <sim/generator.hpp>

#include <scene_builders.hpp>

#include <doctest/doctest.h>

namespace {
study::Plan sceneTrialPlan(const std::string& generate) {
    return study::parsePlan(R"({"trials": [{"scene": "s.json"}], "generate": )" + generate + "}", "p.json", "/plans");
}
}  // namespace

TEST_CASE("a scene trial's cloud is generated with the plan's resolution, views and ground filter") {
    const sim::GenerateOptions plain = study::sceneGenerateOptions(sceneTrialPlan("{}"));
    CHECK(plain.ground.method == sim::GroundMethod::Ransac);  // the generator's default
    CHECK_FALSE(plain.white);
    CHECK(plain.orbit.xres == 128);

    const sim::GenerateOptions smrf =
        study::sceneGenerateOptions(sceneTrialPlan(R"({"xres": 32, "yres": 24, "views": 6, "ground": "smrf"})"));
    CHECK(smrf.orbit.xres == 32);
    CHECK(smrf.orbit.yres == 24);
    CHECK(smrf.orbit.views == 6);
    CHECK(smrf.ground.method == sim::GroundMethod::Smrf);
    CHECK_FALSE(smrf.white);
    CHECK(study::sceneGenerateOptions(sceneTrialPlan(R"({"ground": "csf"})")).ground.method == sim::GroundMethod::Csf);
    CHECK(study::sceneGenerateOptions(sceneTrialPlan(R"({"ground": "white"})")).white);

    // The cloud itself: SMRF whitens it and gives each point its height above the fitted
    // terrain (what the above-ground colours need); white runs no ground filter.
    const core::Scene scene = test_support::townScene(40.0, 1.0);
    sim::GenerateStats stats;
    const core::PointCloud cloud = sim::generateCloud(scene, smrf, &stats);
    REQUIRE_FALSE(cloud.points.empty());
    CHECK(stats.ground_method == sim::GroundMethod::Smrf);
    CHECK(stats.ground_found > 0);
    CHECK(cloud.fields.height_above_ground);
    sim::GenerateOptions white =
        study::sceneGenerateOptions(sceneTrialPlan(R"({"xres": 32, "yres": 24, "views": 6, "ground": "white"})"));
    sim::GenerateStats white_stats;
    const core::PointCloud white_cloud = sim::generateCloud(scene, white, &white_stats);
    CHECK(white_stats.ground_found == 0);
    CHECK_FALSE(white_cloud.fields.height_above_ground);
}
