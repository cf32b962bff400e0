// study/src/trial_shown.cpp: shown_<N>.json written and read back (study/trial_shown.hpp).
#include <study/trial_shown.hpp>

#include <core/error.hpp>
#include <core/frames.hpp>
#include <io/strict_json.hpp>
#include <platform/safe_file.hpp>

#include <cmath>
#include <cstdio>

namespace study {

namespace {
using json = nlohmann::json;
constexpr std::size_t kMaxShownBytes = std::size_t(64) << 20;

json triple(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
std::string shortNumber(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", v);
    return buffer;
}

/// Reads the fields of one file, each failure one line naming the field.
struct ShownReader {
    std::string file;
    [[noreturn]] void bad(const std::string& where, const std::string& allowed) const {
        throw core::Error("study: --replay " + core::printable(file, 400) + ": " + where + ": allowed " + allowed);
    }
    double number(const json& o, const char* key, const std::string& where, double lo, double hi) const {
        const auto it = o.find(key);
        if (it == o.end() || !it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() < lo ||
            it->get<double>() > hi)
            bad(where + "." + key, "a number in [" + shortNumber(lo) + ", " + shortNumber(hi) + "]");
        return it->get<double>();
    }
    glm::dvec3 point(const json& v, const std::string& where, double max_abs) const {
        if (!v.is_array() || v.size() != 3) bad(where, "three numbers");
        glm::dvec3 p;
        for (int i = 0; i < 3; ++i) {
            const json& c = v[static_cast<std::size_t>(i)];
            if (!c.is_number() || !std::isfinite(c.get<double>()) || std::abs(c.get<double>()) > max_abs)
                bad(where, "three numbers within " + shortNumber(max_abs) + " m");
            p[i] = c.get<double>();
        }
        return p;
    }
    std::string text(const json& o, const char* key, const std::string& where) const {
        const auto it = o.find(key);
        if (it == o.end() || !it->is_string() || it->get<std::string>().empty())
            bad(where + "." + key, "a non-empty string");
        return it->get<std::string>();
    }
};
}  // namespace

std::string shownFileName(int trial_number) { return "shown_" + std::to_string(trial_number) + ".json"; }

std::string formatTrialShown(const TrialShown& shown) {
    json out = json::object();
    if (shown.colour) out["colour"] = viewer::colourModeName(*shown.colour);
    if (shown.eye_dome) out["eye_dome"] = *shown.eye_dome;
    json boxes = json::array();
    for (const core::Candidate& c : shown.candidates)
        boxes.push_back({{"id", c.id},
                         {"centre", triple(c.centre_world)},
                         {"size_m", triple(c.size_m)},
                         {"yaw_deg", c.yaw_deg},
                         {"score", c.score}});
    out["candidates"] = std::move(boxes);
    json marks = json::array();
    for (const viewer::TrialMark& m : shown.marks) {
        if (!m.candidate.empty())
            marks.push_back({{"t_s", m.t_s}, {"candidate", m.candidate}, {"verdict", viewer::verdictName(m.verdict)}});
        else
            marks.push_back(
                {{"t_s", m.t_s}, {"designate", m.designated_world ? triple(*m.designated_world) : json(nullptr)}});
    }
    out["marks"] = std::move(marks);
    if (!shown.terrain_source.empty())
        out["terrain"] = {{"source", shown.terrain_source}};
    else if (!shown.terrain_failure.empty())
        out["terrain"] = {{"failure", shown.terrain_failure}};
    return out.dump() + "\n";
}

TrialShown readTrialShown(const std::filesystem::path& file) {
    const ShownReader r{file.string()};
    const std::string what = "study: --replay " + core::printable(file.string(), 400);
    const json doc = io::parseStrictJson(platform::readOwnOutput(file, kMaxShownBytes, what), what);
    if (!doc.is_object()) r.bad("the top level", "an object");
    for (auto it = doc.begin(); it != doc.end(); ++it)
        if (it.key() != "colour" && it.key() != "eye_dome" && it.key() != "candidates" && it.key() != "marks" &&
            it.key() != "terrain")
            r.bad("key '" + core::printable(it.key(), 40) + "'", "colour, eye_dome, candidates, marks, terrain");
    TrialShown shown;
    if (const auto it = doc.find("colour"); it != doc.end()) {
        if (!it->is_string()) r.bad("colour", "file, height, white, label, above-ground, class, intensity or return");
        try {
            shown.colour = viewer::parseColourMode(it->get<std::string>());
        } catch (const core::Error&) {
            r.bad("colour '" + core::printable(it->get<std::string>(), 40) + "'",
                  "file, height, white, label, above-ground, class, intensity or return");
        }
    }
    if (const auto it = doc.find("eye_dome"); it != doc.end()) {
        if (!it->is_boolean()) r.bad("eye_dome", "true or false");
        shown.eye_dome = it->get<bool>();
    }
    const auto boxes = doc.find("candidates");
    if (boxes == doc.end() || !boxes->is_array()) r.bad("candidates", "an array of boxes");
    for (std::size_t i = 0; i < boxes->size(); ++i) {
        const json& b = (*boxes)[i];
        const std::string where = "candidates[" + std::to_string(i) + "]";
        if (!b.is_object()) r.bad(where, "an object");
        core::Candidate c;
        c.id = r.text(b, "id", where);
        if (!b.contains("centre")) r.bad(where + ".centre", "three numbers");
        if (!b.contains("size_m")) r.bad(where + ".size_m", "three numbers");
        c.centre_world = r.point(b["centre"], where + ".centre", core::kMaxWorldCoordinate_m);
        c.size_m = r.point(b["size_m"], where + ".size_m", core::kMaxLocalCoordinate_m);
        c.yaw_deg = r.number(b, "yaw_deg", where, -360.0, 360.0);
        c.score = r.number(b, "score", where, 0.0, 1.0);
        shown.candidates.push_back(std::move(c));
    }
    const auto marks = doc.find("marks");
    if (marks == doc.end() || !marks->is_array()) r.bad("marks", "an array of marks");
    double last_t_s = 0.0;
    for (std::size_t i = 0; i < marks->size(); ++i) {
        const json& m = (*marks)[i];
        const std::string where = "marks[" + std::to_string(i) + "]";
        if (!m.is_object()) r.bad(where, "an object");
        viewer::TrialMark mark;
        mark.t_s = r.number(m, "t_s", where, last_t_s, 1e6);
        last_t_s = mark.t_s;
        if (const auto d = m.find("designate"); d != m.end()) {
            if (!d->is_null()) mark.designated_world = r.point(*d, where + ".designate", core::kMaxWorldCoordinate_m);
        } else {
            mark.candidate = r.text(m, "candidate", where);
            const std::string v = r.text(m, "verdict", where);
            if (v == "confirmed")
                mark.verdict = viewer::Verdict::Confirmed;
            else if (v == "rejected")
                mark.verdict = viewer::Verdict::Rejected;
            else
                r.bad(where + ".verdict '" + core::printable(v, 40) + "'", "confirmed or rejected");
        }
        shown.marks.push_back(std::move(mark));
    }
    if (const auto it = doc.find("terrain"); it != doc.end()) {
        if (!it->is_object() || it->size() != 1 || !(it->contains("source") || it->contains("failure")))
            r.bad("terrain", "an object with one key, source or failure");
        if (it->contains("source"))
            shown.terrain_source = r.text(*it, "source", "terrain");
        else
            shown.terrain_failure = r.text(*it, "failure", "terrain");
    }
    return shown;
}

}  // namespace study
