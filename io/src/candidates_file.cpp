// candidates_file: reading and writing candidate detections (io/candidates_file.hpp).
#include <core/error.hpp>
#include <core/frames.hpp>
#include <io/candidates_file.hpp>
#include <io/strict_json.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <cmath>
#include <set>

namespace io {

using core::Candidate;
using core::Error;
using core::shownNumber;
using platform::checkWritableDestination;
using platform::readTextFile;
using platform::writeFileAtomic;
namespace {

using nlohmann::json;

// A detector emits one candidate per cluster: a few thousand at most in practice.
constexpr std::size_t kMaxCandidatesBytes = std::size_t(16) << 20;
constexpr std::size_t kMaxCandidates = 100000;

double number(const json& o, const char* key, const std::string& where, const char* allowed) {
    const auto it = o.find(key);
    if (it == o.end()) throw Error(where + ": missing '" + key + "'; allowed: " + allowed);
    if (!it->is_number()) throw Error(where + "." + key + " must be " + allowed + ", not " + jsonTypeName(*it));
    const double v = it->get<double>();
    if (!std::isfinite(v)) throw Error(where + "." + key + " is not finite; allowed: " + allowed);
    return v;
}

// Three finite numbers, each of magnitude at most `max_abs` (the frame's coordinate bound:
// past it a box would silently fall off the float-precision local frame of the viewer).
glm::dvec3 triple(const json& o, const char* key, const std::string& where, const char* allowed, double max_abs) {
    const auto it = o.find(key);
    if (it == o.end()) throw Error(where + ": missing '" + key + "'; allowed: " + allowed);
    if (!it->is_array() || it->size() != 3)
        throw Error(where + "." + key + " must be " + allowed + ", not " + jsonTypeName(*it) +
                    (it->is_array() ? " of " + std::to_string(it->size()) : ""));
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i) {
        const json& e = (*it)[std::size_t(i)];
        if (!e.is_number() || !std::isfinite(e.get<double>()))
            throw Error(where + "." + key + "[" + std::to_string(i) + "] must be a finite number; allowed: " + allowed);
        v[i] = e.get<double>();
        if (std::abs(v[i]) > max_abs)
            throw Error(where + "." + key + "[" + std::to_string(i) + "] is " + shownNumber(v[i]) + "; allowed: " +
                        allowed + ", each in [-" + shownNumber(max_abs) + ", " + shownNumber(max_abs) + "]");
    }
    return v;
}

// The "units" object: the length of the centres' units in metres, each in [1e-6, 1e6].
CandidateUnits parseUnits(const json& u, const std::string& name) {
    const std::string where = name + ": units";
    const char* allowed = "a length in metres in [1e-06, 1e+06]";
    if (!u.is_object())
        throw Error(where + " must be an object {\"horizontal_m\": ..., \"vertical_m\": ...}, not " + jsonTypeName(u));
    for (auto it = u.begin(); it != u.end(); ++it)
        if (it.key() != "horizontal_m" && it.key() != "vertical_m")
            throw Error(where + ": unknown key '" + core::printable(it.key(), 40, true) +
                        "'; allowed: horizontal_m, vertical_m");
    CandidateUnits out;
    out.horizontal_m = number(u, "horizontal_m", where, allowed);
    out.vertical_m = number(u, "vertical_m", where, allowed);
    for (const auto& [key, v] : {std::pair{"horizontal_m", out.horizontal_m}, std::pair{"vertical_m", out.vertical_m}})
        if (!(v >= 1e-6 && v <= 1e6))
            throw Error(where + "." + key + " is " + shownNumber(v) + "; allowed: " + allowed);
    return out;
}

}  // namespace

std::vector<Candidate> readCandidates(const std::filesystem::path& file, CandidateUnits* units) {
    const std::string name = "candidates: " + core::printable(file.string(), 400, true);
    return parseCandidates(readTextFile(file, kMaxCandidatesBytes, name + ": the candidates file"), name, units);
}

std::vector<Candidate> parseCandidates(std::string_view text, const std::string& name, CandidateUnits* units) {
    if (text.size() > kMaxCandidatesBytes)
        throw Error(name + ": " + std::to_string(text.size()) + " bytes; allowed: at most " +
                    std::to_string(kMaxCandidatesBytes));
    const json root = parseStrictJson(text, name);
    if (!root.is_object() || !root.contains("candidates"))
        throw Error(name + ": the top level must be an object with 'candidates', a list of detections");
    for (auto it = root.begin(); it != root.end(); ++it)
        if (it.key() != "candidates" && it.key() != "units")
            throw Error(name + ": unknown key '" + core::printable(it.key(), 40, true) +
                        "'; allowed: candidates, units");
    const CandidateUnits read_units = root.contains("units") ? parseUnits(root["units"], name) : CandidateUnits{};
    if (units != nullptr) *units = read_units;
    const json& list = root["candidates"];
    if (!list.is_array()) throw Error(name + ": 'candidates' must be an array, not " + jsonTypeName(list));
    if (list.size() > kMaxCandidates)
        throw Error(name + ": " + std::to_string(list.size()) + " candidates; allowed: at most " +
                    std::to_string(kMaxCandidates));
    std::vector<Candidate> out;
    out.reserve(list.size());
    std::set<std::string> ids;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string where = name + ": candidates[" + std::to_string(i) + "]";
        const json& c = list[i];
        if (!c.is_object()) throw Error(where + " must be an object, not " + jsonTypeName(c));
        for (auto it = c.begin(); it != c.end(); ++it) {
            const std::string& k = it.key();
            if (k != "id" && k != "centre" && k != "size_m" && k != "yaw_deg" && k != "score")
                throw Error(where + ": unknown key '" + core::printable(k, 40, true) +
                            "'; allowed: id, centre, size_m, yaw_deg, score");
        }
        Candidate cand;
        const auto id = c.find("id");
        if (id == c.end() || !id->is_string() || id->get_ref<const std::string&>().empty())
            throw Error(where + ".id must be a non-empty string");
        cand.id = id->get<std::string>();
        if (!ids.insert(cand.id).second)
            throw Error(where + ".id '" + core::printable(cand.id, 40, true) + "' is given twice; allowed: unique ids");
        cand.centre_world = triple(c, "centre", where, "[x, y, z] in world metres", core::kMaxWorldCoordinate_m);
        cand.size_m =
            triple(c, "size_m", where, "[length, width, height], each > 0 metres", core::kMaxLocalCoordinate_m);
        if (cand.size_m.x <= 0 || cand.size_m.y <= 0 || cand.size_m.z <= 0)
            throw Error(where + ".size_m must be > 0 metres in each dimension");
        cand.yaw_deg = c.contains("yaw_deg") ? number(c, "yaw_deg", where, "degrees") : 0.0;
        cand.score = number(c, "score", where, "a number in [0, 1]");
        if (cand.score < 0.0 || cand.score > 1.0)
            throw Error(where + ".score " + std::to_string(cand.score) + " is not in [0, 1]");
        out.push_back(std::move(cand));
    }
    return out;
}

std::string candidatesJson(const std::vector<Candidate>& candidates, const CandidateUnits& units) {
    json list = json::array();
    for (const Candidate& c : candidates) {
        list.push_back({{"id", c.id},
                        {"centre", {c.centre_world.x, c.centre_world.y, c.centre_world.z}},
                        {"size_m", {c.size_m.x, c.size_m.y, c.size_m.z}},
                        {"yaw_deg", c.yaw_deg},
                        {"score", c.score}});
    }
    json root{{"candidates", list}};
    if (!units.metres()) root["units"] = {{"horizontal_m", units.horizontal_m}, {"vertical_m", units.vertical_m}};
    return root.dump(2) + "\n";
}

void writeCandidates(const std::filesystem::path& file, const std::vector<Candidate>& candidates,
                     const CandidateUnits& units) {
    const std::string text = candidatesJson(candidates, units);
    checkWritableDestination(file);
    writeFileAtomic(file, text);
}

}  // namespace io
