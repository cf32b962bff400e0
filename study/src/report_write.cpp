// study/src/report_write.cpp: the study report's folder (study/report.hpp): the tables as
// CSV (columns added after the first reports come last, so a reader by position finds the
// older ones where they were), every figure in figures.json (report_json.cpp), the plots
// and index.html, made in memory and written as one folder through
// platform::writeFolderAtomic, so a reader sees the previous report or this one, never a
// mix.
#include <study/report.hpp>

#include "report_format.hpp"
#include "report_plot.hpp"

#include <study/csv_cell.hpp>

#include <platform/output_folder.hpp>

#include <cmath>
#include <cstdio>
#include <set>

namespace study {

namespace {
constexpr std::array<std::string_view, 3> kOccasions{"pre", "post", "difference"};

using detail::csvNumber;

std::string cellCsv(const CellFigures& c) {
    return std::to_string(c.trials) + "," + std::to_string(c.scored) + "," + std::to_string(c.hits) + "," +
           std::to_string(c.decided) + "," + csvNumber(c.hit_rate) + "," + csvNumber(c.false_confirmations) + "," +
           csvNumber(c.time_to_decision_s) + "," + csvNumber(c.target_distance_m);
}
constexpr const char* kCellColumns =
    "trials,scored,hits,decided,hit_rate,false_confirmations,time_to_decision_s,target_distance_m";
// The target-absent trials' columns, after each table's older ones.
std::string correctRejectionsCsv(const CellFigures& c) {
    return std::to_string(c.absent) + "," + std::to_string(c.correct_rejections) + "," +
           csvNumber(c.correct_rejection_rate);
}
constexpr const char* kCorrectRejectionColumns = "absent,correct_rejections,correct_rejection_rate";

std::string summaryCsv(const stats::Summary& s) {
    return std::to_string(s.n) + "," + csvNumber(s.mean) + "," + csvNumber(s.sd) + "," + csvNumber(s.ci95_low) + "," +
           csvNumber(s.ci95_high) + "," + csvNumber(s.median) + "," + csvNumber(s.q1) + "," + csvNumber(s.q3);
}
constexpr const char* kSummaryColumns = "n,mean,sd,ci95_low,ci95_high,median,q1,q3";

std::string testCsv(const stats::TestResult& t) {
    return csvCell(t.test) + "," + std::to_string(t.n) + "," + std::to_string(t.k) + "," + csvNumber(t.statistic) +
           "," + csvNumber(t.df) + "," + detail::csvP(t.p) + "," + csvNumber(t.z) + "," + csvCell(t.effect) + "," +
           csvNumber(t.effect_size) + "," + csvCell(t.p_method);
}

std::string participantsCsv(const StudyResults& results, const ReportFigures& f) {
    std::string out = std::string("participant,") + kCellColumns + ",questionnaires," + kCorrectRejectionColumns +
                      ",session,trials_recorded,trials_planned\n";
    for (std::size_t i = 0; i < f.participants.size(); ++i) {
        const SessionRecord session = sessionRecord(results.participants[i]);
        out += csvCell(f.participants[i]) + "," + cellCsv(f.participant_totals[i]) + "," +
               (results.participants[i].questionnaires ? "1" : "0") + "," +
               correctRejectionsCsv(f.participant_totals[i]) + "," + csvCell(sessionStateName(session.state)) + "," +
               std::to_string(session.trials_recorded) + "," + std::to_string(session.trials_planned) + "\n";
    }
    return out;
}

std::string ssqCsv(const ReportFigures& f) {
    std::string ssq = "participant,occasion,nausea,oculomotor,disorientation,total\n";
    for (std::size_t i = 0; i < f.participants.size(); ++i) {
        const auto row = [&](std::string_view occasion, auto value) {
            ssq += csvCell(f.participants[i]) + "," + csvCell(occasion);
            for (const std::string_view name : ssqScoreNames()) ssq += "," + csvNumber(value(name));
            ssq += "\n";
        };
        const std::optional<SsqScores>&pre = f.ssq_pre[i], &post = f.ssq_post[i];
        if (pre) row("pre", [&](std::string_view n) { return ssqScore(*pre, n); });
        if (post) row("post", [&](std::string_view n) { return ssqScore(*post, n); });
        if (pre && post) row("difference", [&](std::string_view n) { return ssqScore(*post, n) - ssqScore(*pre, n); });
    }
    return ssq;
}

std::string likertCsv(const ReportFigures& f) {
    std::string out = "item,occasion,condition,n,median,q1,q3,mean";
    for (int r = 1; r <= kMaxLikertRating; ++r) out += ",count_" + std::to_string(r);
    out += "\n";
    for (const LikertFigures& l : f.likert) {
        out += csvCell(l.question.item) + "," + csvCell(l.question.occasion) + "," + csvCell(l.question.condition) +
               "," + std::to_string(l.summary.n) + "," + csvNumber(l.summary.median) + "," + csvNumber(l.summary.q1) +
               "," + csvNumber(l.summary.q3) + "," + csvNumber(l.summary.mean);
        for (int r = 1; r <= kMaxLikertRating; ++r) out += "," + std::to_string(l.counts[std::size_t(r)]);
        out += "\n";
    }
    return out;
}
}  // namespace

std::vector<std::pair<std::string, std::string>> reportTables(const StudyResults& results, const ReportFigures& f) {
    std::vector<std::pair<std::string, std::string>> out;
    const std::size_t k = f.conditions.size();

    std::string conditions = std::string("measure,condition,") + kSummaryColumns + "\n";
    for (const std::string_view measure : reportMeasures())
        for (std::size_t j = 0; j < k; ++j)
            conditions += csvCell(measure) + "," + csvCell(f.conditions[j]) + "," +
                          summaryCsv(f.by_condition.find(measure)->second[j]) + "\n";
    out.emplace_back("conditions.csv", conditions);

    std::string cells =
        std::string("participant,condition,") + kCellColumns + ",tlx_raw," + kCorrectRejectionColumns + "\n";
    for (std::size_t i = 0; i < f.participants.size(); ++i)
        for (std::size_t j = 0; j < k; ++j)
            cells += csvCell(f.participants[i]) + "," + csvCell(f.conditions[j]) + "," + cellCsv(f.cells[i][j]) + "," +
                     csvNumber(f.cells[i][j].tlx_raw) + "," + correctRejectionsCsv(f.cells[i][j]) + "\n";
    out.emplace_back("cells.csv", cells);
    out.emplace_back("participants.csv", participantsCsv(results, f));
    out.emplace_back("ssq.csv", ssqCsv(f));

    std::string ssq_summary = std::string("score,occasion,") + kSummaryColumns + "\n";
    for (const std::string_view name : ssqScoreNames())
        for (std::size_t o = 0; o < kOccasions.size(); ++o)
            ssq_summary += csvCell(name) + "," + csvCell(kOccasions[o]) + "," +
                           summaryCsv(f.ssq_summary.find(name)->second[o]) + "\n";
    out.emplace_back("ssq_summary.csv", ssq_summary);

    std::string tests = "measure,test,n,k,statistic,df,p,z,effect,effect_size,p_method\n";
    for (const std::string_view measure : reportMeasures())
        if (const auto it = f.condition_tests.find(measure); it != f.condition_tests.end())
            tests += csvCell(measure) + "," + testCsv(it->second) + "\n";
    for (const std::string_view name : ssqScoreNames())
        tests +=
            csvCell("ssq_" + std::string(name) + "_post_vs_pre") + "," + testCsv(f.ssq_tests.find(name)->second) + "\n";
    out.emplace_back("tests.csv", tests);

    std::string clouds = std::string("cloud,") + kCellColumns + ",visibility_metric," + kCorrectRejectionColumns + "\n";
    for (const CloudFigures& c : f.clouds)
        clouds += csvCell(c.cloud) + "," + cellCsv(c.all) + "," + csvNumber(c.visibility_metric) + "," +
                  correctRejectionsCsv(c.all) + "\n";
    out.emplace_back("clouds.csv", clouds);
    out.emplace_back("likert.csv", likertCsv(f));
    out.emplace_back("figures.json", detail::figuresJson(results, f));
    return out;
}

std::vector<std::pair<std::string, std::string>> reportFiles(const StudyResults& results, const ReportFigures& f) {
    std::vector<std::pair<std::string, std::string>> files = reportTables(results, f);
    const std::size_t k = f.conditions.size();
    const auto values = [&](std::string_view measure) {
        std::vector<std::vector<double>> v;
        for (const auto& row : f.cells) {
            std::vector<double> r;
            for (std::size_t c = 0; c < k; ++c) r.push_back(measureValue(row[c], measure));
            v.push_back(std::move(r));
        }
        return v;
    };
    files.emplace_back("time_to_decision.png",
                       detail::conditionPlotPng("Time to decision per condition", "mean seconds (decided trials)",
                                                f.conditions, values("time_to_decision_s"),
                                                f.by_condition.find("time_to_decision_s")->second, false));
    files.emplace_back("hit_rate.png",
                       detail::conditionPlotPng("Hit rate per condition", "hits / scored trials", f.conditions,
                                                values("hit_rate"), f.by_condition.find("hit_rate")->second, true));
    files.emplace_back("cloud_difficulty.png", detail::cloudPlotPng(f.clouds));
    files.emplace_back("index.html", reportHtml(results, f));
    return files;
}

bool isReportFile(const std::string& name) {
    static const std::set<std::string, std::less<>> kNames{
        "conditions.csv", "cells.csv",    "participants.csv",     "ssq.csv",      "ssq_summary.csv",      "tests.csv",
        "clouds.csv",     "figures.json", "time_to_decision.png", "hit_rate.png", "cloud_difficulty.png", "index.html",
        "likert.csv"};
    return kNames.contains(name);
}

void writeStudyReport(const StudyResults& results, const std::filesystem::path& out) {
    const ReportFigures figures = computeFigures(results);
    platform::writeFolderAtomic(out, reportFiles(results, figures), isReportFile);
}

}  // namespace study
