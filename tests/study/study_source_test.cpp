// tests/study/study_source_test.cpp: the generator's options of a plan's scene trials
// (study/study_source.hpp): the plan's generate block, its ground filter included, reaches
// the cloud a scene trial shows; and the terrain a cloud trial in above-ground colours
// gets from the starter, held only while the trial runs; a trial over a survey in feet
// draws its candidates' sizes in feet.
#include <study/plan.hpp>
#include <study/study_source.hpp>

#include <core/error.hpp>
#include <sim/generator.hpp>
#include <viewer/cloud_feed.hpp>

#include <scene_builders.hpp>
#include <test_files.hpp>
#include <test_paths.hpp>

#include <doctest/doctest.h>

#include <memory>
#include <optional>
#include <vector>

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

namespace {
// A job that counts how many are alive: destroying one is the thread stopped and joined.
struct CountedJob final : study::TerrainJob {
    explicit CountedJob(int& live) : live_(live) { ++live_; }
    ~CountedJob() override { --live_; }
    int& live_;
};

constexpr const char* kTwoPointPcd =
    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n0 0 0\n1 1 1\n";
}  // namespace

TEST_CASE("a cloud trial in above-ground colours gets its terrain from the starter, stopped when the trial ends") {
    using viewer::ColourMode;
    test_support::TempDir dir("study_source_terrain");
    const std::filesystem::path cloud = dir.write("c.pcd", kTwoPointPcd);
    study::Plan plan;
    // Conditions' colours: above-ground, then as they stand (still above-ground), height,
    // then as they stand (height).
    for (const std::optional<ColourMode> colour : {std::optional(ColourMode::AboveGround), std::optional<ColourMode>(),
                                                   std::optional(ColourMode::HeightJet), std::optional<ColourMode>()}) {
        study::PlanTrial t;
        t.cloud = cloud;
        t.colour = colour;
        plan.trials.push_back(t);
    }
    int live = 0;
    std::vector<std::filesystem::path> asked;
    const study::TerrainStarter starter = [&](const std::filesystem::path& file) {
        asked.push_back(file);
        study::CloudTerrain t;
        t.feed = std::make_shared<viewer::TerrainFeed>();
        t.job = std::make_unique<CountedJob>(live);
        return t;
    };
    viewer::CloudFeed feeds[4];  // outlive the source, as the viewer's do
    study::StudySource source(plan, {0, 1, 2, 3}, 0, false);
    source.setTerrain(starter, ColourMode::File);
    CHECK(source.startColour(0) == ColourMode::AboveGround);
    CHECK(source.startColour(1) == ColourMode::AboveGround);
    CHECK(source.startColour(2) == ColourMode::HeightJet);
    CHECK(source.startColour(3) == ColourMode::HeightJet);

    const viewer::TrialSetup first = source.begin(0, feeds[0]);
    CHECK(first.terrain != nullptr);
    CHECK(live == 1);
    CHECK(asked == std::vector<std::filesystem::path>{cloud});
    source.end(0);
    CHECK(live == 0);  // no thread outlives its trial
    CHECK(source.begin(1, feeds[1]).terrain != nullptr);
    CHECK(live == 1);
    // The next begin ends a trial the viewer did not end.
    CHECK(source.begin(2, feeds[2]).terrain == nullptr);
    CHECK(live == 0);
    CHECK(source.begin(3, feeds[3]).terrain == nullptr);
    source.end(3);
    CHECK(asked.size() == 2);

    // Where no condition sets colours, the run's count: --colour above-ground.
    study::Plan plain = plan;
    for (study::PlanTrial& t : plain.trials) t.colour.reset();
    study::StudySource run_colour(plain, {0, 1, 2, 3}, 0, false);
    run_colour.setTerrain(starter, ColourMode::AboveGround);
    CHECK(run_colour.startColour(2) == ColourMode::AboveGround);
    viewer::CloudFeed plain_feed;
    CHECK(run_colour.begin(2, plain_feed).terrain != nullptr);
    run_colour.end(2);
    CHECK(live == 0);
    // Without a starter, no trial has a terrain.
    study::StudySource none(plan, {0, 1, 2, 3}, 0, false);
    viewer::CloudFeed none_feed;
    CHECK(none.begin(0, none_feed).terrain == nullptr);
}

TEST_CASE("a trial over a survey in US survey feet draws its candidates' sizes in feet, a file in metres is refused") {
    constexpr double kFoot_m = 1200.0 / 3937.0;
    test_support::TempDir dir("study_source_feet");
    const std::filesystem::path survey = std::filesystem::path(test_support::realDataDir()) / "4_6_crop.las";
    const std::string box =
        R"({"id": "c1", "centre": [1639700, 1454600, 7100], "size_m": [7, 3.5, 2.5], "score": 0.9})";
    const std::filesystem::path in_feet = dir.write(
        "feet.json", R"({"candidates": [)" + box +
                         R"(], "units": {"horizontal_m": 0.3048006096012192, "vertical_m": 0.3048006096012192}})");
    const std::filesystem::path in_metres = dir.write("metres.json", R"({"candidates": [)" + box + "]}");
    study::Plan plan;
    study::PlanTrial t;
    t.cloud = survey;
    t.candidates = in_feet;
    plan.trials.push_back(t);
    {
        const study::StudySource source(plan, {0});
        const core::Candidate& c = source.candidatesOf(0).at(0);
        CHECK(c.centre_world == glm::dvec3(1639700, 1454600, 7100));
        CHECK(c.size_m.x == doctest::Approx(7.0 / kFoot_m).epsilon(1e-6));
        CHECK(c.size_m.z == doctest::Approx(2.5 / kFoot_m).epsilon(1e-6));
    }
    plan.trials[0].candidates = in_metres;
    CHECK_THROWS_WITH_AS(study::StudySource(plan, {0}),
                         doctest::Contains("metres.json: centres in metres; the cloud is in US survey feet"),
                         core::Error);
}
