// study/src/plan.cpp: PLAN.json, parsed strictly (io/strict_json.hpp).
#include <study/plan.hpp>

#include "json_fields.hpp"

#include <core/error.hpp>
#include <core/random.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

namespace study {

namespace detail {
using nlohmann::json;

void onlyKeys(const json& o, const std::string& where, std::initializer_list<const char*> keys) {
    for (const auto& [key, value] : o.items()) {
        bool known = false;
        std::string allowed;
        for (const char* k : keys) {
            known = known || key == k;
            allowed += std::string(allowed.empty() ? "" : ", ") + k;
        }
        if (!known) throw core::Error(where + ": unknown key '" + core::printable(key, 40) + "'; allowed: " + allowed);
    }
}

std::string field(const std::string& where, const char* key) {
    return where + (!where.empty() && where.back() == ':' ? " " : ".") + key;
}

double number(const json& o, const char* key, const std::string& where, double lo, double hi, double fallback) {
    const auto it = o.find(key);
    if (it == o.end()) return fallback;
    const std::string range = "[" + core::shownNumber(lo) + ", " + core::shownNumber(hi) + "]";
    if (!it->is_number())
        throw core::Error(field(where, key) + " must be a number in " + range + ", not " + io::jsonTypeName(*it));
    const double v = it->get<double>();
    if (!(std::isfinite(v) && v >= lo && v <= hi))
        throw core::Error(field(where, key) + " " + core::shownNumber(v) + " is not in " + range);
    return v;
}

int whole(const json& o, const char* key, const std::string& where, int lo, int hi, int fallback) {
    const double v = number(o, key, where, lo, hi, fallback);
    if (v != std::floor(v))
        throw core::Error(field(where, key) + " " + core::shownNumber(v) + " is not a whole number");
    return static_cast<int>(v);
}

std::string text(const json& o, const char* key, const std::string& where) {
    const auto it = o.find(key);
    if (it == o.end()) return {};
    if (!it->is_string() || it->get<std::string>().empty())
        throw core::Error(field(where, key) + " must be a non-empty string, not " +
                          (it->is_string() ? std::string("an empty one") : io::jsonTypeName(*it)));
    return it->get<std::string>();
}

std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p) {
    const std::filesystem::path path(p);
    return path.is_absolute() ? path : base / path;
}

PlanTrial parseTrial(const json& t, const std::string& w, const std::filesystem::path& base) {
    if (!t.is_object()) throw core::Error(w + " must be an object, not " + io::jsonTypeName(t));
    onlyKeys(t, w, {"cloud", "scene", "candidates", "time_limit_s", "name"});
    PlanTrial trial;
    const std::string cloud = text(t, "cloud", w), scene = text(t, "scene", w);
    if (cloud.empty() == scene.empty()) throw core::Error(w + ": give exactly one of 'cloud' and 'scene'");
    if (!cloud.empty()) trial.cloud = resolve(base, cloud);
    if (!scene.empty()) trial.scene = resolve(base, scene);
    trial.source = cloud.empty() ? scene : cloud;
    if (const std::string c = text(t, "candidates", w); !c.empty()) trial.candidates = resolve(base, c);
    trial.time_limit_s = number(t, "time_limit_s", w, 0.0, 86400.0, 120.0);
    // A label, echoed on the ready screen and in stderr lines: control characters (a
    // newline, a terminal escape) escaped and the length capped here, once, for all of them.
    std::string label = text(t, "name", w);
    if (label.empty()) label = std::filesystem::path(trial.source).filename().string();
    trial.name = platform::printableUtf8(label, kMaxTrialNameChars);
    return trial;
}

void parseRunSettings(const json& root, const std::string& where, Plan& plan) {
    plan.hit_radius_m = number(root, "hit_radius_m", where + ":", 0.001, 10000.0, plan.hit_radius_m);
    if (const auto orbit = root.find("orbit"); orbit != root.end()) {
        const std::string w = where + ": orbit";
        if (!orbit->is_object()) throw core::Error(w + " must be an object, not " + io::jsonTypeName(*orbit));
        onlyKeys(*orbit, w, {"radius_m", "height_m", "period_s"});
        plan.orbit_radius_m = number(*orbit, "radius_m", w, 0.1, 100000.0, plan.orbit_radius_m);
        plan.orbit_height_m = number(*orbit, "height_m", w, -100000.0, 100000.0, plan.orbit_height_m);
        plan.orbit_period_s = number(*orbit, "period_s", w, 0.1, 1e9, plan.orbit_period_s);
    }
    if (const auto g = root.find("generate"); g != root.end()) {
        const std::string w = where + ": generate";
        if (!g->is_object()) throw core::Error(w + " must be an object, not " + io::jsonTypeName(*g));
        onlyKeys(*g, w, {"xres", "yres", "views", "ground"});
        plan.xres = whole(*g, "xres", w, 1, 8192, plan.xres);
        plan.yres = whole(*g, "yres", w, 1, 8192, plan.yres);
        plan.views = whole(*g, "views", w, 1, 65535, plan.views);
        if (const std::string ground = text(*g, "ground", w); !ground.empty()) {
            if (std::find(kPlanGrounds.begin(), kPlanGrounds.end(), ground) == kPlanGrounds.end())
                throw core::Error(field(w, "ground") + " '" + core::printable(ground, 40) +
                                  "' is not one of ransac, smrf, csf, white");
            plan.ground = ground;
        }
    }
}

void checkTrialFiles(const PlanTrial& t, const std::string& w) {
    for (const auto& [key, path] :
         {std::pair{"cloud", &t.cloud}, std::pair{"scene", &t.scene}, std::pair{"candidates", &t.candidates}})
        if (!path->empty())
            platform::checkInputFile(*path, w + "." + key + " '" + core::printable(path->string(), 400) + "'");
}
}  // namespace detail

using detail::onlyKeys;
using nlohmann::json;

Plan parsePlan(std::string_view text_in, const std::string& name, const std::filesystem::path& base) {
    const std::string where = "study: " + name;
    const json root = io::parseStrictJson(text_in, where);
    if (!root.is_object()) throw core::Error(where + ": the plan must be an object, not " + io::jsonTypeName(root));
    onlyKeys(root, where, {"trials", "shuffle_seed", "hit_radius_m", "orbit", "generate", "comment"});
    Plan plan;
    const auto trials = root.find("trials");
    if (trials == root.end() || !trials->is_array() || trials->empty())
        throw core::Error(where + ": 'trials' must be a non-empty array of trials");
    if (trials->size() > 10000)
        throw core::Error(where + ": " + std::to_string(trials->size()) + " trials; allowed at most 10000");
    for (std::size_t i = 0; i < trials->size(); ++i)
        plan.trials.push_back(detail::parseTrial((*trials)[i], where + ": trials[" + std::to_string(i) + "]", base));
    if (const auto seed = root.find("shuffle_seed"); seed != root.end()) {
        if (!seed->is_number_unsigned())
            throw core::Error(where + ": shuffle_seed must be a whole number >= 0, not " +
                              (seed->is_number() ? core::shownNumber(seed->get<double>()) : io::jsonTypeName(*seed)));
        plan.shuffle_seed = seed->get<std::uint64_t>();
    }
    detail::parseRunSettings(root, where, plan);
    return plan;
}

Plan readPlan(const std::filesystem::path& file) {
    const std::string shown = core::printable(file.string(), 400);
    Plan plan = parsePlan(platform::readTextFile(file, kMaxPlanBytes, "study: " + shown + ":"), shown,
                          file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path());
    for (std::size_t i = 0; i < plan.trials.size(); ++i)
        detail::checkTrialFiles(plan.trials[i], "study: " + shown + ": trials[" + std::to_string(i) + "]");
    return plan;
}

std::vector<int> trialOrder(const Plan& plan) {
    std::vector<int> order(plan.trials.size());
    std::iota(order.begin(), order.end(), 0);
    if (plan.shuffle_seed) {
        std::mt19937_64 rng(*plan.shuffle_seed);
        core::shuffle(order.begin(), order.end(), rng);
    }
    return order;
}

}  // namespace study
