// Tests of study/src/report_read.cpp and report_csv.cpp: trials.csv and questionnaires.csv read field by field
// (one line naming the file, line, column and what is allowed), the SSQ and TLX scored
// from the answers, and the refusals of session folders that do not belong together.
#include <study/report.hpp>

#include <study/study_log.hpp>

#include <core/error.hpp>
#include <test_files.hpp>
#include <test_paths.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <map>
#include <string>

namespace {
// Most rows here are in the layout sessions had before name and candidates_shown came,
// still read as they are (kNamedHeader's rows have the two columns).
const std::string kHeader = study::StudyLog::designTrialsHeader(study::TrialColumns::Base) + "\n";
const std::string kNamedHeader = study::StudyLog::designTrialsHeader(study::TrialColumns::Named) + "\n";
const std::string kJudgedHeader = study::StudyLog::designTrialsHeader() + "\n";
// trial,cloud,decision,x,y,z,distance,hit,first,time,designations,switches,free,metric,
// participant,condition,block,practice[,name,candidates_shown]
const std::string kRows =
    "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,,1\n"
    "2,demo.pcd,confirm,5,5,1,7.1,0,1.0,3.0,2,1,0.5,0.4,P01,a,first,0\n"
    "3,\"b,c.pcd\",no_target,,,,,,,4.0,0,0,0,,P01,b,first,0\n";

std::string errorOfTrials(const std::string& text) {
    return test_support::errorOf([&] { study::parseReportTrials(text, "T/trials.csv"); });
}

std::string ssqRows(const std::string& occasion, int rating) {
    std::string out;
    for (const study::SsqItem& it : study::ssqItems())
        out += "P01,,ssq," + occasion + "," + std::string(it.item.id) + "," + std::to_string(rating) + ",1.0\n";
    return out;
}
const std::string kQHeader = "participant,condition,instrument,occasion,item,response,time_s\n";

study::ParticipantResults participant() {
    study::ParticipantResults p;
    p.participant = "P01";
    p.condition_order = {"a", "b"};
    return p;
}
}  // namespace

TEST_CASE("trials.csv: rows read, quoting and empty fields kept") {
    const std::vector<study::ReportTrial> t = study::parseReportTrials(kHeader + kRows, "T/trials.csv");
    REQUIRE(t.size() == 3);
    CHECK(t[0].practice);
    CHECK(t[0].block.empty());
    CHECK(t[1].hit == 0);
    CHECK(*t[1].target_distance_m == doctest::Approx(7.1));
    CHECK(*t[1].visibility_metric == doctest::Approx(0.4));
    CHECK(t[2].cloud == "b,c.pcd");
    CHECK(t[2].decision == study::TrialDecision::NoTarget);
    CHECK(!t[2].hit);
    CHECK(t[2].time_to_decision_s == 4.0);
    CHECK(t[2].condition == "b");
    CHECK(t[2].participant == "P01");
}

TEST_CASE("trials.csv: the trial's name and the candidates shown, or an older session without them") {
    const std::vector<study::ReportTrial> t =
        study::parseReportTrials(kNamedHeader +
                                     "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,,1,practice one,0\n"
                                     "2,\"b,c.pcd\",no_target,,,,,,,4.0,0,0,0,,P01,b,first,0,\"'=village, east\",3\n",
                                 "T/trials.csv");
    REQUIRE(t.size() == 2);
    CHECK(t[0].name == "practice one");
    CHECK(t[0].candidates_shown == 0);
    CHECK(t[1].cloud == "b,c.pcd");
    CHECK(t[1].name == "'=village, east");
    CHECK(t[1].candidates_shown == 3);
    CHECK(t[1].block == "first");  // the design's columns where they were
    const std::vector<study::ReportTrial> older = study::parseReportTrials(kHeader + kRows, "T/trials.csv");
    REQUIRE(older.size() == 3);
    CHECK(older[0].name.empty());
    CHECK_FALSE(older[0].candidates_shown);

    CHECK(errorOfTrials(kNamedHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,first,0,a,-1\n") ==
          "T/trials.csv: line 2, column candidates_shown: '-1'; allowed a whole number 0 .. 1e9");
    CHECK(errorOfTrials(kNamedHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,first,0,,1\n") ==
          "T/trials.csv: line 2, column name: ''; allowed the trial's name");
    // A row of the older layout under the newer header: counted, not read by position.
    CHECK(errorOfTrials(kNamedHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2: 18 fields; allowed: 20, as the header");
    CHECK(errorOfTrials(study::StudyLog::designTrialsHeader(study::TrialColumns::Base) + ",name\n") ==
          "T/trials.csv: line 1: not the header of a design session's trials.csv; allowed: " +
              study::StudyLog::designTrialsHeader() +
              " (or the same without designation_hit,box_hit, or without name,candidates_shown too)");
}

TEST_CASE("trials.csv: the two ways to hit, or a session written before those columns") {
    const std::vector<study::ReportTrial> t =
        study::parseReportTrials(kJudgedHeader +
                                     "1,demo.pcd,confirm,0,0,1,20,1,1.5,2.5,1,0,0,,P01,a,first,0,one,2,0,1\n"
                                     "2,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,first,0,one,2,1,\n"
                                     "3,demo.pcd,no_target,,,,,,,4.0,0,0,0,,P01,b,first,0,one,0,,\n",
                                 "T/trials.csv");
    REQUIRE(t.size() == 3);
    CHECK(t[0].hit == 1);
    CHECK(t[0].designation_hit == 0);
    CHECK(t[0].box_hit == 1);
    CHECK(t[1].designation_hit == 1);
    CHECK_FALSE(t[1].box_hit);
    CHECK_FALSE(t[2].designation_hit);
    CHECK(t[2].candidates_shown == 0);
    const std::vector<study::ReportTrial> named = study::parseReportTrials(
        kNamedHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,,1,practice one,0\n", "T/trials.csv");
    REQUIRE(named.size() == 1);
    CHECK(named[0].name == "practice one");
    CHECK_FALSE(named[0].designation_hit);
    CHECK(errorOfTrials(kJudgedHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,first,0,one,2,2,\n") ==
          "T/trials.csv: line 2, column designation_hit: '2'; allowed 1, 0 or empty");
    CHECK(errorOfTrials(kJudgedHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,first,0,one,2\n") ==
          "T/trials.csv: line 2: 20 fields; allowed: 22, as the header");
}

TEST_CASE("trials.csv: malformed rows are refused with file, line, column and what is allowed") {
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,0.2,2,1.5,2.5,1,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column hit: '2'; allowed 1, 0 or empty");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,maybe,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column decision: 'maybe'; allowed confirm, no_target, timeout or quit");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,-2,1,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column time_to_decision_s: '-2'; allowed a number 0 .. 1e9 (seconds)");
    // The words name the bound the check uses.
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,1e308,1,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column time_to_decision_s: '1e308'; allowed a number 0 .. 1e9 (seconds)");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,2e12,1,1.5,2,1,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column target_distance_m: '2e12'; allowed a number 0 .. 1e12 (metres) or empty");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2,2000000000,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column designations: '2000000000'; allowed a whole number 0 .. 1e9");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2,1,0,0,,P01,a,=1+2,0\n") ==
          "T/trials.csv: line 2, column block: '=1+2'; allowed a block's name, 1 to 40 letters, digits, '_', '-' or "
          "'.', not starting with '-'");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2,1,0,0,1.5,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column visibility_metric: '1.5'; allowed a number in [0, 1] or empty");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2,1,0,0,,P01,a,,0\n") ==
          "T/trials.csv: line 2, column block: ''; allowed a block's name for a trial that is not practice");
    CHECK(errorOfTrials(kHeader + "2,demo.pcd,confirm,0,0,1,0.2,1,1.5,2,1,0,0,,P01,a,first,0\n") ==
          "T/trials.csv: line 2, column trial: '2'; allowed the row's number 1 (trials are numbered 1, 2, ... "
          "in order)");
    CHECK(errorOfTrials(kHeader + "1,demo.pcd,confirm\n") ==
          "T/trials.csv: line 2: 3 fields; allowed: 18, as the header");
    CHECK(errorOfTrials(kHeader + "\n") == "T/trials.csv: line 2: an empty line; allowed: none");
    CHECK(errorOfTrials("trial,cloud\n").find("line 1: not the header of a design session's trials.csv") !=
          std::string::npos);
    CHECK(errorOfTrials(kHeader + "1,\"demo.pcd,confirm\n") == "T/trials.csv: line 2: an unclosed quote");
}

TEST_CASE("questionnaires.csv: the SSQ before and after, the TLX per condition, last answers count") {
    study::ParticipantResults p = participant();
    std::string text = kQHeader + ssqRows("pre", 0) + ssqRows("post", 1) +
                       "P01,,ssq,post,nausea,3,9.0\n"  // answered again: the last answer counts
                       "P01,a,tlx,after_condition,mental,50,2\nP01,a,tlx,after_condition,physical,10,2\n"
                       "P01,a,tlx,after_condition,temporal,20,2\nP01,a,tlx,after_condition,performance,30,2\n"
                       "P01,a,tlx,after_condition,effort,40,2\nP01,a,tlx,after_condition,frustration,0,2\n"
                       "P01,b,tlx,after_condition,mental,50,3\n"  // incomplete: not scored
                       "P01,b,likert,after_condition,liked,4,3\n"
                       "P01,,text,post,comments,\"fine, thanks\nreally\",10\n";
    study::parseQuestionnaires(text, "Q", p);
    REQUIRE(p.ssq_pre);
    REQUIRE(p.ssq_post);
    CHECK(p.ssq_pre->total == 0.0);
    // Post: every symptom 1, nausea 3 (in the nausea and disorientation clusters).
    CHECK(p.ssq_post->nausea == doctest::Approx((7 + 2) * 9.54));
    CHECK(p.ssq_post->oculomotor == doctest::Approx(7 * 7.58));
    CHECK(p.ssq_post->disorientation == doctest::Approx((7 + 2) * 13.92));
    CHECK(p.ssq_post->total == doctest::Approx((21 + 4) * 3.74));
    REQUIRE(p.tlx_raw.size() == 1);
    CHECK(p.tlx_raw.at("a") == doctest::Approx(150.0 / 6.0));
    REQUIRE(p.likert.size() == 1);
    CHECK(p.likert.at({"liked", "after_condition", "b"}) == 4);

    // Likert answers: per condition after a condition, once for pre and post (post's
    // condition column names the last condition run); an answer given again counts last.
    study::ParticipantResults l = participant();
    study::parseQuestionnaires(kQHeader +
                                   "P01,,likert,pre,ready,2,1\nP01,a,likert,after_condition,liked,6,2\n"
                                   "P01,b,likert,after_condition,liked,3,3\nP01,b,likert,after_condition,liked,5,4\n"
                                   "P01,b,likert,post,overall,7,5\n",
                               "Q", l);
    CHECK(l.likert.size() == 4);
    CHECK(l.likert.at({"ready", "pre", ""}) == 2);
    CHECK(l.likert.at({"liked", "after_condition", "a"}) == 6);
    CHECK(l.likert.at({"liked", "after_condition", "b"}) == 5);
    CHECK(l.likert.at({"overall", "post", ""}) == 7);

    study::ParticipantResults q = participant();
    study::parseQuestionnaires(kQHeader + ssqRows("pre", 1), "Q", q);
    CHECK(q.ssq_pre);
    CHECK(!q.ssq_post);
}

TEST_CASE("questionnaires.csv: malformed rows are refused with one line") {
    const auto err = [](const std::string& rows) {
        study::ParticipantResults p = participant();
        return test_support::errorOf([&] { study::parseQuestionnaires(kQHeader + rows, "Q", p); });
    };
    CHECK(err("P01,,ssq,pre,nausea,4,1\n") == "Q: line 2, column response: '4'; allowed 0, 1, 2 or 3");
    CHECK(err("P01,a,tlx,after_condition,mental,52,1\n") ==
          "Q: line 2, column response: '52'; allowed 0 to 100 in steps of 5");
    CHECK(err("P02,,ssq,pre,nausea,1,1\n") == "Q: line 2, column participant: 'P02'; allowed 'P01', as study.json");
    CHECK(err("P01,c,tlx,after_condition,mental,50,1\n").find("column condition: 'c'; allowed one of the session's") !=
          std::string::npos);
    CHECK(err("P01,,ssq,pre,itching,1,1\n").find("column item: 'itching'") != std::string::npos);
    CHECK(err("P01,,poll,pre,x,1,1\n") == "Q: line 2, column instrument: 'poll'; allowed ssq, tlx, likert or text");
    // An answer asked after a condition names it (found by fuzz_study_report).
    CHECK(err("P01,,likert,after_condition,liked,4,1\n") ==
          "Q: line 2, column condition: ''; allowed the condition, with occasion after_condition");
    CHECK(err("P01,,text,after_condition,remarks,fine,1\n") ==
          "Q: line 2, column condition: ''; allowed the condition, with occasion after_condition");
    CHECK(test_support::errorOf([] {
              study::ParticipantResults p = participant();
              study::parseQuestionnaires("participant,item\n", "Q", p);
          }).find("Q: line 1: not the header of questionnaires.csv") != std::string::npos);
}

TEST_CASE("session folders: different designs and a participant twice are refused") {
    // Kept to the end of the process, so that no later test reuses its folders.
    static test_support::TempDir dir("report_read");
    const auto session = [&](const std::string& name, const std::string& participant, const std::string& sha) {
        std::filesystem::create_directories(dir.path / name);
        dir.write(name + "/study.json", "{\"design\": \"/d.json\", \"design_sha256\": \"" + sha +
                                            "\", \"participant\": \"" + participant +
                                            "\", \"condition_order\": [\"b\", \"a\"], \"order\": []}");
        std::string rows = kRows;
        for (std::size_t at = rows.find("P01"); at != std::string::npos; at = rows.find("P01", at + 1))
            rows.replace(at, 3, participant);
        dir.write(name + "/trials.csv", kHeader + rows);
        return dir.path / name;
    };
    const auto a = session("A", "P01", "aaaa");
    const auto b = session("B", "P02", "aaaa");
    const study::StudyResults ok = study::readStudyResults(study::findSessionFolders({dir.path}));
    REQUIRE(ok.participants.size() == 2);
    CHECK(ok.conditions == std::vector<std::string>{"a", "b"});
    CHECK(ok.participants[1].participant == "P02");
    CHECK(ok.participants[1].trials.size() == 3);
    CHECK(!ok.participants[0].questionnaires);

    const auto c = session("C", "P03", "bbbb");
    CHECK(test_support::errorOf([&] { study::readStudyResults({a, c}); }) ==
          "study report: " + (c / "study.json").string() + ": design SHA-256 bbbb differs from " +
              (a / "study.json").string() + "'s aaaa; allowed: the sessions of one design");
    const auto d = session("D", "P01", "aaaa");
    CHECK(test_support::errorOf([&] { study::readStudyResults({a, b, d}); }) ==
          "study report: " + (d / "study.json").string() + ": participant P01 again (also in " + a.string() +
              "); allowed: each participant once");
    dir.write("D/trials.csv", kHeader + "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P09,a,,1\n");
    CHECK(test_support::errorOf([&] { study::readStudyResults({d}); }) ==
          "study report: " + (d / "trials.csv").string() +
              ": line 2, column participant: 'P09'; allowed 'P01', as "
              "study.json");
    // The participant's id goes into every table: the design's rules, checked on reading.
    for (const std::string bad : {"=1+2", "<img src=x onerror=alert(1)>", "-P1", ""}) {
        CAPTURE(bad);
        dir.write("D/study.json", "{\"design\": \"/d.json\", \"design_sha256\": \"aaaa\", \"participant\": \"" + bad +
                                      "\", \"condition_order\": [\"b\", \"a\"], \"order\": []}");
        CHECK(test_support::errorOf([&] { study::readStudyResults({d}); }) ==
              "study report: " + (d / "study.json").string() + ": participant '" + bad +
                  "' is not an id of 1 to 40 letters, digits, '_', '-' or '.', not starting with '-'; allowed: the "
                  "folder of a `ladarvr study DESIGN.json --participant P` session");
    }
    dir.write("D/study.json",
              "{\"design\": \"/d.json\", \"design_sha256\": \"aaaa\", \"participant\": \"P01\", "
              "\"condition_order\": [\"b\", \"@a\"], \"order\": []}");
    CHECK(test_support::errorOf([&] { study::readStudyResults({d}); }).find("condition_order holds '@a'; allowed") !=
          std::string::npos);
    dir.write("D/study.json", "{\"plan\": \"/p.json\", \"order\": [0]}");
    CHECK(test_support::errorOf([&] { study::readStudyResults({d}); }).find("not a design's session") !=
          std::string::npos);
    CHECK(test_support::errorOf([&] {
              study::findSessionFolders({dir.path / "A" / "trials.csv"});
          }).find("not a folder") != std::string::npos);
    std::filesystem::create_directories(dir.path / "empty");
    CHECK(test_support::errorOf([&] {
              study::findSessionFolders({dir.path / "empty"});
          }).find("no study.json in it nor in a folder one level below") != std::string::npos);
}

TEST_CASE("session folders: empty and partial sessions are told apart, empty ones left out") {
    static test_support::TempDir dir("report_sessions");
    // A session of 8 planned trials (study.json's order) with `rows` of trials.csv, or
    // without trials.csv when `rows` is empty and `with_trials` false.
    const auto session = [&](const std::string& name, const std::string& participant, const std::string& rows,
                             bool with_trials = true) {
        std::filesystem::create_directories(dir.path / name);
        dir.write(name + "/study.json", "{\"design\": \"/d.json\", \"design_sha256\": \"aaaa\", \"participant\": \"" +
                                            participant +
                                            "\", \"condition_order\": [\"a\", \"b\"], "
                                            "\"order\": [0, 1, 2, 3, 4, 5, 6, 7]}");
        if (with_trials) {
            std::string text = rows;
            for (std::size_t at = text.find("P01"); at != std::string::npos; at = text.find("P01", at + 1))
                text.replace(at, 3, participant);
            dir.write(name + "/trials.csv", kHeader + text);
        }
        return dir.path / name;
    };
    const std::string practice = "1,demo.pcd,confirm,0,0,1,0.2,1,1.5,2.5,1,0,0,,P01,a,,1\n";
    const std::string two =
        "1,demo.pcd,confirm,5,5,1,7.1,0,1.0,3.0,2,1,0.5,0.4,P01,a,first,0\n"
        "2,demo.pcd,no_target,,,,,,,4.0,0,0,0,,P01,b,first,0\n";
    std::string eight;
    for (int i = 1; i <= 8; ++i)
        eight += std::to_string(i) + ",demo.pcd,no_target,,,,,,,4.0,0,0,0,,P01," + (i % 2 ? "a" : "b") + ",first,0\n";
    const auto complete = session("complete", "P01", eight);
    const auto partial = session("partial", "P02", two);
    const auto bare = session("bare", "P03", "", false);  // study.json only
    const auto header_only = session("header", "P04", "");
    const auto practice_only = session("practice", "P05", practice);
    std::string with_practice = practice + two;
    with_practice.replace(with_practice.find("\n2,"), 3, "\n3,");
    with_practice.replace(with_practice.find("\n1,demo.pcd,confirm,5"), 3, "\n2,");
    const auto mixed = session("mixed", "P06", with_practice);

    const study::StudyResults r = study::readStudyResults({complete, partial, bare, header_only, practice_only, mixed});
    REQUIRE(r.participants.size() == 3);  // P01, P02, P06: the empty sessions are not participants
    CHECK(r.participants[0].participant == "P01");
    CHECK(r.participants[1].participant == "P02");
    CHECK(r.participants[2].participant == "P06");
    CHECK(r.participants[1].trials_planned == 8);
    REQUIRE(r.sessions.size() == 6);
    CHECK(r.sessions[0].state == study::SessionState::Complete);
    CHECK(r.sessions[1].state == study::SessionState::Partial);
    CHECK(r.sessions[1].trials_recorded == 2);
    CHECK(r.sessions[2].state == study::SessionState::Empty);
    CHECK(r.sessions[3].state == study::SessionState::Empty);
    CHECK(r.sessions[4].state == study::SessionState::Empty);
    CHECK(r.sessions[5].state == study::SessionState::Partial);
    CHECK(study::countSessions(r, study::SessionState::Complete) == 1);
    CHECK(study::countSessions(r, study::SessionState::Partial) == 2);
    CHECK(study::countSessions(r, study::SessionState::Empty) == 3);
    const std::vector<std::string> warnings = study::sessionWarnings(r);
    REQUIRE(warnings.size() == 5);
    CHECK(warnings[0] == "study report: " + partial.string() + ": 2 of 8 trials recorded; its figures count those 2");
    CHECK(warnings[1] == "study report: " + bare.string() + ": no trial recorded; left out");
    CHECK(warnings[2] == "study report: " + header_only.string() + ": no trial recorded; left out");
    CHECK(warnings[3] ==
          "study report: " + practice_only.string() + ": 1 of 8 trials recorded, practice only; left out");
    CHECK(warnings[4] ==
          "study report: " + mixed.string() + ": 3 of 8 trials recorded (1 practice); its figures count the other 2");

    // The figures count the participants with trials; the JSON lists every session.
    const study::ReportFigures f = study::computeFigures(r);
    CHECK(f.participants.size() == 3);
    std::map<std::string, std::string> files;
    for (auto& [name, content] : study::reportFiles(r, f)) files[name] = content;
    CHECK(files.at("figures.json").find("\"complete\": 1,\n  \"partial\": 2,\n  \"empty\": 3") != std::string::npos);
    CHECK(files.at("participants.csv").find(",partial,2,8\n") != std::string::npos);
    CHECK(files.at("index.html").find("Sessions: 1 complete, 2 partial") != std::string::npos);
    CHECK(files.at("index.html").find("<tr><td>P03</td><td>empty</td><td>0</td><td>8</td><td>left out</td></tr>") !=
          std::string::npos);

    // Nothing to count anywhere: refused rather than a report of empty figures.
    CHECK(test_support::errorOf([&] { study::readStudyResults({bare, header_only, practice_only}); }) ==
          "study report: none of the 3 session(s) recorded a trial that is not practice; allowed: at least one "
          "session with a trial to count");
    dir.write("bare/study.json",
              "{\"design\": \"/d.json\", \"design_sha256\": \"aaaa\", \"participant\": \"P03\", "
              "\"condition_order\": [\"a\", \"b\"], \"order\": 8}");
    CHECK(test_support::errorOf([&] { study::readStudyResults({bare}); }) ==
          "study report: " + (bare / "study.json").string() +
              ": order holds a number; allowed: the list of the session's trials");
}

TEST_CASE("the report's fuzz seeds: each file read, or refused in one line naming it, as fuzz_study_report expects") {
    // fuzz/seeds/study_report (fuzz/make_seeds.py): the first byte chooses the file, 0 for
    // trials.csv and 1 for questionnaires.csv; what a session writes, and refused rows.
    const std::filesystem::path seeds = std::filesystem::path(test_support::fuzzSeedsDir()) / "study_report";
    int read = 0, refused = 0;
    for (const auto& entry : std::filesystem::directory_iterator(seeds)) {
        const std::string bytes = test_support::slurp(entry.path());
        REQUIRE_FALSE(bytes.empty());
        const bool questionnaires = (bytes[0] & 1) != 0;
        const std::string text = bytes.substr(1);
        CAPTURE(entry.path().string());
        try {
            if (questionnaires) {
                study::ParticipantResults p = participant();
                p.participant = "P1";
                study::parseQuestionnaires(text, "questionnaires.csv", p);
                CHECK(p.ssq_pre);
                CHECK(p.ssq_post);
                CHECK(p.tlx_raw.size() == 1);
                CHECK(p.likert.size() == 3);
            } else {
                const std::size_t rows = study::parseReportTrials(text, "trials.csv").size();
                CHECK(rows > 0);
            }
            ++read;
        } catch (const core::Error& e) {
            const std::string m = e.what();
            CHECK(m.rfind(questionnaires ? "questionnaires.csv: line " : "trials.csv: line ", 0) == 0);
            CHECK(m.find('\n') == std::string::npos);
            CHECK(entry.path().filename().string().find("errors") != std::string::npos);
            ++refused;
        }
    }
    CHECK(read >= 3);
    CHECK(refused >= 3);
}
