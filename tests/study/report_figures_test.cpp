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
    CHECK(t.statistic == doctest::Approx(4.0));  // both participants order a < b < c
    CHECK(t.p == doctest::Approx(std::exp(-2.0)));
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
    CHECK(files.at("cells.csv").find("P1,a,3,2,1,2,0.5,1,11,6.5,20\n") != std::string::npos);
    CHECK(files.at("tests.csv").find("time_to_decision_s,wilcoxon_signed_rank,3,2,0,,0.25\n") != std::string::npos);
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
