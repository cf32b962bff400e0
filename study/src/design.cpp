// study/src/design.cpp: DESIGN.json, parsed strictly, the orders of conditions and a
// participant's session (study/design.hpp).
#include <study/design.hpp>

#include "json_fields.hpp"

#include <core/error.hpp>
#include <core/random.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

namespace study {

namespace {
using detail::field;
using detail::onlyKeys;
using nlohmann::json;

std::string name(const json& o, const char* key, const std::string& where, const std::string& fallback) {
    const auto it = o.find(key);
    if (it == o.end()) return fallback;
    if (!it->is_string() || !isStudyName(it->get<std::string>()))
        throw core::Error(field(where, key) + " " +
                          (it->is_string() ? "'" + core::printable(it->get<std::string>(), 40) + "'"
                                           : std::string(io::jsonTypeName(*it))) +
                          " is not a name of " + std::string(kStudyNameRule));
    return it->get<std::string>();
}

std::optional<bool> flag(const json& o, const char* key, const std::string& where) {
    const auto it = o.find(key);
    if (it == o.end()) return std::nullopt;
    if (!it->is_boolean())
        throw core::Error(field(where, key) + " must be true or false, not " + io::jsonTypeName(*it));
    return it->get<bool>();
}

const json& array(const json& root, const char* key, const std::string& where, std::size_t most, bool required) {
    static const json kEmpty = json::array();
    const auto it = root.find(key);
    if (it == root.end()) {
        if (required) throw core::Error(where + ": '" + key + "' is required");
        return kEmpty;
    }
    if (!it->is_array() || (required && it->empty()))
        throw core::Error(where + ": '" + key + "' must be " + (required ? "a non-empty " : "an ") + "array, not " +
                          (it->is_array() ? std::string("an empty one") : io::jsonTypeName(*it)));
    if (it->size() > most)
        throw core::Error(where + ": '" + key + "' has " + std::to_string(it->size()) + " entries; allowed at most " +
                          std::to_string(most));
    return *it;
}

Condition parseCondition(const json& c, const std::string& w, const std::filesystem::path& base) {
    if (!c.is_object()) throw core::Error(w + " must be an object, not " + io::jsonTypeName(c));
    onlyKeys(c, w,
             {"name", "colour", "eye_dome", "candidates", "time_limit_s", "start", "detector", "tools", "cut",
              "cut_radius_m", "comment"});
    Condition condition;
    if (!c.contains("name")) throw core::Error(w + ": 'name' is required");
    condition.name = name(c, "name", w, "");
    if (const auto it = c.find("colour"); it != c.end()) {
        if (!it->is_string())
            throw core::Error(field(w, "colour") + " must be a string, not " + io::jsonTypeName(*it) +
                              "; allowed: file, height, white, label, above-ground, class, intensity, return");
        try {
            condition.colour = viewer::parseColourMode(it->get<std::string>());
        } catch (const core::Error&) {
            throw core::Error(field(w, "colour") + " '" + core::printable(it->get<std::string>(), 40) +
                              "' is not one of file, height, white, label, above-ground, class, intensity, return");
        }
    }
    condition.eye_dome = flag(c, "eye_dome", w);
    condition.cut = flag(c, "cut", w);
    if (c.contains("cut_radius_m")) condition.cut_radius_m = detail::number(c, "cut_radius_m", w, 0.1, 10000.0, 15.0);
    condition.candidates = flag(c, "candidates", w).value_or(true);
    if (c.contains("time_limit_s")) condition.time_limit_s = detail::number(c, "time_limit_s", w, 0.0, 86400.0, 0.0);
    if (const auto it = c.find("start"); it != c.end()) {
        if (!it->is_string())
            throw core::Error(field(w, "start") + " must be a string, not " + io::jsonTypeName(*it) +
                              "; allowed: automatic, free");
        const std::string v = it->get<std::string>();
        if (v == "automatic")
            condition.start = viewer::ViewMode::Automatic;
        else if (v == "free")
            condition.start = viewer::ViewMode::Free;
        else
            throw core::Error(field(w, "start") + " '" + core::printable(v, 40) + "' is not one of automatic, free");
    }
    if (const auto it = c.find("tools"); it != c.end()) {
        if (!it->is_array() || it->size() > 3)
            throw core::Error(field(w, "tools") + " must be an array of tool names; allowed: zoom, cut, colour");
        unsigned tools = 0;
        for (const json& t : *it) {
            const std::string v = t.is_string() ? t.get<std::string>() : "";
            const unsigned bit = v == "zoom"     ? viewer::kToolZoom
                                 : v == "cut"    ? viewer::kToolCut
                                 : v == "colour" ? viewer::kToolColour
                                                 : 0u;
            if (bit == 0)
                throw core::Error(field(w, "tools") + " '" +
                                  (t.is_string() ? core::printable(v, 40) : std::string(io::jsonTypeName(t))) +
                                  "' is not one of zoom, cut, colour");
            tools |= bit;
        }
        condition.tools = tools;
    }
    if (const auto it = c.find("detector"); it != c.end()) {
        if (!it->is_string() || it->get<std::string>().empty())
            throw core::Error(field(w, "detector") + " must be a non-empty string; allowed: baseline, or a model " +
                              "file written by 'ladarvr train'");
        condition.detector = it->get<std::string>();
        if (condition.detector != "baseline")
            condition.detector = (base / condition.detector).lexically_normal().string();
        if (!condition.candidates)
            throw core::Error(field(w, "detector") + " goes with candidates shown; allowed: drop 'candidates': false");
    }
    return condition;
}

QuestionWhen parseWhen(const json& o, const std::string& w) {
    const auto it = o.find("when");
    if (it == o.end()) throw core::Error(w + ": 'when' is required (pre, post or after_condition)");
    const std::string v = it->is_string() ? it->get<std::string>() : "";
    if (v == "pre") return QuestionWhen::Pre;
    if (v == "post") return QuestionWhen::Post;
    if (v == "after_condition") return QuestionWhen::AfterCondition;
    throw core::Error(field(w, "when") + " " +
                      (it->is_string() ? "'" + core::printable(v, 40) + "'" : std::string(io::jsonTypeName(*it))) +
                      " is not one of pre, post, after_condition");
}

// A statement or question shown on the questionnaire screen: one line of 1 to
// kMaxStatementChars characters without control characters.
std::string statement(const json& o, const char* key, const std::string& w) {
    const auto it = o.find(key);
    if (it == o.end()) throw core::Error(w + ": '" + key + "' is required");
    const std::string s = it->is_string() ? it->get<std::string>() : "";
    const bool control = std::any_of(s.begin(), s.end(), [](char c) { return (unsigned char)c < 0x20 || c == 0x7f; });
    if (!it->is_string() || s.empty() || s.size() > kMaxStatementChars || control)
        throw core::Error(field(w, key) + " must be a string of 1 to " + std::to_string(kMaxStatementChars) +
                          " characters without control characters, not " +
                          (it->is_string() ? "one of " + std::to_string(s.size()) + " characters" +
                                                 (control ? " with a control character" : "")
                                           : std::string(io::jsonTypeName(*it))));
    return s;
}

Questionnaires parseQuestionnaires(const json& q, const std::string& w) {
    if (!q.is_object()) throw core::Error(w + " must be an object, not " + io::jsonTypeName(q));
    onlyKeys(q, w, {"ssq", "tlx", "likert", "text", "comment"});
    Questionnaires out;
    out.ssq = flag(q, "ssq", w).value_or(false);
    out.tlx = flag(q, "tlx", w).value_or(false);
    std::set<std::string> ids;
    const json& likert = array(q, "likert", w, kMaxQuestionItems, false);
    for (std::size_t i = 0; i < likert.size(); ++i) {
        const std::string iw = w + ".likert[" + std::to_string(i) + "]";
        const json& l = likert[i];
        if (!l.is_object()) throw core::Error(iw + " must be an object, not " + io::jsonTypeName(l));
        onlyKeys(l, iw, {"id", "statement", "points", "when", "comment"});
        if (!l.contains("id")) throw core::Error(iw + ": 'id' is required");
        LikertItem item;
        item.id = name(l, "id", iw, "");
        if (!ids.insert(item.id).second)
            throw core::Error(iw + ".id '" + item.id + "' is used twice; allowed: a different id per item");
        item.statement = statement(l, "statement", iw);
        item.points = detail::whole(l, "points", iw, 2, 11, 7);
        item.when = parseWhen(l, iw);
        out.likert.push_back(std::move(item));
    }
    const json& text = array(q, "text", w, kMaxQuestionItems, false);
    for (std::size_t i = 0; i < text.size(); ++i) {
        const std::string iw = w + ".text[" + std::to_string(i) + "]";
        const json& t = text[i];
        if (!t.is_object()) throw core::Error(iw + " must be an object, not " + io::jsonTypeName(t));
        onlyKeys(t, iw, {"id", "question", "when", "comment"});
        if (!t.contains("id")) throw core::Error(iw + ": 'id' is required");
        TextItem item;
        item.id = name(t, "id", iw, "");
        if (!ids.insert(item.id).second)
            throw core::Error(iw + ".id '" + item.id + "' is used twice; allowed: a different id per item");
        item.question = statement(t, "question", iw);
        item.when = parseWhen(t, iw);
        out.text.push_back(std::move(item));
    }
    return out;
}

std::vector<PlanTrial> parseTrials(const json& list, const std::string& w, const std::filesystem::path& base) {
    std::vector<PlanTrial> trials;
    for (std::size_t i = 0; i < list.size(); ++i)
        trials.push_back(detail::parseTrial(list[i], w + "[" + std::to_string(i) + "]", base));
    return trials;
}

std::string listed(const std::vector<std::string>& names) {
    if (names.size() <= 4) {
        std::string s;
        for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
        return s;
    }
    return names[0] + ", " + names[1] + ", ..., " + names.back();
}
}  // namespace

const char* questionWhenName(QuestionWhen when) {
    switch (when) {
        case QuestionWhen::Pre: return "pre";
        case QuestionWhen::Post: return "post";
        case QuestionWhen::AfterCondition: return "after_condition";
    }
    return "?";
}

bool isStudyName(std::string_view s) {
    if (s.empty() || s.size() > 40 || s.front() == '-') return false;
    return std::all_of(s.begin(), s.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
               c == '.';
    });
}

bool isDesignText(std::string_view text, const std::string& name) {
    const json root = io::parseStrictJson(text, "study: " + name);
    return root.is_object() && root.contains("conditions");
}

Design parseDesign(std::string_view text_in, const std::string& name_in, const std::filesystem::path& base) {
    const std::string where = "study: " + name_in;
    const json root = io::parseStrictJson(text_in, where);
    if (!root.is_object()) throw core::Error(where + ": the design must be an object, not " + io::jsonTypeName(root));
    onlyKeys(root, where,
             {"conditions", "blocks", "practice", "break_s", "order", "seed", "participants", "hit_radius_m", "orbit",
              "generate", "questionnaires", "comment"});
    Design design;
    const json& conditions = array(root, "conditions", where, kMaxConditions, true);
    std::set<std::string> seen;
    for (std::size_t i = 0; i < conditions.size(); ++i) {
        const std::string w = where + ": conditions[" + std::to_string(i) + "]";
        design.conditions.push_back(parseCondition(conditions[i], w, base));
        if (!seen.insert(design.conditions.back().name).second)
            throw core::Error(w + ".name '" + design.conditions.back().name +
                              "' is used twice; allowed: a different name per condition");
    }
    const json& blocks = array(root, "blocks", where, 1000, true);
    std::size_t trials = 0;
    seen.clear();
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        const std::string w = where + ": blocks[" + std::to_string(i) + "]";
        const json& b = blocks[i];
        if (!b.is_object()) throw core::Error(w + " must be an object, not " + io::jsonTypeName(b));
        onlyKeys(b, w, {"name", "trials", "corpus", "select", "count", "seed", "time_limit_s", "comment"});
        DesignBlock block;
        block.name = name(b, "name", w, std::to_string(i + 1));
        if (!seen.insert(block.name).second)
            throw core::Error(w + ".name '" + block.name + "' is used twice; allowed: a different name per block");
        if (b.contains("corpus")) {  // a selection from a corpus, picked by readDesign
            if (b.contains("trials"))
                throw core::Error(w + ": give either 'trials' or 'corpus' with 'select' and 'count', not both");
            block.corpus = detail::resolve(base, detail::text(b, "corpus", w));
            block.select = detail::text(b, "select", w);
            if (block.select.empty())
                throw core::Error(w +
                                  ": 'select' is required with 'corpus' (a manifest condition, e.g. \"metric<0.3\")");
            if (!b.contains("count")) throw core::Error(w + ": 'count' is required with 'corpus' (1 to 1000 items)");
            block.count = std::size_t(detail::whole(b, "count", w, 1, 1000, 1));
            block.select_seed = std::uint64_t(detail::whole(b, "seed", w, 0, 2147483647, 1));
            block.time_limit_s = detail::number(b, "time_limit_s", w, 0.0, 86400.0, 120.0);
            trials += block.count;
        } else {
            for (const char* k : {"select", "count", "seed", "time_limit_s"})
                if (b.contains(k)) throw core::Error(w + ": '" + k + "' goes with 'corpus'");
            const auto t = b.find("trials");
            if (t == b.end() || !t->is_array() || t->empty())
                throw core::Error(w + ".trials must be a non-empty array of trials");
            block.trials = parseTrials(*t, w + ".trials", base);
            trials += block.trials.size();
        }
        design.blocks.push_back(std::move(block));
    }
    design.practice = parseTrials(array(root, "practice", where, 1000, false), where + ": practice", base);
    trials += design.practice.size();
    // The session runs every block and the practice once per condition.
    if (trials * design.conditions.size() > 10000)
        throw core::Error(where + ": " + std::to_string(trials * design.conditions.size()) +
                          " trials per session (conditions x (practice + blocks' trials)); allowed at most 10000");
    design.break_s = detail::number(root, "break_s", where + ":", 0.0, 86400.0, 0.0);
    if (const auto it = root.find("order"); it != root.end()) {
        const std::string o = it->is_string() ? it->get<std::string>() : "";
        if (o == "latin")
            design.order = ConditionOrder::Latin;
        else if (o == "permutation")
            design.order = ConditionOrder::Permutation;
        else if (o == "random")
            design.order = ConditionOrder::Random;
        else
            throw core::Error(where + ": order " +
                              (it->is_string() ? "'" + core::printable(o, 40) + "'" : io::jsonTypeName(*it)) +
                              " is not one of latin, permutation, random");
    }
    if (const auto seed = root.find("seed"); seed != root.end()) {
        if (design.order != ConditionOrder::Random)
            throw core::Error(where + ": seed is only used with order 'random'");
        if (!seed->is_number_unsigned())
            throw core::Error(where + ": seed must be a whole number >= 0, not " +
                              (seed->is_number() ? core::shownNumber(seed->get<double>()) : io::jsonTypeName(*seed)));
        design.seed = seed->get<std::uint64_t>();
    } else if (design.order == ConditionOrder::Random) {
        throw core::Error(where + ": order 'random' needs a 'seed' (a whole number >= 0), so orders are reproducible");
    }
    if (design.order == ConditionOrder::Permutation && design.conditions.size() > kMaxPermutationConditions)
        throw core::Error(where + ": order 'permutation' with " + std::to_string(design.conditions.size()) +
                          " conditions; allowed at most " + std::to_string(kMaxPermutationConditions) +
                          " (use 'latin')");
    const json& participants = array(root, "participants", where, kMaxParticipants, true);
    seen.clear();
    for (std::size_t i = 0; i < participants.size(); ++i) {
        const std::string w = where + ": participants[" + std::to_string(i) + "]";
        const json& p = participants[i];
        if (!p.is_string() || !isStudyName(p.get<std::string>()))
            throw core::Error(w + " " +
                              (p.is_string() ? "'" + core::printable(p.get<std::string>(), 40) + "'"
                                             : std::string(io::jsonTypeName(p))) +
                              " is not an id of " + std::string(kStudyNameRule));
        if (!seen.insert(p.get<std::string>()).second)
            throw core::Error(w + " '" + p.get<std::string>() + "' is listed twice; allowed: each id once");
        design.participants.push_back(p.get<std::string>());
    }
    detail::parseRunSettings(root, where, design.settings);
    if (const auto q = root.find("questionnaires"); q != root.end())
        design.questionnaires = parseQuestionnaires(*q, where + ": questionnaires");
    // A detector runs on the trial's cloud file before the session: scenes have none yet.
    for (std::size_t i = 0; i < design.conditions.size(); ++i) {
        if (design.conditions[i].detector.empty()) continue;
        const auto scene = [](const PlanTrial& t) { return !t.scene.empty(); };
        bool scenes = std::any_of(design.practice.begin(), design.practice.end(), scene);
        for (const DesignBlock& b : design.blocks)
            scenes = scenes || std::any_of(b.trials.begin(), b.trials.end(), scene);
        if (scenes)
            throw core::Error(where + ": conditions[" + std::to_string(i) +
                              "].detector runs on cloud files; allowed: trials with 'cloud', not 'scene'");
    }
    return design;
}

std::vector<std::vector<int>> williamsSquare(int n) {
    // The first row alternates from the two ends: 0, 1, n-1, 2, n-2, ...
    std::vector<int> first;
    for (int lo = 0, hi = n - 1, k = 0; k < n; ++k) first.push_back(k == 0 ? lo++ : (k % 2 == 1 ? lo++ : hi--));
    std::vector<std::vector<int>> rows;
    for (int r = 0; r < n; ++r) {
        std::vector<int> row;
        for (int c : first) row.push_back((c + r) % n);
        rows.push_back(std::move(row));
    }
    if (n % 2 == 1)
        for (int r = 0; r < n; ++r) rows.emplace_back(rows[std::size_t(r)].rbegin(), rows[std::size_t(r)].rend());
    return rows;
}

std::vector<int> conditionOrder(const Design& design, std::size_t participant_index) {
    const int n = static_cast<int>(design.conditions.size());
    std::vector<int> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    switch (design.order) {
        case ConditionOrder::Latin: {
            const auto rows = williamsSquare(n);
            return rows[participant_index % rows.size()];
        }
        case ConditionOrder::Permutation: {
            // The k-th permutation in lexicographic order, k written in the factorial base.
            std::size_t factorial = 1;
            for (int i = 2; i <= n; ++i) factorial *= std::size_t(i);
            std::size_t k = participant_index % factorial;
            std::vector<int> left = order, out;
            for (int i = n; i >= 1; --i) {
                factorial /= std::size_t(i);
                const std::size_t pick = k / factorial;
                k %= factorial;
                out.push_back(left[pick]);
                left.erase(left.begin() + std::ptrdiff_t(pick));
            }
            return out;
        }
        case ConditionOrder::Random: {
            std::mt19937_64 rng(core::mix64(design.seed + core::kGolden * (participant_index + 1)));
            core::shuffle(order.begin(), order.end(), rng);
            return order;
        }
    }
    return order;
}

Session expandSession(const Design& design, const std::string& participant, const std::string& name_in) {
    const auto it = std::find(design.participants.begin(), design.participants.end(), participant);
    if (it == design.participants.end())
        throw core::Error("study: --participant '" + core::printable(participant, 40) + "' is not in " + name_in +
                          "'s participants (" + listed(design.participants) + ")");
    Session session;
    session.participant = participant;
    session.condition_order =
        conditionOrder(design, static_cast<std::size_t>(std::distance(design.participants.begin(), it)));
    session.plan = design.settings;
    session.plan.trials.clear();
    session.plan.shuffle_seed.reset();
    for (std::size_t k = 0; k < session.condition_order.size(); ++k) {
        const int ci = session.condition_order[k];
        const Condition& c = design.conditions[std::size_t(ci)];
        const std::size_t first = session.plan.trials.size();
        auto add = [&](const PlanTrial& t, int block) {
            PlanTrial trial = t;
            if (c.colour) trial.colour = c.colour;
            if (c.eye_dome) trial.eye_dome = c.eye_dome;
            if (!c.candidates) trial.candidates.clear();
            if (c.time_limit_s) trial.time_limit_s = *c.time_limit_s;
            if (c.start) trial.start_mode = c.start;
            if (!c.detector.empty()) trial.detector = c.detector;
            if (c.tools) trial.tools = c.tools;
            if (c.cut) trial.cut = c.cut;
            if (c.cut_radius_m) trial.cut_radius_m = c.cut_radius_m;
            session.plan.trials.push_back(std::move(trial));
            session.trials.push_back({ci, block, block < 0});
        };
        for (const PlanTrial& t : design.practice) add(t, -1);
        for (std::size_t b = 0; b < design.blocks.size(); ++b)
            for (const PlanTrial& t : design.blocks[b].trials) add(t, static_cast<int>(b));
        // A condition with no trial (a design whose corpus blocks readDesign has not yet
        // filled) carries no break.
        if (k > 0 && first < session.plan.trials.size()) session.plan.trials[first].min_ready_s = design.break_s;
    }
    return session;
}

}  // namespace study
