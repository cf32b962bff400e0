// Tests of study/src/report_figures.cpp, report_plot.cpp and report_write.cpp: the
// per-participant cells (practice left out, quits not scored, false confirmations), the
// conditions' summaries and tests, the clouds, the plots decoded as PNG, and the folder.
// Also report_html.cpp: text from the inputs escaped in index.html.
#include <study/report.hpp>

#include <png_decode.hpp>
#include <test_files.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <map>

namespace {
study::ReportTrial trial(const std::string& condition, study::TrialDecision d, std::optional<int> hit, double time_s,
                         bool practice = false, const std::string& cloud = "c.pcd") {
    study::ReportTrial t;
    t.cloud = cloud;
    t.condition = condition;
    t.decision = d;
    t.hit = hit;
    t.time_to_decision_s = time_s;
    t.practice = practice;
    t.block = practice ? "" : "b1";
    if (hit) t.target_distance_m = *hit ? 0.5 : 9.5;
    return t;
}
using D = study::TrialDecision;

// Three participants, conditions a and b; participant i's times in a are 10 + i, in b 20 + 2i.
study::StudyResults twoConditions() {
    study::StudyResults r;
    r.conditions = {"a", "b"};
    for (int i = 0; i < 3; ++i) {
        study::ParticipantResults p;
        p.participant = "P" + std::to_string(i);
        p.condition_order = {"a", "b"};
        p.trials = {trial("a", D::Confirm, 1, 99.0, true),  // practice: left out
                    trial("a", D::Confirm, 1, 10 + i),
                    trial("a", D::Confirm, 0, 10 + i),
                    trial("a", D::Quit, 0, 50.0),  // quit: not scored, not decided
                    trial("b", D::Confirm, 1, 20 + 2 * i, false, "d.pcd"),
                    trial("b", D::Timeout, 0, 120.0),
                    trial("b", D::NoTarget, std::nullopt, 20 + 2 * i, false, "d.pcd")};
        p.trials[5].target_distance_m.reset();
        p.trials[2].visibility_metric = 0.25;
        p.tlx_raw["a"] = 10.0 * (i + 1);
        p.tlx_raw["b"] = 20.0 * (i + 1);
        study::SsqScores pre, post;
        pre.total = 3.74 * i;
        post.total = 3.74 * (2 * i + 1);
        p.ssq_pre = pre;
        p.ssq_post = post;
        r.participants.push_back(p);
    }
    return r;
}
}  // namespace

TEST_CASE("figures: cells leave practice out, score no quit, count false confirmations") {
    const study::ReportFigures f = study::computeFigures(twoConditions());
    REQUIRE(f.cells.size() == 3);
    const study::CellFigures& a = f.cells[1][0];
    CHECK(a.trials == 3);
    CHECK(a.scored == 2);
    CHECK(a.hits == 1);
    CHECK(a.decided == 2);
    CHECK(a.hit_rate == doctest::Approx(0.5));
    CHECK(a.false_confirmations == 1.0);
    CHECK(a.time_to_decision_s == doctest::Approx(11.0));
    CHECK(a.target_distance_m == doctest::Approx((0.5 + 9.5 + 9.5) / 3.0));
    CHECK(a.tlx_raw == 20.0);
    const study::CellFigures& b = f.cells[2][1];
    CHECK(b.scored == 2);  // the confirm and the timeout; the no_target trial has no hit field
    CHECK(b.hit_rate == doctest::Approx(0.5));
    CHECK(b.false_confirmations == 0.0);
    CHECK(b.time_to_decision_s == doctest::Approx(24.0));  // timeout left out
    CHECK(f.participant_totals[0].trials == 6);

    // Conditions' summaries over the three participants: times 10, 11, 12 in a.
    const study::stats::Summary& ta = f.by_condition.at("time_to_decision_s")[0];
    CHECK(ta.n == 3);
    CHECK(ta.mean == doctest::Approx(11.0));
    CHECK(ta.ci95_high - ta.mean == doctest::Approx(4.302652729749464 * 1.0 / std::sqrt(3.0)).epsilon(1e-9));
    // Two conditions: Wilcoxon signed-rank; every participant slower in b, n 3, p 2/8.
    const study::stats::TestResult& tt = f.condition_tests.at("time_to_decision_s");
    CHECK(tt.test == "wilcoxon_signed_rank");
    CHECK(tt.n == 3);
    CHECK(tt.p == doctest::Approx(0.25));
    // Hit rates equal in both conditions: every difference is zero, nothing to test.
    CHECK(f.condition_tests.at("hit_rate").n == 3);
    CHECK(std::isnan(f.condition_tests.at("hit_rate").p));
    // SSQ total: post - pre = 3.74 (i + 1).
    CHECK(f.ssq_summary.at("total")[2].mean == doctest::Approx(3.74 * 2.0));
    CHECK(f.ssq_tests.at("total").p == doctest::Approx(0.25));
    // Clouds: c.pcd (a's trials) and d.pcd.
    REQUIRE(f.clouds.size() == 2);
    CHECK(f.clouds[0].cloud == "c.pcd");
    CHECK(f.clouds[0].all.trials == 9 + 3);  // a's three per participant, b's timeout
    CHECK(f.clouds[0].visibility_metric == doctest::Approx(0.25));
    CHECK(std::isnan(f.clouds[1].visibility_metric));
}

TEST_CASE("figures: three conditions take the Friedman test over complete participants") {
    study::StudyResults r = twoConditions();
    r.conditions = {"a", "b", "c"};
    for (std::size_t i = 0; i < r.participants.size(); ++i) {
        r.participants[i].condition_order = {"a", "b", "c"};
        r.participants[i].trials.push_back(trial("c", D::Confirm, 1, 30.0 + double(i)));
    }
    r.participants[2].trials.back().decision = D::Quit;  // P2 has no decided trial in c
    const study::ReportFigures f = study::computeFigures(r);
    const study::stats::TestResult& t = f.condition_tests.at("time_to_decision_s");
    CHECK(t.test == "friedman");
    CHECK(t.n == 2);
    CHECK(t.k == 3);
    CHECK(t.statistic == doctest::Approx(4.0));    // both participants order a < b < c
    CHECK(t.effect_size == doctest::Approx(1.0));  // Kendall's W: complete agreement
    // Exactly: 6 of the 6^2 arrangements have both rows in one order (chi-square: e^-2).
    CHECK(t.p == doctest::Approx(1.0 / 6.0));
    CHECK(t.p_method == "exact");
    CHECK(f.by_condition.at("time_to_decision_s")[2].n == 2);
}

TEST_CASE("report files: the tables, plots that decode, and the folder written whole") {
    const study::StudyResults r = twoConditions();
    const study::ReportFigures f = study::computeFigures(r);
    std::map<std::string, std::string> files;
    for (auto& [name, content] : study::reportFiles(r, f)) {
        CHECK(study::isReportFile(name));
        files[name] = content;
    }
    // The columns added after the first reports come last: the older ones stay where they were.
    CHECK(files.at("cells.csv")
              .rfind("participant,condition,trials,scored,hits,decided,hit_rate,false_confirmations,"
                     "time_to_decision_s,target_distance_m,tlx_raw,absent,correct_rejections,"
                     "correct_rejection_rate\n",
                     0) == 0);
    CHECK(files.at("cells.csv").find("\nP1,a,3,2,1,2,0.5,1,11,6.5,20,0,0,\n") != std::string::npos);
    CHECK(files.at("cells.csv").find("\nP1,b,3,2,1,2,0.5,0,22,0.5,40,1,1,1\n") != std::string::npos);
    CHECK(files.at("conditions.csv").rfind("measure,condition,n,mean,sd,ci95_low,ci95_high,median,q1,q3\n", 0) == 0);
    // Times in a: 10, 11, 12 (sd 1); hit rates 0.5 for all three (sd 0, no residue).
    CHECK(files.at("conditions.csv").find("\ntime_to_decision_s,a,3,11,1,") != std::string::npos);
    CHECK(files.at("conditions.csv").find("\nhit_rate,a,3,0.5,0,0.5,0.5,0.5,0.5,0.5\n") != std::string::npos);
    CHECK(files.at("tests.csv").rfind("measure,test,n,k,statistic,df,p,z,effect,effect_size,p_method\n", 0) == 0);
    // Every participant slower in b: W+ = 6 of 6, Z = 3 / sqrt(3.5), r = 1, p exact 2/8.
    CHECK(files.at("tests.csv")
              .find("\ntime_to_decision_s,wilcoxon_signed_rank,3,2,0,,0.25,1.60356745,"
                    "rank_biserial_r,1,exact\n") != std::string::npos);
    CHECK(files.at("tests.csv").find("\nhit_rate,wilcoxon_signed_rank,3,2,,,,,rank_biserial_r,,\n") !=
          std::string::npos);
    CHECK(files.at("participants.csv").find("\nP0,6,4,2,4,0.5,1,") != std::string::npos);
    CHECK(files.at("participants.csv")
              .find(",questionnaires,absent,correct_rejections,correct_rejection_rate,"
                    "session,trials_recorded,trials_planned\n") != std::string::npos);
    CHECK(files.at("clouds.csv").find("\nd.pcd,6,3,3,6,1,0,") != std::string::npos);
    CHECK(files.at("likert.csv") ==
          "item,occasion,condition,n,median,q1,q3,mean,count_1,count_2,count_3,count_4,count_5,count_6,count_7,"
          "count_8,count_9,count_10,count_11\n");
    for (const char* png : {"time_to_decision.png", "hit_rate.png", "cloud_difficulty.png"}) {
        CAPTURE(png);
        const test_support::DecodedPng d = test_support::decodePng(files.at(png));
        REQUIRE(d.width == 720);
        CHECK(d.height == 420);
        // Dark text and axes on the white page: a good share of pixels are neither white nor empty.
        std::size_t dark = 0;
        for (std::size_t i = 0; i + 2 < d.pixels.size(); i += std::size_t(d.channels))
            if (d.pixels[i] < 100 && d.pixels[i + 1] < 100 && d.pixels[i + 2] < 100) ++dark;
        CHECK(dark > 1000);
    }
    CHECK(files.at("index.html").find("<img src=\"hit_rate.png\"") != std::string::npos);
    CHECK(files.at("index.html").find("http") == std::string::npos);  // nothing fetched

    test_support::TempDir dir("report_write");
    dir.write("notes.txt", "mine");
    CHECK(test_support::errorOf([&] { study::writeStudyReport(r, dir.path); }).find("notes.txt") != std::string::npos);
    study::writeStudyReport(r, dir.path / "report");
    study::writeStudyReport(r, dir.path / "report");  // an earlier report is replaced whole
    CHECK(test_support::slurp(dir.path / "report" / "cells.csv") == files.at("cells.csv"));
    CHECK(dir.entries() == 2);  // notes.txt and report: no temporary left
}

TEST_CASE("figures: target-absent trials give the correct-rejection rate") {
    study::StudyResults r = twoConditions();
    // P0 confirms something on b's target-absent cloud once more: 1 of 2 correct in b.
    r.participants[0].trials.push_back(trial("b", D::Confirm, std::nullopt, 15.0, false, "d.pcd"));
    // A quit on a target-absent cloud is the experimenter's: not counted.
    r.participants[1].trials.push_back(trial("b", D::Quit, std::nullopt, 15.0, false, "d.pcd"));
    const study::ReportFigures f = study::computeFigures(r);
    CHECK(f.cells[0][1].absent == 2);
    CHECK(f.cells[0][1].correct_rejections == 1);
    CHECK(f.cells[0][1].correct_rejection_rate == doctest::Approx(0.5));
    CHECK(f.cells[0][1].false_confirmations == 1.0);  // the confirm on a cloud without a target
    CHECK(f.cells[1][1].absent == 1);
    CHECK(f.cells[1][1].correct_rejection_rate == 1.0);
    CHECK(std::isnan(f.cells[0][0].correct_rejection_rate));  // a has no target-absent trial
    const study::stats::Summary& b = f.by_condition.at("correct_rejection_rate")[1];
    CHECK(b.n == 3);
    CHECK(b.mean == doctest::Approx(2.5 / 3.0));
    CHECK(b.median == 1.0);
    CHECK(f.clouds[1].all.absent == 4);
    CHECK(f.clouds[1].all.correct_rejections == 3);
    // Only b has target-absent trials: no participant has the rate in every condition.
    CHECK(f.condition_tests.at("correct_rejection_rate").n == 0);
}

TEST_CASE("figures: the Likert answers per question and condition") {
    study::StudyResults r = twoConditions();
    const int ease_a[] = {2, 5, 5}, ease_b[] = {4, 4, 7};
    for (std::size_t i = 0; i < 3; ++i) {
        r.participants[i].likert[{"ease", "after_condition", "a"}] = ease_a[i];
        r.participants[i].likert[{"ease", "after_condition", "b"}] = ease_b[i];
    }
    r.participants[0].likert[{"overall", "post", ""}] = 6;
    const study::ReportFigures f = study::computeFigures(r);
    REQUIRE(f.likert.size() == 3);
    const study::LikertFigures& a = f.likert[0];
    CHECK(a.question.item == "ease");
    CHECK(a.question.condition == "a");
    CHECK(a.summary.n == 3);
    CHECK(a.counts[2] == 1);
    CHECK(a.counts[5] == 2);
    CHECK(a.counts[4] == 0);
    CHECK(a.summary.median == 5.0);
    CHECK(a.summary.q1 == 3.5);
    CHECK(a.summary.q3 == 5.0);
    CHECK(f.likert[1].question.condition == "b");
    CHECK(f.likert[1].summary.median == 4.0);
    CHECK(f.likert[2].question.item == "overall");
    CHECK(f.likert[2].counts[6] == 1);
    std::map<std::string, std::string> files;
    for (auto& [name, content] : study::reportTables(r, f)) files[name] = content;
    CHECK(files.at("likert.csv").find("\nease,after_condition,a,3,5,3.5,5,4,0,1,0,0,2,0,0,0,0,0,0\n") !=
          std::string::npos);
    CHECK(files.at("likert.csv").find("\noverall,post,,1,6,6,6,6,0,0,0,0,0,1,0,0,0,0,0\n") != std::string::npos);
    const std::string html = study::reportHtml(r, f);
    CHECK(html.find("<h2>Likert items</h2>") != std::string::npos);
    CHECK(html.find("<tr><td>ease</td><td>after_condition</td><td>a</td><td>3</td><td>5 (3.5&ndash;5)</td>"
                    "<td>0</td><td>1</td><td>0</td><td>0</td><td>2</td><td>0</td><td>0</td></tr>") !=
          std::string::npos);
}

TEST_CASE("report html: medians, effect sizes, how p was found, rounding residue shown as 0") {
    const study::StudyResults r = twoConditions();
    const study::ReportFigures f = study::computeFigures(r);
    const std::string html = study::reportHtml(r, f);
    CHECK(html.find("<th>Z</th><th>effect size</th><th>p from</th>") != std::string::npos);
    // Time to decision: a 10, 11, 12; b 20, 22, 24; the test exact, r 1.
    CHECK(html.find("<td>11 <span class=ci>") != std::string::npos);
    CHECK(html.find("median 11 (10.5&ndash;11.5)") != std::string::npos);
    CHECK(html.find("<td>wilcoxon_signed_rank</td><td>3</td><td>0</td><td>&ndash;</td><td>0.2500</td><td>1.6</td>"
                    "<td>r 1</td><td>exact</td>") != std::string::npos);
    CHECK(html.find("e-1") == std::string::npos);  // no 7.1e-15 anywhere
    CHECK(html.find("Sessions: 0 complete") != std::string::npos);
}

TEST_CASE("report html: names show controls and bidirectional overrides as escapes") {
    study::StudyResults r = twoConditions();
    // A cloud name with RIGHT-TO-LEFT OVERRIDE (U+202E), a C1 control (U+0085) and markup,
    // and a participant id with LEFT-TO-RIGHT ISOLATE (U+2066).
    for (study::ParticipantResults& p : r.participants) p.trials[1].cloud = "gpj.\xE2\x80\xAEx\xC2\x85<b>.pcd";
    r.participants[0].participant = std::string("P\xE2\x81\xA6") + "0";
    const std::string html = study::reportHtml(r, study::computeFigures(r));
    CHECK(html.find("\xE2\x80\xAE") == std::string::npos);
    CHECK(html.find("\xE2\x81\xA6") == std::string::npos);
    CHECK(html.find("\xC2\x85") == std::string::npos);
    CHECK(html.find("<td>gpj.\\u202ex\\u0085&lt;b&gt;.pcd</td>") != std::string::npos);
    CHECK(html.find("<td>P\\u20660</td>") != std::string::npos);
}
