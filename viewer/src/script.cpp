// viewer/src/script.cpp: the `--script` parser (engine and the standard library only,
// so the fuzz build compiles it without GL).
#include <viewer/script.hpp>

#include <engine/error.hpp>
#include <engine/safe_file.hpp>

#include <sstream>
#include <stdexcept>

namespace viewer {

std::vector<ScriptEvent> parseScript(std::string_view text, const std::string& name) {
    std::vector<ScriptEvent> events;
    std::istringstream in{std::string(text)};
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
            constexpr std::string_view kDesktop = "desktop+";
            ev.after_desktop = frame_text.starts_with(kDesktop);
            const std::string number_text = ev.after_desktop ? frame_text.substr(kDesktop.size()) : frame_text;
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

std::vector<ScriptEvent> readScript(const std::filesystem::path& file) {
    const std::string name = "view: --script " + engine::printable(file.string(), 400);
    return parseScript(engine::readTextFile(file, kMaxScriptBytes, name + ":"), name);
}

}  // namespace viewer
