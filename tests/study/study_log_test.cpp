// tests/study/study_log_test.cpp: the study's files from a sequence of trial reports.
#include <study/study_log.hpp>

#include <test_files.hpp>

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

namespace {
std::vector<std::string> lines(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}
}  // namespace

TEST_CASE("trials.csv holds one row per finished trial, rewritten whole as each ends") {
    test_support::TempDir dir("study_log");
    study::StudyLog log(
        dir.path,
        [](int trial) {
            study::TrialInfo info;
            info.source = trial == 0 ? "village, east.pcd" : "s.json";
            info.name = trial == 0 ? "village" : "scene, again";
            info.candidates_shown = trial == 0 ? 3 : 0;
            if (trial == 1) info.visibility_metric = 0.25;
            return info;
        },
        1.0);
    CHECK_FALSE(std::filesystem::exists(dir.path / "trials.csv"));

    log.onStart(0);
    viewer::TraceSample s;
    s.t_s = 0.5;
    s.head_world = {1.0, 2.0, 3.0};
    log.onFrame(0, s);
    s.t_s = 0.6;
    s.hit_world = glm::dvec3(10.0, 20.0, 0.5);
    s.mode = viewer::ViewMode::Free;
    s.scale = 2.0;
    log.onFrame(0, s);
    log.onDesignate(0, 0.6, {10.0, 20.0, 0.5});
    core::Candidate c;
    c.id = "c1";
    c.score = 0.75;
    log.onVerdict(0, 0.7, c, viewer::Verdict::Rejected);
    viewer::TrialOutcome o;
    o.decision = viewer::Decision::Confirm;
    o.designated_world = glm::dvec3(10.0, 20.0, 0.5);
    o.target_distance_m = 0.25;
    o.target_known = true;
    o.time_to_first_designation_s = 0.6;
    o.time_to_decision_s = 0.8;
    o.designations = 1;
    o.mode_switches = 2;
    o.seconds_in_free_mode = 0.1;
    log.onEnd(0, o);

    auto rows = lines(dir.path / "trials.csv");
    REQUIRE(rows.size() == 2);
    CHECK(rows[0] == study::StudyLog::trialsHeader());
    // The trial's name and the candidate boxes it showed come last, after the columns
    // older readers take by position.
    CHECK(rows[0].ends_with(",visibility_metric,name,candidates_shown,designation_hit,box_hit"));
    CHECK(rows[1] ==
          "1,\"village, east.pcd\",confirm,10.000000,20.000000,0.500000,0.250000,1,0.600000,0.800000,1,2,"
          "0.100000,,village,3,1,");
    std::vector<viewer::TraceSample> samples;  // and back
    for (const io::TraceRow& r : io::readTrace(dir.path / "trace_1.csv").rows)
        samples.push_back(viewer::toTraceSample(r));
    REQUIRE(samples.size() == 2);
    CHECK(samples[0].t_s == 0.5);
    CHECK(samples[0].head_world == glm::dvec3(1.0, 2.0, 3.0));
    CHECK_FALSE(samples[0].hit_world);
    CHECK(samples[1].mode == viewer::ViewMode::Free);
    CHECK(samples[1].scale == 2.0);
    CHECK(*samples[1].hit_world == glm::dvec3(10.0, 20.0, 0.5));
    const auto trace = lines(dir.path / "trace_1.csv");
    REQUIRE(trace.size() == 3);
    CHECK(trace[0] == io::kTraceHeader);
    CHECK(trace[1].starts_with("0.500000,1.000000,2.000000,3.000000,1.000000000,0.000000000,"));
    CHECK(trace[1].ends_with(",automatic,1,,,"));
    CHECK(trace[2].ends_with(",free,2,10.000000,20.000000,0.500000"));
    auto cands = lines(dir.path / "candidates.csv");
    REQUIRE(cands.size() == 2);
    CHECK(cands[1] == "1,c1,0.750000,rejected,0.700000");

    // Trial 2: far from the target, a timeout; the file is replaced with both rows and no
    // temporary is left beside it.
    log.onStart(1);
    viewer::TrialOutcome miss;
    miss.decision = viewer::Decision::Timeout;
    miss.designated_world = glm::dvec3(-30.0, 22.0, 4.0);
    miss.target_distance_m = 36.5;
    miss.target_known = true;
    miss.time_to_decision_s = 120.0;
    log.onEnd(1, miss);
    rows = lines(dir.path / "trials.csv");
    REQUIRE(rows.size() == 3);
    CHECK(rows[2] ==
          "2,s.json,timeout,-30.000000,22.000000,4.000000,36.500000,0,,120.000000,0,0,0.000000,0.250000,"
          "\"scene, again\",0,0,");
    CHECK(lines(dir.path / "trace_2.csv").size() == 1);  // the header only: no frame
    CHECK(log.trialsWritten() == 2);
    CHECK_MESSAGE(log.error().empty(), log.error());
    CHECK(dir.entries() == 6);  // trials, candidates, two traces, two shown files
}

TEST_CASE("hit: 1 only for a confirmed point near the target, 0 otherwise, empty without ground truth") {
    test_support::TempDir dir("study_log_hit");
    study::StudyLog log(dir.path, [](int) { return study::TrialInfo{"a.pcd", {}}; }, 1.0);
    const viewer::Decision decisions[] = {viewer::Decision::NoTarget, viewer::Decision::Timeout,
                                          viewer::Decision::Quit};
    int trial = 0;
    for (const bool known : {true, false}) {
        for (const viewer::Decision d : decisions) {
            log.onStart(trial);
            viewer::TrialOutcome o;
            o.decision = d;
            o.target_known = known;
            o.time_to_decision_s = 2.0;
            log.onEnd(trial++, o);
        }
    }
    const auto rows = lines(dir.path / "trials.csv");
    REQUIRE(rows.size() == 7);
    CHECK(rows[1] == "1,a.pcd,no_target,,,,,0,,2.000000,0,0,0.000000,,,0,0,");
    CHECK(rows[2] == "2,a.pcd,timeout,,,,,0,,2.000000,0,0,0.000000,,,0,0,");
    CHECK(rows[3] == "3,a.pcd,quit,,,,,0,,2.000000,0,0,0.000000,,,0,0,");
    CHECK(rows[4] == "4,a.pcd,no_target,,,,,,,2.000000,0,0,0.000000,,,0,,");
    CHECK(rows[6] == "6,a.pcd,quit,,,,,,,2.000000,0,0,0.000000,,,0,,");
    CHECK(dir.entries() == 14);  // trials, candidates, six traces trace_1 .. trace_6, six shown_1 .. shown_6
    CHECK(std::filesystem::exists(dir.path / "trace_6.csv"));

    // A designation on the target still standing at no_target or timeout keeps its distance
    // but is no hit: only a confirmed point is the operator's answer.
    for (const viewer::Decision d :
         {viewer::Decision::NoTarget, viewer::Decision::Timeout, viewer::Decision::Confirm}) {
        log.onStart(trial);
        viewer::TrialOutcome o;
        o.decision = d;
        o.target_known = true;
        o.designated_world = glm::dvec3(1.0, 2.0, 3.0);
        o.target_distance_m = 0.5;
        o.time_to_decision_s = 2.0;
        log.onEnd(trial++, o);
    }
    const auto more = lines(dir.path / "trials.csv");
    REQUIRE(more.size() == 10);
    CHECK(more[7] == "7,a.pcd,no_target,1.000000,2.000000,3.000000,0.500000,0,,2.000000,0,0,0.000000,,,0,0,");
    CHECK(more[8] == "8,a.pcd,timeout,1.000000,2.000000,3.000000,0.500000,0,,2.000000,0,0,0.000000,,,0,0,");
    CHECK(more[9] == "9,a.pcd,confirm,1.000000,2.000000,3.000000,0.500000,1,,2.000000,0,0,0.000000,,,0,1,");
}

TEST_CASE("hit: a confirmed candidate box that holds the target is a hit, wherever the designation stood") {
    test_support::TempDir dir("study_log_box_hit");
    study::StudyLog log(
        dir.path,
        [](int) {
            study::TrialInfo info{"s.json", {}};
            info.target_centre_world = glm::dvec3(100.0, 50.0, 1.25);
            return info;
        },
        1.0);
    core::Candidate tank;  // 7 x 3.5 x 2.5 m, turned 90 degrees: long along y
    tank.id = "c1";
    tank.centre_world = {100.5, 51.5, 1.0};
    tank.size_m = {7.0, 3.5, 2.5};
    tank.yaw_deg = 90.0;
    core::Candidate house = tank;  // a box beside the target
    house.id = "c2";
    house.centre_world = {120.0, 50.0, 3.0};
    int trial = 0;
    // The designation stands on a house 20 m away; the operator confirms a box.
    for (const core::Candidate& box : {tank, house}) {
        log.onStart(trial);
        log.onVerdict(trial, 1.0, box, viewer::Verdict::Confirmed);
        viewer::TrialOutcome o;
        o.decision = viewer::Decision::Confirm;
        o.target_known = true;
        o.designated_world = glm::dvec3(120.0, 50.0, 6.0);
        o.target_distance_m = 20.0;
        o.time_to_decision_s = 2.0;
        log.onEnd(trial++, o);
    }
    // A box confirmed in an earlier trial does not carry over to the next one.
    log.onStart(trial);
    viewer::TrialOutcome o;
    o.decision = viewer::Decision::Confirm;
    o.target_known = true;
    o.designated_world = glm::dvec3(120.0, 50.0, 6.0);
    o.target_distance_m = 20.0;
    o.time_to_decision_s = 2.0;
    log.onVerdict(trial, 1.0, tank, viewer::Verdict::Rejected);
    log.onEnd(trial++, o);
    const auto rows = lines(dir.path / "trials.csv");
    REQUIRE(rows.size() == 4);
    // The designation missed in every one; the box hit in the first only (box_hit empty in
    // the third: no box was confirmed there).
    CHECK(rows[1] == "1,s.json,confirm,120.000000,50.000000,6.000000,20.000000,1,,2.000000,0,0,0.000000,,,0,0,1");
    CHECK(rows[2] == "2,s.json,confirm,120.000000,50.000000,6.000000,20.000000,0,,2.000000,0,0,0.000000,,,0,0,0");
    CHECK(rows[3] == "3,s.json,confirm,120.000000,50.000000,6.000000,20.000000,0,,2.000000,0,0,0.000000,,,0,0,");
    const auto verdicts = lines(dir.path / "candidates.csv");
    REQUIRE(verdicts.size() == 4);
    CHECK(verdicts[1] == "1,c1,0.000000,confirmed,1.000000");
}

TEST_CASE("hit: a cloud trial's confirmed box is judged on the centre of the cloud's target points") {
    // A cloud file (a COPC file too) has no target meshes: the viewer reports the centre of
    // the bounds of the points labelled target, and the box holding it is a hit.
    test_support::TempDir dir("study_log_cloud_box_hit");
    study::StudyLog log(dir.path, [](int) { return study::TrialInfo{"c.copc.laz", {}}; }, 1.0);
    core::Candidate tank;
    tank.id = "c1";
    tank.centre_world = {100.5, 51.5, 1.0};
    tank.size_m = {7.0, 3.5, 2.5};
    core::Candidate house = tank;
    house.id = "c2";
    house.centre_world = {120.0, 50.0, 3.0};
    int trial = 0;
    for (const core::Candidate& box : {tank, house}) {
        log.onStart(trial);
        log.onVerdict(trial, 1.0, box, viewer::Verdict::Confirmed);
        viewer::TrialOutcome o;
        o.decision = viewer::Decision::Confirm;
        o.target_known = true;
        o.target_centre_world = glm::dvec3(100.0, 51.0, 1.25);
        o.designated_world = glm::dvec3(120.0, 50.0, 6.0);
        o.target_distance_m = 20.0;
        o.time_to_decision_s = 2.0;
        log.onEnd(trial++, o);
    }
    const auto rows = lines(dir.path / "trials.csv");
    REQUIRE(rows.size() == 3);
    CHECK(rows[1] == "1,c.copc.laz,confirm,120.000000,50.000000,6.000000,20.000000,1,,2.000000,0,0,0.000000,,,0,0,1");
    CHECK(rows[2] == "2,c.copc.laz,confirm,120.000000,50.000000,6.000000,20.000000,0,,2.000000,0,0,0.000000,,,0,0,0");
}

TEST_CASE("boxHolds: the point inside the turned box, faces included") {
    core::Candidate box;
    box.centre_world = {10.0, 20.0, 1.0};
    box.size_m = {4.0, 2.0, 2.0};
    box.yaw_deg = 90.0;  // long along y
    CHECK(study::StudyLog::boxHolds(box, {10.0, 20.0, 1.0}));
    CHECK(study::StudyLog::boxHolds(box, {10.0, 21.9, 1.0}));
    CHECK(study::StudyLog::boxHolds(box, {10.0, 20.0, 2.0}));
    CHECK_FALSE(study::StudyLog::boxHolds(box, {11.9, 20.0, 1.0}));
    CHECK_FALSE(study::StudyLog::boxHolds(box, {10.0, 22.1, 1.0}));
    CHECK_FALSE(study::StudyLog::boxHolds(box, {10.0, 20.0, 2.1}));
}

TEST_CASE("a trace that exists already is not overwritten and the error is kept") {
    test_support::TempDir dir("study_log_exists");
    dir.write("trace_1.csv", "someone else's\n");
    study::StudyLog log(dir.path, {}, 1.0);
    log.onStart(0);
    log.onFrame(0, {});
    CHECK(log.error().find("trace_1.csv") != std::string::npos);
    CHECK(lines(dir.path / "trace_1.csv") == std::vector<std::string>{"someone else's"});
}

TEST_CASE("trials.csv and candidates.csv: text cells cannot become formulas or steer a terminal") {
    test_support::TempDir dir("study_log_cells");
    study::StudyLog log(
        dir.path,
        [](int) {
            study::TrialInfo info;
            info.source = "=HYPERLINK(\"http://x\",\"a\x1b[2J\u202e.pcd\")";
            info.participant = "P01";
            info.condition = "edl";
            info.block = "b1";
            info.name = "-2+3 \x1b[1m";
            info.candidates_shown = 1;
            return info;
        },
        1.0);
    log.addDesignColumns();
    log.onStart(0);
    core::Candidate c;
    c.id = "@SUM(1)";
    c.score = -0.5;
    log.onVerdict(0, 0.7, c, viewer::Verdict::Rejected);
    viewer::TrialOutcome o;
    o.decision = viewer::Decision::NoTarget;
    o.designated_world = glm::dvec3(-1.5, 2.0, -3.0);
    o.time_to_decision_s = 2.0;
    log.onEnd(0, o);
    const auto rows = lines(dir.path / "trials.csv");
    REQUIRE(rows.size() == 2);
    // The cloud's and the trial's names: a leading ', escapes for ESC and U+202E; numbers
    // stay numbers. The name follows the design's columns.
    CHECK(rows[0] == study::StudyLog::designTrialsHeader());
    CHECK(rows[0].ends_with(",practice,name,candidates_shown,designation_hit,box_hit"));
    CHECK(rows[1] ==
          "1,\"'=HYPERLINK(\"\"http://x\"\",\"\"a\\x1b[2J\\u202e.pcd\"\")\",no_target,-1.500000,2.000000,-3.000000,,,,"
          "2.000000,0,0,0.000000,,P01,edl,b1,0,'-2+3 \\x1b[1m,1,,");
    const auto candidates = lines(dir.path / "candidates.csv");
    REQUIRE(candidates.size() == 2);
    CHECK(candidates[1] == "1,'@SUM(1),-0.500000,rejected,0.700000");
}

TEST_CASE("a resumed session whose trials.csv predates name and candidates_shown goes on without them") {
    test_support::TempDir dir("study_log_older");
    study::StudyLog log(
        dir.path,
        [](int) {
            study::TrialInfo info;
            info.source = "a.pcd";
            info.participant = "P01";
            info.condition = "edl";
            info.block = "b1";
            info.name = "a";
            info.candidates_shown = 2;
            return info;
        },
        1.0);
    log.addDesignColumns();
    log.setColumns(study::TrialColumns::Base);
    const std::string kept = "1,a.pcd,quit,,,,,,,1.000000,0,0,0.000000,,P01,edl,b1,0";
    log.resumeAt(1, {kept}, {});
    CHECK_FALSE(log.recordedAnything());
    log.onStart(0);
    CHECK(log.recordedAnything());
    viewer::TrialOutcome o;
    o.time_to_decision_s = 2.0;
    log.onEnd(0, o);
    const auto rows = lines(dir.path / "trials.csv");
    REQUIRE(rows.size() == 3);
    CHECK(rows[0] == study::StudyLog::designTrialsHeader(study::TrialColumns::Base));
    CHECK(rows[0].ends_with(",practice"));
    CHECK(rows[1] == kept);
    CHECK(rows[2] == "2,a.pcd,quit,,,,,,,2.000000,0,0,0.000000,,P01,edl,b1,0");
}

TEST_CASE("a trace sample becomes a row and back, mode, scale and hit kept") {
    viewer::TraceSample s;
    s.t_s = 2.5;
    s.head_world = {1.0, -2.0, 3.0};
    s.head_orientation = glm::dquat(0.0, 1.0, 0.0, 0.0);
    s.mode = viewer::ViewMode::Free;
    s.scale = 4.0;
    s.hit_world = glm::dvec3(7.0, 8.0, 9.0);
    const io::TraceRow r = viewer::toTraceRow(s);
    CHECK(r.mode == io::TraceMode::Free);
    CHECK(r.head_orientation.x == 1.0);
    const viewer::TraceSample back = viewer::toTraceSample(r);
    CHECK(back.t_s == 2.5);
    CHECK(back.head_world == s.head_world);
    CHECK(back.head_orientation == s.head_orientation);
    CHECK(back.mode == viewer::ViewMode::Free);
    CHECK(back.scale == 4.0);
    CHECK(*back.hit_world == glm::dvec3(7.0, 8.0, 9.0));
    CHECK(viewer::toTraceSample(viewer::toTraceRow(viewer::TraceSample{})).mode == viewer::ViewMode::Automatic);
}

TEST_CASE("shown_N.json: the boxes and colours a trial showed and the operator's marks, read back for a replay") {
    test_support::TempDir dir("study_log_shown");
    core::Candidate tank;
    tank.id = "c1";
    tank.centre_world = {100.5, 51.5, 1.0};
    tank.size_m = {7.0, 3.5, 2.5};
    tank.yaw_deg = 20.0;
    tank.score = 0.9;
    core::Candidate house = tank;
    house.id = "c2";
    house.centre_world = {120.0, 50.0, 3.0};
    house.score = 0.25;
    study::StudyLog log(
        dir.path,
        [&](int) {
            study::TrialInfo info{"a.pcd", {}};
            info.shown.candidates = {tank, house};
            info.shown.colour = viewer::ColourMode::HeightJet;
            return info;
        },
        1.0);
    log.onStart(0);
    // Written at the start: the boxes and colours, no mark yet.
    study::TrialShown started = study::readTrialShown(dir.path / "shown_1.json");
    CHECK(started.candidates.size() == 2);
    CHECK(started.marks.empty());
    log.onDesignate(0, 0.5, {120.0, 50.0, 6.0});
    log.onWithdraw(0, 0.75);
    log.onVerdict(0, 1.0, house, viewer::Verdict::Rejected);
    log.onDesignate(0, 1.25, {100.0, 51.0, 1.5});
    log.onVerdict(0, 1.5, tank, viewer::Verdict::Confirmed);
    log.onVerdict(0, 1.5, house, viewer::Verdict::Unreviewed);  // not a mark
    viewer::TrialOutcome o;
    o.decision = viewer::Decision::Confirm;
    o.time_to_decision_s = 1.5;
    o.terrain_source = "the file's class 2 (35,318 points)";
    log.onEnd(0, o);
    REQUIRE(log.error().empty());
    const study::TrialShown shown = study::readTrialShown(dir.path / "shown_1.json");
    CHECK(shown.terrain_source == "the file's class 2 (35,318 points)");
    CHECK(shown.terrain_failure.empty());
    REQUIRE(shown.colour);
    CHECK(*shown.colour == viewer::ColourMode::HeightJet);
    CHECK_FALSE(shown.eye_dome);
    REQUIRE(shown.candidates.size() == 2);
    CHECK(shown.candidates[0].id == "c1");
    CHECK(shown.candidates[0].centre_world == tank.centre_world);
    CHECK(shown.candidates[0].yaw_deg == 20.0);
    CHECK(shown.candidates[1].score == 0.25);
    REQUIRE(shown.marks.size() == 5);
    CHECK(*shown.marks[0].designated_world == glm::dvec3(120.0, 50.0, 6.0));
    CHECK(shown.marks[1].t_s == 0.75);
    CHECK_FALSE(shown.marks[1].designated_world);
    CHECK(shown.marks[1].candidate.empty());
    CHECK(shown.marks[2].candidate == "c2");
    CHECK(shown.marks[2].verdict == viewer::Verdict::Rejected);
    CHECK(shown.marks[4].verdict == viewer::Verdict::Confirmed);

    // A damaged file is refused in one line naming the field.
    test_support::TempDir bad("study_log_shown_bad");
    bad.write("shown_1.json", R"({"candidates": [], "marks": [{"t_s": 1, "candidate": "c1", "verdict": "maybe"}]})");
    CHECK(test_support::errorOf([&] { study::readTrialShown(bad.path / "shown_1.json"); }) ==
          "study: --replay " + (bad.path / "shown_1.json").string() +
              ": marks[0].verdict 'maybe': allowed confirmed or rejected");
    bad.write("shown_2.json", R"({"candidates": [], "marks": [], "colours": "x"})");
    CHECK(test_support::errorOf([&] { study::readTrialShown(bad.path / "shown_2.json"); }) ==
          "study: --replay " + (bad.path / "shown_2.json").string() +
              ": key 'colours': allowed colour, eye_dome, candidates, marks, terrain");
    bad.write("shown_3.json", R"({"candidates": [], "marks": [], "terrain": {"source": "a", "failure": "b"}})");
    CHECK(test_support::errorOf([&] { study::readTrialShown(bad.path / "shown_3.json"); }) ==
          "study: --replay " + (bad.path / "shown_3.json").string() +
              ": terrain: allowed an object with one key, source or failure");
}

TEST_CASE("shown_N.json: a terrain's failure is kept, and a trial without a terrain coming has none") {
    test_support::TempDir dir("study_log_shown_terrain");
    study::StudyLog log(dir.path, [](int) { return study::TrialInfo{"a.las", {}}; }, 1.0);
    viewer::TrialOutcome failed;
    failed.terrain_failure = "the cloud has no points";
    log.onStart(0);
    log.onEnd(0, failed);
    log.onStart(1);
    log.onEnd(1, viewer::TrialOutcome{});
    REQUIRE(log.error().empty());
    const study::TrialShown first = study::readTrialShown(dir.path / "shown_1.json");
    CHECK(first.terrain_source.empty());
    CHECK(first.terrain_failure == "the cloud has no points");
    const study::TrialShown second = study::readTrialShown(dir.path / "shown_2.json");
    CHECK(second.terrain_source.empty());
    CHECK(second.terrain_failure.empty());
    CHECK(test_support::slurp(dir.path / "shown_2.json").find("terrain") == std::string::npos);
}
