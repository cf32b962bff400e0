// tests/study/resume_test.cpp: finding where a stopped design session resumes
// (study/resume.hpp): the rows a session wrote, text cells made safe by csvCell, are
// taken as this session's, and a study.json whose participant breaks the id rules is
// refused.
#include <study/resume.hpp>

#include <study/study_folder.hpp>
#include <study/study_log.hpp>

#include <test_files.hpp>

#include <doctest/doctest.h>

namespace {
// One condition, one block of two trials; the first trial's cloud is named like a formula
// and holds an escape character, as a design may name its files.
const char* kDesign = R"({"conditions": [{"name": "edl"}],
    "blocks": [{"name": "b1", "trials": [{"cloud": "=1+2,\u001b.pcd"}, {"cloud": "b.pcd"}]}],
    "participants": ["P01"]})";

struct Fixture {
    test_support::TempDir dir{"resume"};
    study::Design design = study::parseDesign(kDesign, "d.json", "/d");
    study::Session session = study::expandSession(design, "P01", "d.json");
    std::filesystem::path out = dir.path / "out";

    Fixture() {
        std::filesystem::create_directory(out);
        study::writeDesignRecord(out, "/d/d.json", "aaaa", {"edl"}, session);
    }
    // The session's first trial, written as a run writes it.
    void runFirstTrial() {
        study::StudyLog log(
            out,
            [&](int position) {
                study::TrialInfo info;
                info.source = session.plan.trials[std::size_t(position)].source;
                info.name = session.plan.trials[std::size_t(position)].name;
                info.participant = "P01";
                info.condition = "edl";
                info.block = "b1";
                return info;
            },
            1.0);
        log.addDesignColumns();
        viewer::TrialOutcome o;
        o.decision = viewer::Decision::NoTarget;
        o.time_to_decision_s = 2.0;
        log.onEnd(0, o);
        REQUIRE(log.error().empty());
    }
};
}  // namespace

TEST_CASE("resume: a trial whose cloud name was made safe in trials.csv is this session's trial") {
    Fixture f;
    f.runFirstTrial();
    CHECK(test_support::slurp(f.out / "trials.csv").find("\"'=1+2,\\x1b.pcd\"") != std::string::npos);
    const std::optional<study::ResumePoint> point = study::findResumePoint(f.out, "aaaa", f.design, f.session);
    REQUIRE(point);
    CHECK(point->trials_done == 1);
    CHECK(point->columns == study::TrialColumns::Judged);
}

TEST_CASE("resume: trials.csv's name must be the session trial's, an older trials.csv without it resumes as it is") {
    Fixture f;
    f.runFirstTrial();
    const std::string header = study::StudyLog::designTrialsHeader();
    const std::string row = test_support::slurp(f.out / "trials.csv").substr(header.size() + 1);
    // The row up to the design's columns, then another trial's name: not this session's trial 1.
    const std::string design_columns = ",P01,edl,b1,0";
    const std::size_t name_at = row.find(design_columns + ",");
    REQUIRE(name_at != std::string::npos);
    const std::string older_row = row.substr(0, name_at + design_columns.size());
    f.dir.write("out/trials.csv", header + "\n" + older_row + ",b.pcd,0\n");
    CHECK(test_support::errorOf([&] {
              study::findResumePoint(f.out, "aaaa", f.design, f.session);
          }).find("trials.csv: line 2: not trial 1 of this session") != std::string::npos);
    // The layout written before name and candidates_shown came: kept, and said so.
    f.dir.write("out/trials.csv",
                study::StudyLog::designTrialsHeader(study::TrialColumns::Base) + "\n" + older_row + "\n");
    const std::optional<study::ResumePoint> older = study::findResumePoint(f.out, "aaaa", f.design, f.session);
    REQUIRE(older);
    CHECK(older->trials_done == 1);
    CHECK(older->columns == study::TrialColumns::Base);
}

TEST_CASE("resume: study.json's participant must be an id by the design's rules") {
    Fixture f;
    for (const std::string bad : {"=1+2", "<img src=x onerror=alert(1)>", "-P01"}) {
        CAPTURE(bad);
        f.dir.write("out/study.json", R"({"design": "/d/d.json", "design_sha256": "aaaa", "participant": ")" + bad +
                                          R"(", "condition_order": ["edl"], "order": [0, 1]})");
        CHECK(test_support::errorOf([&] { study::findResumePoint(f.out, "aaaa", f.design, f.session); }) ==
              "study: --out " + f.out.string() +
                  "/study.json: participant is not an id of 1 to 40 letters, digits, '_', '-' or '.', not starting "
                  "with '-'; allowed: the same design and participant (to resume), or a new or empty folder");
    }
}
