// study/src/json_fields.hpp: the strict readers of a plan's and a design's JSON fields
// (study/src/plan.cpp, study/src/design.cpp): each refuses a value of the wrong type or
// out of range with one line naming the field and what is allowed.
#pragma once
#include <study/plan.hpp>

#include <io/strict_json.hpp>

#include <filesystem>
#include <initializer_list>
#include <string>

namespace study::detail {

/// Refuses any key of `o` not in `keys`: "<where>: unknown key 'k'; allowed: a, b".
void onlyKeys(const nlohmann::json& o, const std::string& where, std::initializer_list<const char*> keys);
/// "<where>.<key>" inside an object ("study: p.json: trials[0].time_limit_s"), "<where>
/// <key>" at the top, where `where` ends in ':' ("study: p.json: hit_radius_m").
std::string field(const std::string& where, const char* key);
/// o[key] as a number in [lo, hi], `fallback` when absent.
double number(const nlohmann::json& o, const char* key, const std::string& where, double lo, double hi,
              double fallback);
/// o[key] as a whole number in [lo, hi], `fallback` when absent.
int whole(const nlohmann::json& o, const char* key, const std::string& where, int lo, int hi, int fallback);
/// o[key] as a non-empty string, "" when absent.
std::string text(const nlohmann::json& o, const char* key, const std::string& where);
/// `p` taken from `base` unless absolute.
std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p);

/// One trial object of a plan (or of a design's block or practice list), `where` naming it
/// ("study: p.json: trials[2]").
PlanTrial parseTrial(const nlohmann::json& t, const std::string& where, const std::filesystem::path& base);
/// A plan's or design's hit_radius_m, orbit and generate keys into `plan` (its trials untouched).
void parseRunSettings(const nlohmann::json& root, const std::string& where, Plan& plan);
/// Checks that every cloud, scene and candidates file a trial names is a readable regular
/// file (`where` names the trial).
void checkTrialFiles(const PlanTrial& t, const std::string& where);

}  // namespace study::detail
