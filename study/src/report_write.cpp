// study/src/report_write.cpp: the study report's folder (study/report.hpp): the tables as
// CSV, every figure in figures.json, the plots and index.html, made in memory and written
// as one folder through platform::writeFolderAtomic, so a reader sees the previous report
// or this one, never a mix.
#include <study/report.hpp>

#include "report_plot.hpp"

#include <study/csv_cell.hpp>

#include <platform/output_folder.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <set>

namespace study {

namespace {
using Json = nlohmann::ordered_json;

constexpr std::array<std::string_view, 3> kOccasions{"pre", "post", "difference"};

std::string num(double v) {
    if (std::isnan(v)) return "";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

Json jnum(double v) { return std::isnan(v) ? Json(nullptr) : Json(v); }

std::string cellCsv(const CellFigures& c) {
    return std::to_string(c.trials) + "," + std::to_string(c.scored) + "," + std::to_string(c.hits) + "," +
           std::to_string(c.decided) + "," + num(c.hit_rate) + "," + num(c.false_confirmations) + "," +
           num(c.time_to_decision_s) + "," + num(c.target_distance_m);
}
constexpr const char* kCellColumns =
    "trials,scored,hits,decided,hit_rate,false_confirmations,time_to_decision_s,target_distance_m";

Json cellJson(const CellFigures& c) {
    return Json{{"trials", c.trials},
                {"scored", c.scored},
                {"hits", c.hits},
                {"decided", c.decided},
                {"hit_rate", jnum(c.hit_rate)},
                {"false_confirmations", jnum(c.false_confirmations)},
                {"time_to_decision_s", jnum(c.time_to_decision_s)},
                {"target_distance_m", jnum(c.target_distance_m)}};
}

std::string summaryCsv(const stats::Summary& s) {
    return std::to_string(s.n) + "," + num(s.mean) + "," + num(s.sd) + "," + num(s.ci95_low) + "," + num(s.ci95_high);
}
Json summaryJson(const stats::Summary& s) {
    return Json{{"n", s.n},
                {"mean", jnum(s.mean)},
                {"sd", jnum(s.sd)},
                {"ci95_low", jnum(s.ci95_low)},
                {"ci95_high", jnum(s.ci95_high)}};
}
std::string testCsv(const stats::TestResult& t) {
    return csvCell(t.test) + "," + std::to_string(t.n) + "," + std::to_string(t.k) + "," + num(t.statistic) + "," +
           num(t.df) + "," + num(t.p);
}
Json testJson(const stats::TestResult& t) {
    return Json{{"test", t.test},   {"n", t.n},      {"k", t.k}, {"statistic", jnum(t.statistic)},
                {"df", jnum(t.df)}, {"p", jnum(t.p)}};
}
Json ssqJson(const std::optional<SsqScores>& s) {
    if (!s) return nullptr;
    Json o = Json::object();
    for (const std::string_view name : ssqScoreNames()) o[std::string(name)] = ssqScore(*s, name);
    return o;
}
}  // namespace

std::vector<std::pair<std::string, std::string>> reportTables(const StudyResults& results, const ReportFigures& f) {
    std::vector<std::pair<std::string, std::string>> out;
    const std::size_t k = f.conditions.size();

    std::string conditions = "measure,condition,n,mean,sd,ci95_low,ci95_high\n";
    for (const std::string_view measure : reportMeasures())
        for (std::size_t j = 0; j < k; ++j)
            conditions += csvCell(measure) + "," + csvCell(f.conditions[j]) + "," +
                          summaryCsv(f.by_condition.find(measure)->second[j]) + "\n";
    out.emplace_back("conditions.csv", conditions);

    std::string cells = std::string("participant,condition,") + kCellColumns + ",tlx_raw\n";
    for (std::size_t i = 0; i < f.participants.size(); ++i)
        for (std::size_t j = 0; j < k; ++j)
            cells += csvCell(f.participants[i]) + "," + csvCell(f.conditions[j]) + "," + cellCsv(f.cells[i][j]) + "," +
                     num(f.cells[i][j].tlx_raw) + "\n";
    out.emplace_back("cells.csv", cells);

    std::string participants = std::string("participant,") + kCellColumns + ",questionnaires\n";
    for (std::size_t i = 0; i < f.participants.size(); ++i)
        participants += csvCell(f.participants[i]) + "," + cellCsv(f.participant_totals[i]) + "," +
                        (results.participants[i].questionnaires ? "1" : "0") + "\n";
    out.emplace_back("participants.csv", participants);

    std::string ssq = "participant,occasion,nausea,oculomotor,disorientation,total\n";
    for (std::size_t i = 0; i < f.participants.size(); ++i) {
        const auto row = [&](std::string_view occasion, auto value) {
            ssq += csvCell(f.participants[i]) + "," + csvCell(occasion);
            for (const std::string_view name : ssqScoreNames()) ssq += "," + num(value(name));
            ssq += "\n";
        };
        const std::optional<SsqScores>&pre = f.ssq_pre[i], &post = f.ssq_post[i];
        if (pre) row("pre", [&](std::string_view n) { return ssqScore(*pre, n); });
        if (post) row("post", [&](std::string_view n) { return ssqScore(*post, n); });
        if (pre && post) row("difference", [&](std::string_view n) { return ssqScore(*post, n) - ssqScore(*pre, n); });
    }
    out.emplace_back("ssq.csv", ssq);

    std::string ssq_summary = "score,occasion,n,mean,sd,ci95_low,ci95_high\n";
    for (const std::string_view name : ssqScoreNames())
        for (std::size_t o = 0; o < kOccasions.size(); ++o)
            ssq_summary += csvCell(name) + "," + csvCell(kOccasions[o]) + "," +
                           summaryCsv(f.ssq_summary.find(name)->second[o]) + "\n";
    out.emplace_back("ssq_summary.csv", ssq_summary);

    std::string tests = "measure,test,n,k,statistic,df,p\n";
    for (const std::string_view measure : reportMeasures())
        if (const auto it = f.condition_tests.find(measure); it != f.condition_tests.end())
            tests += csvCell(measure) + "," + testCsv(it->second) + "\n";
    for (const std::string_view name : ssqScoreNames())
        tests +=
            csvCell("ssq_" + std::string(name) + "_post_vs_pre") + "," + testCsv(f.ssq_tests.find(name)->second) + "\n";
    out.emplace_back("tests.csv", tests);

    std::string clouds = std::string("cloud,") + kCellColumns + ",visibility_metric\n";
    for (const CloudFigures& c : f.clouds)
        clouds += csvCell(c.cloud) + "," + cellCsv(c.all) + "," + num(c.visibility_metric) + "\n";
    out.emplace_back("clouds.csv", clouds);

    Json j;
    j["design_sha256"] = results.design_sha256;
    j["conditions"] = f.conditions;
    j["participants"] = f.participants;
    Json measures = Json::object();
    for (const std::string_view measure : reportMeasures()) {
        Json m;
        Json by = Json::object();
        for (std::size_t c = 0; c < k; ++c) by[f.conditions[c]] = summaryJson(f.by_condition.find(measure)->second[c]);
        m["by_condition"] = by;
        const auto it = f.condition_tests.find(measure);
        m["test"] = it == f.condition_tests.end() ? Json(nullptr) : testJson(it->second);
        measures[std::string(measure)] = m;
    }
    j["measures"] = measures;
    Json cell_list = Json::array(), totals = Json::array(), ssq_list = Json::array();
    for (std::size_t i = 0; i < f.participants.size(); ++i) {
        for (std::size_t c = 0; c < k; ++c) {
            Json cell{{"participant", f.participants[i]}, {"condition", f.conditions[c]}};
            cell.update(cellJson(f.cells[i][c]));
            cell["tlx_raw"] = jnum(f.cells[i][c].tlx_raw);
            cell_list.push_back(cell);
        }
        Json total{{"participant", f.participants[i]}};
        total.update(cellJson(f.participant_totals[i]));
        total["questionnaires"] = results.participants[i].questionnaires;
        totals.push_back(total);
        Json s{{"participant", f.participants[i]}, {"pre", ssqJson(f.ssq_pre[i])}, {"post", ssqJson(f.ssq_post[i])}};
        if (f.ssq_pre[i] && f.ssq_post[i]) {
            Json d = Json::object();
            for (const std::string_view name : ssqScoreNames())
                d[std::string(name)] = ssqScore(*f.ssq_post[i], name) - ssqScore(*f.ssq_pre[i], name);
            s["difference"] = d;
        } else {
            s["difference"] = nullptr;
        }
        ssq_list.push_back(s);
    }
    j["cells"] = cell_list;
    j["participant_totals"] = totals;
    Json ssq_summary_json = Json::object();
    for (const std::string_view name : ssqScoreNames()) {
        Json s;
        for (std::size_t o = 0; o < kOccasions.size(); ++o)
            s[std::string(kOccasions[o])] = summaryJson(f.ssq_summary.find(name)->second[o]);
        s["test"] = testJson(f.ssq_tests.find(name)->second);
        ssq_summary_json[std::string(name)] = s;
    }
    j["ssq"] = Json{{"participants", ssq_list}, {"summary", ssq_summary_json}};
    Json cloud_list = Json::array();
    for (const CloudFigures& c : f.clouds) {
        Json o{{"cloud", c.cloud}};
        o.update(cellJson(c.all));
        o["visibility_metric"] = jnum(c.visibility_metric);
        cloud_list.push_back(o);
    }
    j["clouds"] = cloud_list;
    out.emplace_back("figures.json", j.dump(1) + "\n");
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
        "clouds.csv",     "figures.json", "time_to_decision.png", "hit_rate.png", "cloud_difficulty.png", "index.html"};
    return kNames.contains(name);
}

void writeStudyReport(const StudyResults& results, const std::filesystem::path& out) {
    const ReportFigures figures = computeFigures(results);
    platform::writeFolderAtomic(out, reportFiles(results, figures), isReportFile);
}

}  // namespace study
