// tests/study/plan_test.cpp: PLAN.json parsing with known answers and refused fields.
#include <study/plan.hpp>

#include <core/error.hpp>

#include <test_files.hpp>

#include <doctest/doctest.h>

#include <algorithm>

using study::parsePlan;

TEST_CASE("a plan's trials, paths relative to the plan, defaults") {
    const study::Plan plan = parsePlan(R"({"trials": [
        {"cloud": "a.pcd", "time_limit_s": 30},
        {"scene": "/abs/s.json", "candidates": "c/c.json", "name": "village"}],
        "shuffle_seed": 7, "hit_radius_m": 2.5,
        "orbit": {"radius_m": 80, "height_m": 50, "period_s": 90},
        "generate": {"xres": 64, "yres": 32, "views": 10}})",
                                       "p.json", "/plans");
    REQUIRE(plan.trials.size() == 2);
    CHECK(plan.trials[0].cloud == std::filesystem::path("/plans/a.pcd"));
    CHECK(plan.trials[0].scene.empty());
    CHECK(plan.trials[0].time_limit_s == 30.0);
    CHECK(plan.trials[0].name == "a.pcd");
    CHECK(plan.trials[0].source == "a.pcd");
    CHECK(plan.trials[1].scene == std::filesystem::path("/abs/s.json"));
    CHECK(plan.trials[1].candidates == std::filesystem::path("/plans/c/c.json"));
    CHECK(plan.trials[1].time_limit_s == 120.0);  // the default
    CHECK(plan.trials[1].name == "village");
    CHECK(*plan.shuffle_seed == 7u);
    CHECK(plan.hit_radius_m == 2.5);
    CHECK(plan.orbit_radius_m == 80.0);
    CHECK(plan.orbit_height_m == 50.0);
    CHECK(plan.orbit_period_s == 90.0);
    CHECK(plan.xres == 64);
    CHECK(plan.yres == 32);
    CHECK(plan.views == 10);
    CHECK(plan.ground == "ransac");  // the generator's default
    const study::Plan bare = parsePlan(R"({"trials": [{"cloud": "a.pcd"}]})", "p.json", "/plans");
    CHECK_FALSE(bare.shuffle_seed);
    CHECK(bare.hit_radius_m == 1.0);
    CHECK(bare.orbit_radius_m == 60.0);
}

TEST_CASE("a plan's generate.ground chooses the scene trials' ground filter as the generator's --ground does") {
    for (const char* ground : {"ransac", "smrf", "csf", "white"}) {
        const study::Plan plan =
            parsePlan(std::string(R"({"trials": [{"scene": "s.json"}], "generate": {"ground": ")") + ground + R"("}})",
                      "p.json", "/plans");
        CHECK(plan.ground == ground);
    }
    CHECK_THROWS_WITH_AS(parsePlan(R"({"trials": [{"scene": "s"}], "generate": {"ground": "SMRF"}})", "p.json", "/"),
                         "study: p.json: generate.ground 'SMRF' is not one of ransac, smrf, csf, white", core::Error);
    CHECK_THROWS_WITH_AS(parsePlan(R"({"trials": [{"scene": "s"}], "generate": {"ground": 1}})", "p.json", "/"),
                         doctest::Contains("generate.ground must be a non-empty string"), core::Error);
}

TEST_CASE("a plan's refused fields name the field and what is allowed") {
    auto fails = [](const std::string& text, const std::string& part) {
        CAPTURE(text);
        CHECK_THROWS_WITH_AS(parsePlan(text, "p.json", "/"), doctest::Contains(part.c_str()), core::Error);
    };
    fails(R"({"trials": []})", "study: p.json: 'trials' must be a non-empty array");
    fails(R"({"trials": [{"cloud": "a", "scene": "b"}]})", "trials[0]: give exactly one of 'cloud' and 'scene'");
    fails(R"({"trials": [{}]})", "give exactly one of");
    fails(R"({"trials": [{"cloud": "a", "time_limit_s": -1}]})", "trials[0].time_limit_s -1 is not in [0, 86400]");
    fails(R"({"trials": [{"cloud": "a", "time_limt_s": 5}]})", "trials[0]: unknown key 'time_limt_s'; allowed: cloud,");
    fails(R"({"trials": [{"cloud": 3}]})", "trials[0].cloud must be a non-empty string");
    fails(R"({"trials": [{"cloud": "a"}], "shuffle_seed": -1})", "shuffle_seed must be a whole number >= 0");
    fails(R"({"trials": [{"cloud": "a"}], "shuffle_seed": 1.5})", "shuffle_seed must be a whole number >= 0");
    fails(R"({"trials": [{"cloud": "a"}], "orbit": {"radius_m": 0}})", "orbit.radius_m 0 is not in");
    fails(R"({"trials": [{"cloud": "a"}], "generate": {"xres": 2.5}})", "generate.xres 2.5 is not a whole number");
    fails(R"({"trials": [{"cloud": "a"}], "trials": [{"cloud": "b"}]})", "duplicate key 'trials'");
    fails(R"([1])", "the plan must be an object");
    // Top-level keys follow the plan's name after ": ", never glued to it with a dot.
    fails(R"({"trials": [{"cloud": "a"}], "hit_radius_m": 0})", "study: p.json: hit_radius_m 0 is not in");
    fails(R"({"trials": [{"cloud": "a"}], "orbit": {"radius_m": 0}})", "study: p.json: orbit.radius_m 0 is not in");
    fails(R"({"trials": [{"cloud": "a"}], "generate": {"xres": 2.5}})", "study: p.json: generate.xres 2.5");
    fails(R"({"trials": [{"cloud": "a"}], "shuffle_seed": -1})", "study: p.json: shuffle_seed must be");
    // A NUL would make the system open the path cut short, not the file the plan names:
    // the strict JSON reader refuses it in any string.
    fails(R"({"trials": [{"cloud": "a.pcd\u0000/x"}]})",
          "study: p.json: trials[0].cloud: the string 'a.pcd\\x00/x' holds a NUL character (\\u0000); allowed: "
          "text without NUL");
    fails(R"({"trials": [{"cloud": "a", "candidates": "\u0000c.json"}]})",
          "trials[0].candidates: the string '\\x00c.json' holds a NUL character");
}

TEST_CASE("the trial order: as written, or shuffled the same way for the same seed") {
    std::string text = R"({"trials": [)";
    for (int i = 0; i < 12; ++i)
        text += std::string(i ? "," : "") + R"({"cloud": "c)" + std::to_string(i) + R"(.pcd"})";
    const study::Plan plain = parsePlan(text + "]}", "p.json", "/");
    const std::vector<int> order = study::trialOrder(plain);
    for (int i = 0; i < 12; ++i) CHECK(order[std::size_t(i)] == i);
    const study::Plan shuffled = parsePlan(text + R"(], "shuffle_seed": 1})", "p.json", "/");
    const std::vector<int> a = study::trialOrder(shuffled), b = study::trialOrder(shuffled);
    CHECK(a == b);
    CHECK(a != order);
    std::vector<int> sorted = a;
    std::sort(sorted.begin(), sorted.end());
    CHECK(sorted == order);
}

TEST_CASE("readPlan checks the files the plan names") {
    test_support::TempDir dir("study_plan");
    dir.write("a.pcd", "x");
    const auto plan_file = dir.write("plan.json", R"({"trials": [{"cloud": "a.pcd"}, {"cloud": "missing.pcd"}]})");
    CHECK_THROWS_WITH_AS(study::readPlan(plan_file), doctest::Contains("trials[1].cloud"), core::Error);
    const auto ok = dir.write("ok.json", R"({"trials": [{"cloud": "a.pcd"}]})");
    CHECK(study::readPlan(ok).trials[0].cloud == dir.path / "a.pcd");
}
