// viewer/src/options.cpp: parsing and validation of the viewer's options and scripts.
#include <viewer/viewer.hpp>

#include <engine/error.hpp>
#include <engine/safe_file.hpp>

#include <cmath>
#include <sstream>

namespace viewer {

MirrorEyes parseMirrorEyes(const std::string& name) {
    if (name == "left") return MirrorEyes::Left;
    if (name == "right") return MirrorEyes::Right;
    if (name == "both") return MirrorEyes::Both;
    throw engine::Error("view: --mirror '" + name + "' is not one of left, right, both");
}

ColourMode parseColourMode(const std::string& name) {
    if (name == "file") return ColourMode::File;
    if (name == "height") return ColourMode::HeightJet;
    if (name == "white") return ColourMode::White;
    if (name == "label") return ColourMode::Label;
    throw engine::Error("view: --colour '" + name + "' is not one of file, height, white, label");
}

const char* colourModeName(ColourMode mode) {
    switch (mode) {
        case ColourMode::File: return "file";
        case ColourMode::HeightJet: return "height";
        case ColourMode::White: return "white";
        case ColourMode::Label: return "label";
    }
    return "?";
}

std::vector<ScriptEvent> readScript(const std::filesystem::path& file) {
    const std::string name = "view: --script " + engine::printable(file.string(), 400);
    const std::string text = engine::readTextFile(file, kMaxScriptBytes, name + ":");
    std::vector<ScriptEvent> events;
    std::istringstream in(text);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream ls(line);
        std::string frame_text, key, extra;
        if (!(ls >> frame_text)) continue;
        auto bad = [&](const std::string& what) {
            return engine::Error(name + " line " + std::to_string(number) + ": " + what +
                                 "; allowed '<frame> space|escape', <frame> N or desktop+N");
        };
        // Tokens are quoted escaped and short: a binary file must not reach the terminal.
        auto quoted = [](const std::string& token) { return "'" + engine::printable(token, 40) + "'"; };
        ScriptEvent ev;
        try {
            const std::string prefix = "desktop+";
            ev.after_desktop = frame_text.rfind(prefix, 0) == 0;
            const std::string number_text = ev.after_desktop ? frame_text.substr(prefix.size()) : frame_text;
            std::size_t used = 0;
            ev.frame = std::stol(number_text, &used);
            if (used != number_text.size() || ev.frame < 0) throw std::invalid_argument("frame");
        } catch (const std::exception&) {
            throw bad("frame " + quoted(frame_text) + " is not a whole number >= 0");
        }
        if (!(ls >> key)) throw bad("missing key");
        if (key == "space") ev.key = ScriptEvent::Key::Space;
        else if (key == "escape") ev.key = ScriptEvent::Key::Escape;
        else throw bad("key " + quoted(key) + " is not one of space, escape");
        if (ls >> extra) throw bad("unexpected " + quoted(extra));
        events.push_back(ev);
    }
    return events;
}

void validate(const ViewerOptions& o) {
    validate(o.modes);
    auto fail = [](const std::string& what) { throw engine::Error("view: " + what); };
    if (o.window_width < 64 || o.window_width > 16384 || o.window_height < 64 || o.window_height > 16384)
        fail("window size " + std::to_string(o.window_width) + "x" + std::to_string(o.window_height) +
             ": allowed 64..16384 each");
    if (o.frames < 0) fail("--frames " + std::to_string(o.frames) + ": allowed >= 0 (0 = until closed)");
    if (!(std::isfinite(o.timeout_s) && o.timeout_s >= 0.0))
        fail("--timeout " + engine::shownNumber(o.timeout_s) + ": allowed a finite value >= 0");
    if (!(o.style.point_size_px >= 1.0f && o.style.point_size_px <= 64.0f))
        fail("--point-size " + engine::shownNumber(o.style.point_size_px) + ": allowed [1, 64]");
    if (o.style.jet_entries < 2 || o.style.jet_entries > 256)
        fail("jet entries " + std::to_string(o.style.jet_entries) + ": allowed [2, 256]");
    if (o.upload_points_per_frame < 1024)
        fail("--upload-budget " + std::to_string(o.upload_points_per_frame) + ": allowed >= 1024 points");
    if (!o.screenshot.empty() && o.screenshot.extension() != ".png")
        fail("--screenshot " + o.screenshot.string() + ": the file name must end in .png");
}

}  // namespace viewer
