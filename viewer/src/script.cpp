// viewer/src/script.cpp: the `--script` parser (core, io and the standard library only,
// so the fuzz build compiles it without GL).
#include <viewer/script.hpp>

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace viewer {

namespace {
using Key = ScriptEvent::Key;
constexpr std::array<std::pair<Key, const char*>, 13> kKeys = {{{Key::Space, "space"},
                                                                {Key::Escape, "escape"},
                                                                {Key::Aim, "aim"},
                                                                {Key::Designate, "designate"},
                                                                {Key::Confirm, "confirm"},
                                                                {Key::Reject, "reject"},
                                                                {Key::NoTarget, "no_target"},
                                                                {Key::GrabScale, "grab_scale"},
                                                                {Key::Next, "next"},
                                                                {Key::Answer, "answer"},
                                                                {Key::PointAnswer, "point_answer"},
                                                                {Key::Cut, "cut"},
                                                                {Key::Colour, "colour"}}};
constexpr const char* kAllowed =
    "; allowed '<frame> space|escape|designate|confirm|reject|no_target|next|cut|colour', '<frame> aim X Y Z', "
    "'<frame> grab_scale S', '<frame> answer TEXT', '<frame> point_answer N', <frame> N, desktop+N, loaded+N, "
    "pickable+N or +N";

/// A whole token as a finite double (no hex, no inf/nan), else nullopt.
bool parseNumber(const std::string& token, double& out) {
    if (token.empty() || token.find_first_of("xXnNiI") != std::string::npos) return false;
    char* end = nullptr;
    out = std::strtod(token.c_str(), &end);
    return end == token.c_str() + token.size() && std::isfinite(out);
}
}  // namespace

const char* scriptKeyName(Key key) {
    for (const auto& [k, name] : kKeys)
        if (k == key) return name;
    return "?";
}

std::vector<ScriptEvent> parseScript(std::string_view text, const std::string& name) {
    std::vector<ScriptEvent> events;
    std::istringstream in{std::string(text)};
    std::string line;
    // Frames from the start, or from the last desktop+/loaded+/pickable+ line, that the
    // previous line names: a +N line adds to it, and the sum is held to the same bound.
    long chain = 0;
    for (int number = 1; std::getline(in, line); ++number) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream ls(line);
        std::string frame_text, key, extra;
        if (!(ls >> frame_text)) continue;
        auto bad = [&](const std::string& what) {
            return core::Error(name + " line " + std::to_string(number) + ": " + what + kAllowed);
        };
        // A token is quoted only when it could be a script word (letters, digits, + - . _,
        // at most 32 of them): a binary file must not reach the terminal, and a file that is
        // no script (a password file named by mistake or not) shows nothing of itself.
        auto quoted = [](const std::string& token) {
            const bool word =
                token.size() <= 32 && std::all_of(token.begin(), token.end(), [](char c) {
                    return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.' || c == '_';
                });
            return word ? "'" + token + "'" : "(" + std::to_string(token.size()) + " bytes, not shown)";
        };
        ScriptEvent ev;
        try {
            constexpr std::string_view kDesktop = "desktop+", kLoaded = "loaded+", kPickable = "pickable+";
            ev.after_desktop = frame_text.starts_with(kDesktop);
            ev.after_loaded = frame_text.starts_with(kLoaded);
            ev.after_pickable = frame_text.starts_with(kPickable);
            ev.relative = frame_text.starts_with('+');
            const std::string number_text = ev.after_desktop    ? frame_text.substr(kDesktop.size())
                                            : ev.after_loaded   ? frame_text.substr(kLoaded.size())
                                            : ev.after_pickable ? frame_text.substr(kPickable.size())
                                            : ev.relative       ? frame_text.substr(1)
                                                                : frame_text;
            if (number_text.empty() || number_text[0] < '0' || number_text[0] > '9')
                throw std::invalid_argument("frame");
            std::size_t used = 0;
            ev.frame = std::stol(number_text, &used);
            if (used != number_text.size() || ev.frame < 0 || ev.frame > kMaxScriptFrame)
                throw std::invalid_argument("frame");
        } catch (const std::exception&) {
            throw bad("frame " + quoted(frame_text) + " is not a whole number from 0 to " +
                      std::to_string(kMaxScriptFrame));
        }
        chain = ev.relative ? chain + ev.frame : ev.frame;  // both at most kMaxScriptFrame: no overflow
        if (chain > kMaxScriptFrame)
            throw bad("frame " + quoted(frame_text) + " puts the action " + std::to_string(chain) +
                      " frames after the start (or the last desktop+, loaded+ or pickable+ line); at most " +
                      std::to_string(kMaxScriptFrame));
        if (!(ls >> key)) throw bad("missing action");
        bool known = false;
        for (const auto& [k, key_name] : kKeys)
            if (key == key_name) {
                ev.key = k;
                known = true;
            }
        if (!known)
            throw bad("action " + quoted(key) +
                      " is not one of space, escape, aim, designate, confirm, reject, no_target, grab_scale, next, "
                      "answer, point_answer, cut, colour");
        if (ev.key == Key::Aim) {
            for (int i = 0; i < 3; ++i) {
                std::string token;
                if (!(ls >> token)) throw bad("aim needs X Y Z (world metres)");
                if (!parseNumber(token, ev.point[i]))
                    throw bad("aim coordinate " + quoted(token) + " is not a finite number");
            }
        } else if (ev.key == Key::GrabScale) {
            std::string token;
            if (!(ls >> token)) throw bad("grab_scale needs a scale S");
            if (!parseNumber(token, ev.value) || !(ev.value > 0.0))
                throw bad("grab_scale " + quoted(token) + " is not a finite number > 0");
        } else if (ev.key == Key::PointAnswer) {
            std::string token;
            if (!(ls >> token)) throw bad("point_answer needs a rating N");
            if (!parseNumber(token, ev.value) || ev.value != std::floor(ev.value) || std::abs(ev.value) > 1e6)
                throw bad("point_answer " + quoted(token) + " is not a whole number");
        } else if (ev.key == Key::Answer) {
            std::string rest;
            std::getline(ls, rest);
            const auto first = rest.find_first_not_of(" \t\r");
            const auto last = rest.find_last_not_of(" \t\r");
            if (first == std::string::npos) throw bad("answer needs a rating or a text");
            ev.text = rest.substr(first, last - first + 1);
            if (ev.text.size() > kMaxScriptAnswerBytes)
                throw bad("answer of " + std::to_string(ev.text.size()) + " bytes; at most " +
                          std::to_string(kMaxScriptAnswerBytes));
        }
        if (ls >> extra) throw bad("unexpected " + quoted(extra));
        events.push_back(ev);
    }
    return events;
}

std::string formatScript(const std::vector<ScriptEvent>& events) {
    std::string text;
    char number[64];
    for (const ScriptEvent& ev : events) {
        text += (ev.after_desktop    ? "desktop+"
                 : ev.after_loaded   ? "loaded+"
                 : ev.after_pickable ? "pickable+"
                 : ev.relative       ? "+"
                                     : "") +
                std::to_string(ev.frame) + " " + scriptKeyName(ev.key);
        if (ev.key == Key::Aim)
            for (double v : ev.point) {
                std::snprintf(number, sizeof number, " %.17g", v);
                text += number;
            }
        if (ev.key == Key::GrabScale || ev.key == Key::PointAnswer) {
            std::snprintf(number, sizeof number, " %.17g", ev.value);
            text += number;
        }
        if (ev.key == Key::Answer) text += " " + ev.text;
        text += "\n";
    }
    return text;
}

std::vector<ScriptEvent> readScript(const std::filesystem::path& file) {
    const std::string name = "view: --script " + core::printable(file.string(), 400);
    return parseScript(platform::readTextFile(file, kMaxScriptBytes, name + ":"), name);
}

}  // namespace viewer
