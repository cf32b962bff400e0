// study/src/report_json.cpp: the study report's figures.json (report_format.hpp): every
// figure of the CSV tables in one document, null where a figure does not apply. Keys
// added after the first reports come after the keys that were there, so a reader that
// walks an object in order finds the older ones where they were.
#include "report_format.hpp"

#include <nlohmann/json.hpp>

namespace study::detail {

namespace {
using Json = nlohmann::ordered_json;

constexpr std::array<std::string_view, 3> kOccasions{"pre", "post", "difference"};

Json jnum(double v) { return std::isnan(v) ? Json(nullptr) : Json(shownValue(v)); }
Json jp(double p) { return std::isnan(p) ? Json(nullptr) : Json(p); }

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
// The target-absent trials' figures, added after each row's older keys.
void addCorrectRejections(Json& o, const CellFigures& c) {
    o["absent"] = c.absent;
    o["correct_rejections"] = c.correct_rejections;
    o["correct_rejection_rate"] = jnum(c.correct_rejection_rate);
}

Json summaryJson(const stats::Summary& s) {
    return Json{{"n", s.n},
                {"mean", jnum(s.mean)},
                {"sd", jnum(s.sd)},
                {"ci95_low", jnum(s.ci95_low)},
                {"ci95_high", jnum(s.ci95_high)},
                {"median", jnum(s.median)},
                {"q1", jnum(s.q1)},
                {"q3", jnum(s.q3)}};
}
Json testJson(const stats::TestResult& t) {
    return Json{{"test", t.test},
                {"n", t.n},
                {"k", t.k},
                {"statistic", jnum(t.statistic)},
                {"df", jnum(t.df)},
                {"p", jp(t.p)},
                {"z", jnum(t.z)},
                {"effect", t.effect},
                {"effect_size", jnum(t.effect_size)},
                {"p_method", t.p_method.empty() ? Json(nullptr) : Json(t.p_method)}};
}
Json ssqJson(const std::optional<SsqScores>& s) {
    if (!s) return nullptr;
    Json o = Json::object();
    for (const std::string_view name : ssqScoreNames()) o[std::string(name)] = shownValue(ssqScore(*s, name));
    return o;
}

Json measuresJson(const ReportFigures& f) {
    Json measures = Json::object();
    for (const std::string_view measure : reportMeasures()) {
        Json m;
        Json by = Json::object();
        for (std::size_t c = 0; c < f.conditions.size(); ++c)
            by[f.conditions[c]] = summaryJson(f.by_condition.find(measure)->second[c]);
        m["by_condition"] = by;
        const auto it = f.condition_tests.find(measure);
        m["test"] = it == f.condition_tests.end() ? Json(nullptr) : testJson(it->second);
        measures[std::string(measure)] = m;
    }
    return measures;
}

Json ssqSummaryJson(const ReportFigures& f) {
    Json out = Json::object();
    for (const std::string_view name : ssqScoreNames()) {
        Json s;
        for (std::size_t o = 0; o < kOccasions.size(); ++o)
            s[std::string(kOccasions[o])] = summaryJson(f.ssq_summary.find(name)->second[o]);
        s["test"] = testJson(f.ssq_tests.find(name)->second);
        out[std::string(name)] = s;
    }
    return out;
}

Json sessionsJson(const StudyResults& results) {
    Json list = Json::array();
    for (const SessionRecord& s : results.sessions)
        list.push_back(Json{{"participant", s.participant},
                            {"state", sessionStateName(s.state)},
                            {"trials_recorded", s.trials_recorded},
                            {"trials_planned", s.trials_planned},
                            {"practice_recorded", s.practice_recorded}});
    return Json{{"complete", countSessions(results, SessionState::Complete)},
                {"partial", countSessions(results, SessionState::Partial)},
                {"empty", countSessions(results, SessionState::Empty)},
                {"list", list}};
}

Json likertJson(const ReportFigures& f) {
    Json out = Json::array();
    for (const LikertFigures& l : f.likert) {
        Json counts = Json::array();
        for (int r = 1; r <= kMaxLikertRating; ++r) counts.push_back(l.counts[std::size_t(r)]);
        out.push_back(Json{{"item", l.question.item},
                           {"occasion", l.question.occasion},
                           {"condition", l.question.condition.empty() ? Json(nullptr) : Json(l.question.condition)},
                           {"n", l.summary.n},
                           {"median", jnum(l.summary.median)},
                           {"q1", jnum(l.summary.q1)},
                           {"q3", jnum(l.summary.q3)},
                           {"mean", jnum(l.summary.mean)},
                           {"counts", counts}});
    }
    return out;
}
}  // namespace

std::string figuresJson(const StudyResults& results, const ReportFigures& f) {
    Json j;
    j["design_sha256"] = results.design_sha256;
    j["conditions"] = f.conditions;
    j["participants"] = f.participants;
    j["measures"] = measuresJson(f);
    Json cell_list = Json::array(), totals = Json::array(), ssq_list = Json::array();
    for (std::size_t i = 0; i < f.participants.size(); ++i) {
        for (std::size_t c = 0; c < f.conditions.size(); ++c) {
            Json cell{{"participant", f.participants[i]}, {"condition", f.conditions[c]}};
            cell.update(cellJson(f.cells[i][c]));
            cell["tlx_raw"] = jnum(f.cells[i][c].tlx_raw);
            addCorrectRejections(cell, f.cells[i][c]);
            cell_list.push_back(cell);
        }
        const ParticipantResults& p = results.participants[i];
        Json total{{"participant", f.participants[i]}};
        total.update(cellJson(f.participant_totals[i]));
        total["questionnaires"] = p.questionnaires;
        addCorrectRejections(total, f.participant_totals[i]);
        const SessionRecord session = sessionRecord(p);
        total["session"] = sessionStateName(session.state);
        total["trials_recorded"] = session.trials_recorded;
        total["trials_planned"] = session.trials_planned;
        totals.push_back(total);
        Json s{{"participant", f.participants[i]}, {"pre", ssqJson(f.ssq_pre[i])}, {"post", ssqJson(f.ssq_post[i])}};
        if (f.ssq_pre[i] && f.ssq_post[i]) {
            Json d = Json::object();
            for (const std::string_view name : ssqScoreNames())
                d[std::string(name)] = shownValue(ssqScore(*f.ssq_post[i], name) - ssqScore(*f.ssq_pre[i], name));
            s["difference"] = d;
        } else {
            s["difference"] = nullptr;
        }
        ssq_list.push_back(s);
    }
    j["cells"] = cell_list;
    j["participant_totals"] = totals;
    j["ssq"] = Json{{"participants", ssq_list}, {"summary", ssqSummaryJson(f)}};
    Json cloud_list = Json::array();
    for (const CloudFigures& c : f.clouds) {
        Json o{{"cloud", c.cloud}};
        o.update(cellJson(c.all));
        o["visibility_metric"] = jnum(c.visibility_metric);
        addCorrectRejections(o, c.all);
        cloud_list.push_back(o);
    }
    j["clouds"] = cloud_list;
    j["sessions"] = sessionsJson(results);
    j["likert"] = likertJson(f);
    return j.dump(1) + "\n";
}

}  // namespace study::detail
