// viewer/script.hpp: the viewer's `--script` files, scripted operator actions by frame.
//
// Outside input, so the parser depends only on core, io and the standard library: the
// fuzz build (core, platform and io only, no GL) compiles viewer/src/script.cpp into fuzz_view_script.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace viewer {

/// A scripted action at a frame (for tests and demos): "<frame> <action> [args]" lines.
struct ScriptEvent {
    long frame = 0;
    enum class Key {
        Space,        // toggle automatic / free mode
        Escape,       // quit
        Aim,          // point the active pointer at world point `point` from the head
        Designate,    // mark the picked point
        Confirm,      // this designation (or the candidate pointed at) is the target
        Reject,       // the candidate pointed at is not a target (else: drop the designation)
        NoTarget,     // the operator declares there is no target
        GrabScale,    // set the world scale to `value` about the pointer's hit (or the head)
        Next,         // dismiss the ready screen (nothing when none is up)
        Answer,       // answer the questionnaire item on screen with `text` (waits for one)
        PointAnswer,  // headset: aim a controller ray from the head at rating `value`'s button on
                      // the panel and pull the trigger (waits for an item)
        Cut,          // toggle the cutting volume (as V does)
        Colour,       // step to the next colour mode (as C does)
    } key = Key::Space;
    /// "desktop+N": N frames after the drop to desktop mode (a lost runtime), so a test
    /// acts on that event instead of guessing its frame; waits while none has happened.
    bool after_desktop = false;
    /// "loaded+N": N frames after the whole cloud is on the GPU (the current trial's, in a
    /// study), so a test that needs the full cloud on screen waits for it, however slowly
    /// the loader or the generator runs.
    bool after_loaded = false;
    /// "pickable+N": N frames after the pointer can first pick (the pick index over what is
    /// on the GPU is built; the current trial's, in a study), so a scripted designation
    /// never races the indexing.
    bool after_pickable = false;
    /// "+N": N frames after the previous line's action ran (so a script can follow a
    /// ready screen that waits for its cloud, however long that takes).
    bool relative = false;
    double point[3] = {0.0, 0.0, 0.0};  // Aim: world coordinates (metres)
    double value = 0.0;                 // GrabScale: the scale, > 0
    std::string text;                   // Answer: a rating's number or a text item's text
};

/// The latest frame a script line may name (about 4.6 months at 90 Hz): N in every form,
/// and a run of +N lines added to the line before them. So the frame loop's sums of a
/// line's frame and its base never overflow.
inline constexpr long kMaxScriptFrame = 1'000'000'000;

/// The largest script read (a line per action: a megabyte is tens of thousands).
inline constexpr std::size_t kMaxScriptBytes = std::size_t(1) << 20;

/// The longest `answer` text of a script line.
inline constexpr std::size_t kMaxScriptAnswerBytes = 1000;

/// "space", "escape", "aim", "designate", "confirm", "reject", "no_target", "grab_scale", "next",
/// "answer", "point_answer", "cut", "colour".
const char* scriptKeyName(ScriptEvent::Key key);

/// Parses script text: one "<frame> <action>" per line, frame a whole number from 0 to
/// kMaxScriptFrame (and so the frame a +N line adds up to),
/// desktop+N, loaded+N (after the whole cloud is on the GPU), pickable+N (after the pointer can first pick) or +N (after the previous action); actions space, escape, aim X Y Z (finite numbers), designate, confirm,
/// reject, no_target, grab_scale S (a finite number > 0), next, cut, colour, answer TEXT (the rest of
/// the line, spaces trimmed, 1 to kMaxScriptAnswerBytes bytes), point_answer N (a whole
/// number); '#' starts a comment,
/// blank lines skipped. Throws core::Error("<name> line N: ...; allowed '<frame>
/// <action>' ...") on a bad line; tokens quoted in it are shown escaped and cut to 40
/// characters (core::printable).
std::vector<ScriptEvent> parseScript(std::string_view text, const std::string& name);

/// Writes events back as script text that parses to the same events (numbers with 17
/// significant digits).
std::string formatScript(const std::vector<ScriptEvent>& events);

/// Reads and parses a script file (parseScript, named "view: --script <file>").
/// Throws core::Error("view: --script <file>: is a directory; ...") for anything but a
/// regular file of at most kMaxScriptBytes (platform::readTextFile). Bytes of the file
/// are shown escaped.
std::vector<ScriptEvent> readScript(const std::filesystem::path& file);

}  // namespace viewer
