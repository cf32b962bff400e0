// tests/study/study_folder_test.cpp: the study's output folder (study/study_folder.hpp):
// which folders are refused, the trace's name, and study.json written and read back.
#include <study/study_folder.hpp>

#include <core/error.hpp>

#include <test_files.hpp>

#include <doctest/doctest.h>

using test_support::errorOf;

TEST_CASE("a folder that holds a study's file is refused, other files are allowed") {
    test_support::TempDir dir("study_folder");
    CHECK(study::traceFileName(3) == "trace_3.csv");
    for (const char* name : {"trials.csv", "candidates.csv", "study.json", "trace_1.csv", "trace_x.csv"})
        CHECK(study::isStudyFile(name));
    for (const char* name : {"notes.txt", "trace_1.csv.bak", "trials.csv~", "plan.json"})
        CHECK_FALSE(study::isStudyFile(name));

    study::checkStudyFolder(dir.path);  // empty
    dir.write("notes.txt", "mine\n");
    study::checkStudyFolder(dir.path);
    dir.write("trace_2.csv", "t_s\n");
    CHECK(errorOf([&] { study::checkStudyFolder(dir.path); }) ==
          "study: --out " + dir.path.string() +
              ": already holds a study (trace_2.csv); allowed: a new or empty folder");
    CHECK(errorOf([&] { study::checkStudyFolder(dir.path / "notes.txt"); }) ==
          "study: --out " + (dir.path / "notes.txt").string() + ": not a folder");
    CHECK(errorOf([&] { study::checkStudyFolder(dir.path / "missing"); }).ends_with(": not a folder"));
}

TEST_CASE("study.json records the plan and the order, and is read back against the plan") {
    static test_support::TempDir dir("study_record");
    dir.write("a.pcd", "not read here\n");
    const std::filesystem::path plan =
        dir.write("plan.json", R"({"trials": [{"cloud": "a.pcd"}, {"cloud": "a.pcd", "name": "again"}]})");
    const std::filesystem::path out = dir.path / "out";
    std::filesystem::create_directory(out);
    study::writeStudyRecord(out, plan, {1, 0});
    CHECK(test_support::slurp(out / "study.json") ==
          "{\n  \"order\": [\n    1,\n    0\n  ],\n  \"plan\": \"" + plan.string() + "\"\n}\n");
    const study::RecordedStudy recorded = study::readStudyRecord(out);
    CHECK(recorded.order == std::vector<int>{1, 0});
    REQUIRE(recorded.plan.trials.size() == 2);
    CHECK(recorded.plan.trials[1].name == "again");

    dir.write("out/study.json", R"({"plan": ")" + plan.string() + R"(", "order": [2]})");
    CHECK(errorOf([&] {
              study::readStudyRecord(out);
          }).ends_with("study.json: 'order' does not match the plan's trials"));
    dir.write("out/study.json", R"({"order": [0]})");
    CHECK(errorOf([&] { study::readStudyRecord(out); }).ends_with("not a study's record (needs 'plan' and 'order')"));
    CHECK(errorOf([&] { study::readStudyRecord(dir.path / "none"); }).starts_with("study: --replay "));
}

TEST_CASE("a trace_<N>.csv beside study.json is trial N of that study, its scene or cloud as the plan names it") {
    static test_support::TempDir dir("study_trace_trial");  // kept: see above
    dir.write("a.pcd", "not read here\n");
    dir.write("s.json", "not read here\n");
    const std::filesystem::path plan =
        dir.write("plan.json", R"({"trials": [{"cloud": "a.pcd"}, {"scene": "s.json", "name": "hills"}]})");
    const std::filesystem::path out = dir.path / "out";
    std::filesystem::create_directory(out);
    study::writeStudyRecord(out, plan, {1, 0});  // trial 1 ran the plan's scene, trial 2 its cloud
    const std::optional<study::RecordedTrial> first = study::recordedTraceTrial(out / "trace_1.csv", "metric: --trace");
    REQUIRE(first);
    CHECK(first->number == 1);
    CHECK(first->folder == out);
    CHECK(first->trial.scene == dir.path / "s.json");
    CHECK(first->trial.name == "hills");
    const std::optional<study::RecordedTrial> second = study::recordedTraceTrial(out / "trace_2.csv", "x");
    REQUIRE(second);
    CHECK(second->trial.scene.empty());
    CHECK(second->trial.cloud == dir.path / "a.pcd");

    CHECK(errorOf([&] { study::recordedTraceTrial(out / "trace_3.csv", "metric: --trace"); }) ==
          "metric: --trace " + (out / "trace_3.csv").string() + ": " + (out / "study.json").string() +
              " records 2 trials, not trial 3; allowed the trace of one of its trials");
    // Not a study's trace name, or no study.json beside it: nothing recorded.
    for (const char* name :
         {"trace_01.csv", "trace_+1.csv", "trace_0.csv", "trace_1.csv.bak", "mine.csv", "trace_.csv"})
        CHECK_FALSE(study::recordedTraceTrial(out / name, "metric: --trace"));
    CHECK_FALSE(study::recordedTraceTrial(dir.path / "trace_1.csv", "metric: --trace"));
    // A study.json that cannot be read is named, by the reader's words.
    dir.write("out/study.json", R"({"order": [0]})");
    CHECK(errorOf([&] { study::recordedTraceTrial(out / "trace_1.csv", "metric: --trace"); }) ==
          "metric: --trace " + (out / "study.json").string() + ": not a study's record (needs 'plan' and 'order')");
}
