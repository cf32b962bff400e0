// study/src/report_html.cpp: the report's index.html (study/report.hpp): one page with the
// tables and the plots beside it, its style inline and nothing fetched from elsewhere, so
// it reads the same offline; every text from the inputs is escaped, controls included.
#include "report_format.hpp"

#include <study/csv_cell.hpp>
#include <study/report.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace study {

namespace {
// Text from the inputs as HTML shows it: controls and bidirectional overrides written as
// visible escapes (escapeControlText, as in the CSV cells), so a name cannot reorder the
// page, then the HTML-special characters as entities.
std::string esc(std::string_view s) {
    std::string out;
    for (const char c : escapeControlText(s)) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

// A figure with three significant digits (0 within detail::kZeroBelow of it); a dash
// where it does not apply.
std::string fmt(double v, const char* format = "%.3g") {
    if (std::isnan(v)) return "&ndash;";
    char buf[40];
    std::snprintf(buf, sizeof buf, format, detail::shownValue(v));
    return buf;
}

// A p value with four decimals, or "< 0.0001" below what four decimals show.
std::string fmtP(double p) {
    if (!std::isnan(p) && p < 0.0001) return "&lt;&nbsp;0.0001";
    return fmt(p, "%.4f");
}

std::string summaryCell(const stats::Summary& s) {
    if (s.n == 0) return "<td>&ndash;</td>";
    std::string out = "<td>" + fmt(s.mean);
    if (!std::isnan(s.ci95_low)) out += " <span class=ci>[" + fmt(s.ci95_low) + ", " + fmt(s.ci95_high) + "]</span>";
    out += "<br><span class=md>median " + fmt(s.median) + " (" + fmt(s.q1) + "&ndash;" + fmt(s.q3) + ")</span>";
    return out + " <span class=n>n=" + std::to_string(s.n) + "</span></td>";
}

constexpr const char* kTestHeads =
    "<th>test</th><th>n</th><th>statistic</th><th>df</th><th>p</th><th>Z</th><th>effect size</th><th>p from</th>";
constexpr int kTestColumns = 8;

std::string testCells(const stats::TestResult& t) {
    const std::string effect = std::isnan(t.effect_size)       ? ""
                               : t.effect == "kendall_w"       ? "W "
                               : t.effect == "rank_biserial_r" ? "r "
                                                               : "";
    return "<td>" + esc(t.test) + "</td><td>" + std::to_string(t.n) + "</td><td>" + fmt(t.statistic) + "</td><td>" +
           fmt(t.df, "%.0f") + "</td><td>" + fmtP(t.p) + "</td><td>" + fmt(t.z) + "</td><td>" + effect +
           fmt(t.effect_size) + "</td><td>" + (t.p_method.empty() ? "&ndash;" : esc(t.p_method)) + "</td>";
}

constexpr std::array<std::pair<std::string_view, std::string_view>, 6> kMeasureTitles{{
    {"hit_rate", "Hit rate (hits / scored trials)"},
    {"false_confirmations", "False confirmations (count)"},
    {"time_to_decision_s", "Time to decision (s, decided trials)"},
    {"target_distance_m", "Distance to target (m)"},
    {"tlx_raw", "Raw NASA-TLX (0&ndash;100)"},
    {"correct_rejection_rate", "Correct rejections (no_target / target-absent trials)"},
}};

// The sessions that are not complete: what each recorded and what the report counts.
std::string sessionsSection(const StudyResults& results) {
    std::string h =
        "<h2>Sessions not complete</h2>\n<table><tr><th>participant</th><th>state</th>"
        "<th>trials recorded</th><th>trials planned</th><th>counted</th></tr>\n";
    for (const SessionRecord& s : results.sessions) {
        if (s.state == SessionState::Complete) continue;
        h += "<tr><td>" + esc(s.participant) + "</td><td>" + std::string(sessionStateName(s.state)) + "</td><td>" +
             std::to_string(s.trials_recorded) + "</td><td>" + std::to_string(s.trials_planned) + "</td><td>" +
             (s.state == SessionState::Empty ? std::string("left out")
                                             : std::to_string(s.trials_recorded - s.practice_recorded) + " trials") +
             "</td></tr>\n";
    }
    return h + "</table>\n";
}

// The Likert answers per question (and condition): how many gave each rating, the median
// and quartiles.
std::string likertSection(const ReportFigures& f) {
    int top = 1;
    for (const LikertFigures& l : f.likert)
        for (int r = 1; r <= kMaxLikertRating; ++r)
            if (l.counts[std::size_t(r)] > 0) top = std::max(top, r);
    std::string h =
        "<h2>Likert items</h2>\n<table><tr><th>item</th><th>occasion</th><th>condition</th><th>n</th>"
        "<th>median (quartiles)</th>";
    for (int r = 1; r <= top; ++r) h += "<th>" + std::to_string(r) + "</th>";
    h += "</tr>\n";
    for (const LikertFigures& l : f.likert) {
        h += "<tr><td>" + esc(l.question.item) + "</td><td>" + esc(l.question.occasion) + "</td><td>" +
             (l.question.condition.empty() ? "&ndash;" : esc(l.question.condition)) + "</td><td>" +
             std::to_string(l.summary.n) + "</td><td>" + fmt(l.summary.median) + " (" + fmt(l.summary.q1) + "&ndash;" +
             fmt(l.summary.q3) + ")</td>";
        for (int r = 1; r <= top; ++r) h += "<td>" + std::to_string(l.counts[std::size_t(r)]) + "</td>";
        h += "</tr>\n";
    }
    return h + "</table>\n<p>The columns 1, 2, ... count the participants who gave that rating.</p>\n";
}

// The per-participant and per-cloud tables.
std::string cellsSection(const ReportFigures& f) {
    std::string h =
        "<h2>Per participant and condition</h2>\n<table><tr><th>participant</th><th>condition</th>"
        "<th>trials</th><th>hit rate</th><th>false confirmations</th><th>time to decision (s)</th>"
        "<th>distance (m)</th><th>raw TLX</th><th>correct rejections</th></tr>\n";
    for (std::size_t i = 0; i < f.participants.size(); ++i)
        for (std::size_t j = 0; j < f.conditions.size(); ++j) {
            const CellFigures& c = f.cells[i][j];
            h += "<tr><td>" + esc(f.participants[i]) + "</td><td>" + esc(f.conditions[j]) + "</td><td>" +
                 std::to_string(c.trials) + "</td><td>" + fmt(c.hit_rate) + "</td><td>" + fmt(c.false_confirmations) +
                 "</td><td>" + fmt(c.time_to_decision_s) + "</td><td>" + fmt(c.target_distance_m) + "</td><td>" +
                 fmt(c.tlx_raw) + "</td><td>" + std::to_string(c.correct_rejections) + " / " +
                 std::to_string(c.absent) + "</td></tr>\n";
        }
    h += "</table>\n";

    h += "<h2>Per cloud</h2>\n<table><tr><th>cloud</th><th>trials</th><th>hit rate</th>"
         "<th>correct rejection rate</th><th>time to decision (s)</th><th>visibility metric</th></tr>\n";
    for (const CloudFigures& c : f.clouds)
        h += "<tr><td>" + esc(c.cloud) + "</td><td>" + std::to_string(c.all.trials) + "</td><td>" +
             fmt(c.all.hit_rate) + "</td><td>" + fmt(c.all.correct_rejection_rate) + "</td><td>" +
             fmt(c.all.time_to_decision_s) + "</td><td>" + fmt(c.visibility_metric) + "</td></tr>\n";
    return h + "</table>\n";
}
}  // namespace

std::string reportHtml(const StudyResults& results, const ReportFigures& f) {
    std::string h;
    h += "<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8><title>Study report</title>\n<style>\n"
         "body{font-family:sans-serif;margin:1.5em;color:#222;max-width:70em}\n"
         "table{border-collapse:collapse;margin:.5em 0 1.5em}td,th{border:1px solid #bbb;padding:.2em .5em;"
         "text-align:right}th{background:#eee}td:first-child,th:first-child{text-align:left}\n"
         ".ci{color:#555}.md{color:#555;font-size:85%}.n{color:#888;font-size:85%}img{max-width:100%;border:1px solid "
         "#ddd}\n"
         "</style></head><body>\n<h1>Study report</h1>\n";
    h += "<p>Design SHA-256 <code>" + esc(results.design_sha256) + "</code>; " + std::to_string(f.participants.size()) +
         " participants; conditions: ";
    for (std::size_t j = 0; j < f.conditions.size(); ++j) h += (j ? ", " : "") + esc(f.conditions[j]);
    h += ". Sessions: " + std::to_string(countSessions(results, SessionState::Complete)) + " complete, " +
         std::to_string(countSessions(results, SessionState::Partial)) +
         " partial (counted with the trials they "
         "have), " +
         std::to_string(countSessions(results, SessionState::Empty)) +
         " empty (left out). Practice trials are left out. Each participant's trials of a condition give one value "
         "per measure; the table shows the mean over participants, its 95&nbsp;% confidence interval (t "
         "distribution) in brackets, below it the median and the quartiles, and n, the participants with a "
         "value.</p>\n";

    h += "<h2>Per condition</h2>\n<table><tr><th>measure</th>";
    for (const std::string& c : f.conditions) h += "<th>" + esc(c) + "</th>";
    h += std::string(kTestHeads) + "</tr>\n";
    for (const auto& [measure, title] : kMeasureTitles) {
        h += "<tr><td>" + std::string(title) + "</td>";
        for (const stats::Summary& s : f.by_condition.find(measure)->second) h += summaryCell(s);
        if (const auto it = f.condition_tests.find(measure); it != f.condition_tests.end())
            h += testCells(it->second);
        else
            h += "<td colspan=" + std::to_string(kTestColumns) + ">one condition: no test</td>";
        h += "</tr>\n";
    }
    h += "</table>\n<p>Tests across conditions use the participants with a value in every condition: the "
         "Friedman test with three or more conditions (effect size Kendall's W), the Wilcoxon signed-rank test "
         "with two (Z, and the matched-pairs rank-biserial correlation r, positive when the second condition's "
         "values are larger). p is exact (the permutation distribution counted) for small n, else from the "
         "chi-square or normal approximation, as &ldquo;p from&rdquo; says (docs/study.md says why).</p>\n";

    h += "<h2>Plots</h2>\n";
    for (const auto& [file, alt] :
         {std::pair<const char*, const char*>{"time_to_decision.png", "Time to decision per condition"},
          {"hit_rate.png", "Hit rate per condition"},
          {"cloud_difficulty.png", "Per-cloud hit rate against the visibility metric"}})
        h += std::string("<p><a href=\"") + file + "\"><img src=\"" + file + "\" alt=\"" + alt +
             "\" width=720 "
             "height=420></a></p>\n";

    h += "<h2>Simulator sickness (SSQ)</h2>\n<table><tr><th>score</th><th>pre</th><th>post</th>"
         "<th>post &minus; pre</th>" +
         std::string(kTestHeads) + "</tr>\n";
    for (const std::string_view name : ssqScoreNames()) {
        h += "<tr><td>" + std::string(name) + "</td>";
        for (const stats::Summary& s : f.ssq_summary.find(name)->second) h += summaryCell(s);
        h += testCells(f.ssq_tests.find(name)->second) + "</tr>\n";
    }
    h += "</table>\n";

    if (f.likert.size() > 0) h += likertSection(f);
    if (countSessions(results, SessionState::Complete) < results.sessions.size()) h += sessionsSection(results);
    h += cellsSection(f);

    h += "<h2>Files</h2>\n<p>";
    for (const char* file : {"figures.json", "conditions.csv", "cells.csv", "participants.csv", "ssq.csv",
                             "ssq_summary.csv", "tests.csv", "clouds.csv", "likert.csv"})
        h += std::string("<a href=\"") + file + "\">" + file + "</a> ";
    h += "</p>\n</body></html>\n";
    return h;
}

}  // namespace study
