// fuzz/fuzz_study_report.cpp: libFuzzer target for the CSV files `ladarvr study report`
// reads back from a design session's folder, which a researcher may have edited:
// study::parseReportTrials (trials.csv) and study::parseQuestionnaires (questionnaires.csv),
// chosen by the input's first byte (study/src/report_csv.cpp, compiled here with the
// instruments' scoring, trials.csv's header and the design's name rule, without the rest
// of the study module). The contract: either rows within the file's rules (trials numbered
// 1, 2, ... in order, a known decision, a cloud, participant and condition, a block name
// exactly when not practice, times, distances, hits and the metric within their ranges;
// scores only of the session's conditions, a raw TLX in [0, 100], Likert ratings 1 to 11,
// every SSQ score finite and >= 0), or one printable error line naming the file.
#include <core/error.hpp>
#include <study/design.hpp>
#include <study/report.hpp>
#include "check_message.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace {

bool inRange(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

void checkTrials(const std::vector<study::ReportTrial>& trials) {
    for (std::size_t i = 0; i < trials.size(); ++i) {
        const study::ReportTrial& t = trials[i];
        if (t.trial != int(i + 1)) std::abort();
        if (t.cloud.empty() || t.participant.empty() || t.condition.empty()) std::abort();
        if (t.practice != t.block.empty()) std::abort();
        if (!t.block.empty() && !study::isStudyName(t.block)) std::abort();
        if (!inRange(t.time_to_decision_s, 0.0, 1e9)) std::abort();
        if (t.target_distance_m && !inRange(*t.target_distance_m, 0.0, 1e12)) std::abort();
        if (t.visibility_metric && !inRange(*t.visibility_metric, 0.0, 1.0)) std::abort();
        for (const auto& bit : {t.hit, t.designation_hit, t.box_hit})
            if (bit && *bit != 0 && *bit != 1) std::abort();
        if (t.candidates_shown && (*t.candidates_shown < 0 || t.name.empty())) std::abort();
    }
}

bool ssqOk(const std::optional<study::SsqScores>& s) {
    if (!s) return true;
    for (const double v : {s->nausea, s->oculomotor, s->disorientation, s->total})
        if (!std::isfinite(v) || v < 0.0) return false;
    return true;
}

void checkQuestionnaires(const study::ParticipantResults& p) {
    if (!ssqOk(p.ssq_pre) || !ssqOk(p.ssq_post)) std::abort();
    for (const auto& [condition, raw] : p.tlx_raw)
        if ((condition != "a" && condition != "b") || !inRange(raw, 0.0, 100.0)) std::abort();
    for (const auto& [question, rating] : p.likert) {
        if (rating < 1 || rating > study::kMaxLikertRating) std::abort();
        if (!study::isStudyName(question.item)) std::abort();
        if (question.occasion == "after_condition" ? question.condition.empty() : !question.condition.empty())
            std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return -1;
    const bool questionnaires = (data[0] & 1) != 0;
    const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
    try {
        if (questionnaires) {
            study::ParticipantResults p;
            p.participant = "P1";
            p.condition_order = {"a", "b"};
            study::parseQuestionnaires(text, "questionnaires.csv", p);
            checkQuestionnaires(p);
        } else {
            checkTrials(study::parseReportTrials(text, "trials.csv"));
        }
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what());
        const std::string m = e.what();
        if (m.rfind(questionnaires ? "questionnaires.csv: " : "trials.csv: ", 0) != 0) {
            std::fprintf(stderr, "error not naming the file: %s\n", e.what());
            std::abort();
        }
        // LADARVR_FUZZ_VERBOSE=1 shows why an input was refused (to check the seeds).
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
    }
    return 0;
}
