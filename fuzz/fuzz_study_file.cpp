// fuzz/fuzz_study_file.cpp: libFuzzer target for the study files a researcher writes:
// study::parsePlan and study::parseDesign, chosen by study::isDesignText as `ladarvr study`
// chooses (study/src/plan.cpp and design.cpp, compiled here without the rest of the study
// module: they need core, platform, io and the viewer's headers only). Paths are resolved
// against a base and never opened (readPlan and readDesign check the files). The contract:
// either a plan or design that obeys the rules docs/study.md gives (counts, ranges, names,
// no NUL in a path), whose trial order is a permutation and whose sessions (the first and
// the last participant's) hold every condition once, with its practice and blocks; or one
// printable error line.
#include <core/error.hpp>
#include <study/design.hpp>
#include <study/plan.hpp>
#include "check_message.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace {

const std::filesystem::path kBase = "fuzz-base";

bool inRange(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

bool isPermutation(std::vector<int> order, std::size_t n) {
    if (order.size() != n) return false;
    std::sort(order.begin(), order.end());
    for (std::size_t i = 0; i < n; ++i)
        if (order[i] != int(i)) return false;
    return true;
}

void checkPath(const std::filesystem::path& p) {
    if (p.native().find('\0') != std::string::npos) std::abort();
}

void checkTrial(const study::PlanTrial& t) {
    if (t.cloud.empty() == t.scene.empty()) std::abort();
    checkPath(t.cloud);
    checkPath(t.scene);
    checkPath(t.candidates);
    if (!inRange(t.time_limit_s, 0.0, 86400.0)) std::abort();
    for (const char c : t.name)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) std::abort();
}

void checkSettings(const study::Plan& p) {
    if (!inRange(p.hit_radius_m, 0.001, 10000.0) || !inRange(p.orbit_radius_m, 0.1, 100000.0) ||
        !inRange(p.orbit_height_m, -100000.0, 100000.0) || !inRange(p.orbit_period_s, 0.1, 1e9))
        std::abort();
    if (p.xres < 1 || p.xres > 8192 || p.yres < 1 || p.yres > 8192 || p.views < 1 || p.views > 65535) std::abort();
    if (std::find(study::kPlanGrounds.begin(), study::kPlanGrounds.end(), p.ground) == study::kPlanGrounds.end())
        std::abort();
}

void checkPlan(const study::Plan& plan) {
    if (plan.trials.empty() || plan.trials.size() > 10000) std::abort();
    for (const study::PlanTrial& t : plan.trials) checkTrial(t);
    checkSettings(plan);
    if (!isPermutation(study::trialOrder(plan), plan.trials.size())) std::abort();
}

void checkNames(const std::vector<std::string>& names) {
    std::set<std::string> seen;
    for (const std::string& n : names)
        if (!study::isStudyName(n) || !seen.insert(n).second) std::abort();
}

void checkDesign(const study::Design& d) {
    const std::size_t n = d.conditions.size();
    if (n < 1 || n > study::kMaxConditions) std::abort();
    std::vector<std::string> names;
    for (const study::Condition& c : d.conditions) {
        names.push_back(c.name);
        if (c.time_limit_s && !inRange(*c.time_limit_s, 0.0, 86400.0)) std::abort();
        if (c.cut_radius_m && !inRange(*c.cut_radius_m, 0.1, 10000.0)) std::abort();
        checkPath(c.detector);
    }
    checkNames(names);
    if (d.participants.empty() || d.participants.size() > study::kMaxParticipants) std::abort();
    checkNames(d.participants);
    if (d.order == study::ConditionOrder::Permutation && n > study::kMaxPermutationConditions) std::abort();
    if (d.blocks.empty()) std::abort();
    std::size_t per_condition = d.practice.size();
    names.clear();
    for (const study::DesignBlock& b : d.blocks) {
        names.push_back(b.name);
        checkPath(b.corpus);
        if (b.corpus.empty() == b.trials.empty()) std::abort();  // trials, or a corpus readDesign picks from
        if (!b.corpus.empty() && (b.count < 1 || b.count > 1000)) std::abort();
        for (const study::PlanTrial& t : b.trials) checkTrial(t);
        per_condition += b.trials.size() + b.count;
    }
    checkNames(names);
    for (const study::PlanTrial& t : d.practice) checkTrial(t);
    if (per_condition * n > 10000) std::abort();
    if (!inRange(d.break_s, 0.0, 86400.0)) std::abort();
    checkSettings(d.settings);
    const study::Questionnaires& q = d.questionnaires;
    if (q.likert.size() > study::kMaxQuestionItems || q.text.size() > study::kMaxQuestionItems) std::abort();
    for (const study::LikertItem& l : q.likert)
        if (!study::isStudyName(l.id) || l.points < 2 || l.points > 11 || l.statement.empty()) std::abort();
    for (const study::TextItem& t : q.text)
        if (!study::isStudyName(t.id) || t.question.empty()) std::abort();
    // The first and the last participant's sessions: every condition once, in an order
    // that is a permutation, each with the practice and every block's trials (a corpus
    // block's are picked when the file is read, so none here).
    std::size_t listed = d.practice.size();
    for (const study::DesignBlock& b : d.blocks) listed += b.trials.size();
    for (const std::size_t p : {std::size_t(0), d.participants.size() - 1}) {
        if (!isPermutation(study::conditionOrder(d, p), n)) std::abort();
        const study::Session s = study::expandSession(d, d.participants[p], "fuzz.json");
        if (!isPermutation(s.condition_order, n)) std::abort();
        if (s.plan.trials.size() != listed * n || s.trials.size() != s.plan.trials.size()) std::abort();
        for (const study::SessionTrial& t : s.trials)
            if (t.condition < 0 || std::size_t(t.condition) >= n || t.block >= int(d.blocks.size()) ||
                t.practice != (t.block < 0))
                std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        if (study::isDesignText(text, "fuzz.json"))
            checkDesign(study::parseDesign(text, "fuzz.json", kBase));
        else
            checkPlan(study::parsePlan(text, "fuzz.json", kBase));
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what());
        // LADARVR_FUZZ_VERBOSE=1 shows why an input was refused (to check the seeds).
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
    }
    return 0;
}
