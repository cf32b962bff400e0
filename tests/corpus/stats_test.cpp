// tests/corpus/stats_test.cpp: a plan written by `corpus --stats DIR --select` is one that
// `ladarvr study` reads (study::readPlan): the two commands agree on the trial format.
#include <corpus/stats.hpp>

#include <study/plan.hpp>

#include <doctest/doctest.h>

#include "test_files.hpp"

#include <filesystem>
#include <fstream>
#include <string>

TEST_CASE("a plan selected from a corpus is read by the study") {
    test_support::TempDir dir("corpus_select_plan");
    std::string manifest;
    for (const char* id : {"0000", "0001", "0002"}) {
        std::filesystem::create_directories(dir.path / "items" / id);
        std::ofstream(dir.path / "items" / id / "cloud.pcd") << "x";
        std::ofstream(dir.path / "items" / id / "scene.json") << "{}";
        manifest += std::string(R"({"id": ")") + id + R"(", "index": )" + std::to_string(std::stoi(id)) +
                    R"(, "points": 10, "files": {"scene.json": {"bytes": 2}, "cloud.pcd": {"bytes": 1}}})" + "\n";
    }
    dir.write("manifest.jsonl", manifest);
    corpus::SelectOptions o;
    o.expression = "points>0";
    o.count = 2;
    o.seed = 4;
    o.time_limit_s = 30.0;
    o.plan = dir.path / "plans" / "plan.json";
    std::filesystem::create_directories(o.plan.parent_path());
    REQUIRE(corpus::selectTrials(dir.path, o).written == 2);

    const study::Plan plan = study::readPlan(o.plan);
    REQUIRE(plan.trials.size() == 2);
    for (const study::PlanTrial& t : plan.trials) {
        CHECK(std::filesystem::is_regular_file(t.cloud));
        CHECK(t.cloud.filename() == "cloud.pcd");
        CHECK(t.name.rfind("item 000", 0) == 0);
        CHECK(t.time_limit_s == 30.0);
    }
    CHECK(plan.shuffle_seed == 4u);
}
