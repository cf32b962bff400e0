// fuzz/fuzz_view_script.cpp: libFuzzer target for viewer::parseScript, the parser of the
// viewer's `--script` files (viewer/src/script.cpp, compiled here without the rest of
// the viewer). The contract: a list of actions or an core::Error, nothing else;
// every accepted frame is from 0 to viewer::kMaxScriptFrame, and so is the sum of a run of
// +N lines with the line they follow (the frame loop adds them to a base, so they must
// never overflow); there is at most one event per line, and writing the
// events back with viewer::formatScript parses to the same events (frames, actions,
// aim points and scales). An error is one printable line that names the script and the line.
#include <viewer/script.hpp>

#include <core/error.hpp>
#include "check_message.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace {

constexpr const char* kName = "view: --script fuzz.txt";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // readScript refuses larger files before parsing.
    if (size > viewer::kMaxScriptBytes) return -1;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const std::vector<viewer::ScriptEvent> events = viewer::parseScript(text, kName);
        const std::size_t lines = std::size_t(std::count(text.begin(), text.end(), '\n')) + 1;
        if (events.size() > lines) std::abort();
        long chain = 0;
        for (const viewer::ScriptEvent& ev : events) {
            if (ev.frame < 0 || ev.frame > viewer::kMaxScriptFrame) std::abort();
            chain = ev.relative ? chain + ev.frame : ev.frame;
            if (chain > viewer::kMaxScriptFrame) std::abort();
        }
        const std::vector<viewer::ScriptEvent> again = viewer::parseScript(viewer::formatScript(events), kName);
        if (again.size() != events.size()) std::abort();
        for (std::size_t i = 0; i < events.size(); ++i)
            if (again[i].frame != events[i].frame || again[i].key != events[i].key ||
                again[i].after_desktop != events[i].after_desktop || again[i].relative != events[i].relative ||
                again[i].after_loaded != events[i].after_loaded ||
                again[i].after_pickable != events[i].after_pickable || again[i].value != events[i].value ||
                again[i].point[0] != events[i].point[0] || again[i].point[1] != events[i].point[1] ||
                again[i].point[2] != events[i].point[2])
                std::abort();
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what());
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
    }
    return 0;
}
