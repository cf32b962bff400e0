// viewer/script.hpp: the viewer's `--script` files, scripted key presses by frame.
//
// Outside input, so the parser depends only on engine and the standard library: the
// fuzz build (engine only, no GL) compiles viewer/src/script.cpp into fuzz_view_script.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace viewer {

/// A scripted key press at a frame (for tests and demos): "<frame> <key>" lines.
struct ScriptEvent {
    long frame = 0;
    enum class Key { Space, Escape } key = Key::Space;
    /// "desktop+N": N frames after the drop to desktop mode (a lost runtime), so a test
    /// acts on that event instead of guessing its frame; waits while none has happened.
    bool after_desktop = false;
};

/// The largest script read (a line per key press: a megabyte is tens of thousands).
inline constexpr std::size_t kMaxScriptBytes = std::size_t(1) << 20;

/// Parses script text: one "<frame> space|escape" per line, frame a whole number >= 0 or
/// desktop+N, '#' starts a comment, blank lines skipped. Throws engine::Error("<name> line
/// N: ...; allowed '<frame> space|escape', <frame> N or desktop+N") on a bad line; tokens quoted in it are shown escaped
/// and cut to 40 characters (engine::printable).
std::vector<ScriptEvent> parseScript(std::string_view text, const std::string& name);

/// Reads and parses a script file (parseScript, named "view: --script <file>").
/// Throws engine::Error("view: --script <file>: is a directory; ...") for anything but a
/// regular file of at most kMaxScriptBytes (engine::readTextFile). Bytes of the file
/// are shown escaped.
std::vector<ScriptEvent> readScript(const std::filesystem::path& file);

}  // namespace viewer
