// fuzz/fuzz_view_replay.cpp: libFuzzer target for the replay's input: io::parseTrace, the
// rules of the trace `study --replay` plays (io::readTrace reads a file by the same rules,
// a block at a time), and viewer::ReplayPlayer playing what it accepts
// (viewer/src/input/replay_player.cpp, compiled here without the rest of the viewer).
// The contract: either a trace whose every value is finite and within the reader's bounds
// (times from 0 to io::kMaxTraceTime_s and in order, head and hit within 1e9 m, a unit
// quaternion, a scale in (0, io::kMaxTraceScale]), at most one row per line, that the
// player plays to its last sample once its clock has passed the last time, and reports
// done on the call after; or one printable error line naming the trace and the line.
#include "input/replay_player.hpp"

#include <core/error.hpp>
#include <io/trace_file.hpp>
#include "check_message.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace {

constexpr const char* kName = "fuzz.csv";
// Inputs up to a few blocks of forEachTraceRow: enough for every rule, cheap to mutate.
constexpr std::size_t kMaxInputBytes = std::size_t(4) << 20;

bool within(const glm::dvec3& v, double bound) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::abs(v.x) <= bound &&
           std::abs(v.y) <= bound && std::abs(v.z) <= bound;
}

void checkRows(const io::Trace& trace, std::string_view text) {
    const std::size_t lines = std::size_t(std::count(text.begin(), text.end(), '\n')) + 1;
    if (trace.rows.empty() || trace.rows.size() >= lines) std::abort();  // the header takes a line
    double last_t_s = 0.0;
    for (const io::TraceRow& r : trace.rows) {
        if (!(r.t_s >= last_t_s && r.t_s <= io::kMaxTraceTime_s)) std::abort();
        last_t_s = r.t_s;
        if (!within(r.head_world, 1e9)) std::abort();
        const glm::dquat& q = r.head_orientation;
        if (!(std::abs(glm::length(q) - 1.0) <= 1e-9)) std::abort();
        if (!(r.scale > 0.0 && r.scale <= io::kMaxTraceScale)) std::abort();
        if (r.hit_world && !within(*r.hit_world, 1e9)) std::abort();
    }
}

// The player shows nothing before the cloud is loaded, the last sample once the clock has
// passed the trace's span, and reports done on the call after.
void checkPlayback(const io::Trace& trace) {
    std::vector<viewer::TraceSample> samples;
    samples.reserve(trace.rows.size());
    for (const io::TraceRow& r : trace.rows) samples.push_back(viewer::toTraceSample(r));
    viewer::ReplayPlayer player(samples);
    using Clock = viewer::ReplayPlayer::Clock;
    const Clock::time_point start{};
    if (player.take(false, start).replay) std::abort();
    const viewer::OperatorInput first = player.take(true, start);
    if (!first.replay) std::abort();
    const double span_s = trace.rows.back().t_s - trace.rows.front().t_s;
    const auto end = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(span_s + 1.0));
    const viewer::OperatorInput last = player.take(true, end);
    if (!last.replay || last.replay->t_s != trace.rows.back().t_s) std::abort();
    const viewer::OperatorInput after = player.take(true, end);
    if (!after.replay_done) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > kMaxInputBytes) return -1;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const io::Trace trace = io::parseTrace(text, kName);
        checkRows(trace, text);
        checkPlayback(trace);
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what());
        if (std::string(e.what()).rfind(std::string("trace: ") + kName + ": line ", 0) != 0) std::abort();
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
    }
    return 0;
}
