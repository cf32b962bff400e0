// io/trace_file.hpp: a study's head trace, trace_<N>.csv: its one writer and its one
// reader (the study writes it, the study's replay and the metric's --trace read it).
//
// The header names the columns, comma separated; the rows follow, one per frame:
//   t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,mode,scale,hit_x,hit_y,hit_z
// t_s: seconds since the trial started; head_x..z: the point between the eyes, world
// coordinates (metres, z up); head_q*: a unit quaternion (w first) turning the head frame
// (OpenXR view space: x right, y up, -z forward) into the world frame; mode: automatic or
// free; scale: the world's zoom scale (> 0); hit_x..z: where the pointer meets the cloud,
// world coordinates, three empty fields when it meets nothing. docs/study.md lists them.
//
// What the reader accepts (docs/study.md, "Reading a trace back"):
// - the header's first eight columns are t_s .. head_qz in this order; when its columns
//   9 to 13 are mode,scale,hit_x,hit_y,hit_z they are read too (the study columns);
//   any further column is allowed and ignored;
// - every row has as many fields as the header; no empty lines; a "\r" before a line
//   break is dropped (CRLF files); the last line may lack its line break;
// - numbers are plain decimal text (std::from_chars: no spaces, no leading '+') and
//   finite; t_s from 0 to kMaxTraceTime_s and never decreasing (equal times allowed: the
//   writer's six decimals can round two close frames to one time); |head_x..z| <= 1e9 m;
//   the quaternion's norm within 1e-3 of 1 (it is returned normalised);
// - mode is automatic or free; scale > 0 and at most kMaxTraceScale; hit_x..z all
//   numbers (|hit_x..z| <= 1e9 m) or all empty;
// - at least one row; readTrace, which holds them all, at most kMaxTraceRows.
#pragma once
#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace io {

/// The viewer's view mode as a trace records it.
enum class TraceMode { Automatic, Free };
/// "automatic", "free".
const char* traceModeName(TraceMode mode);

/// One row of a trace: one frame.
struct TraceRow {
    double t_s = 0.0;
    glm::dvec3 head_world{0.0};
    glm::dquat head_orientation{1.0, 0.0, 0.0, 0.0};
    TraceMode mode = TraceMode::Automatic;
    double scale = 1.0;
    std::optional<glm::dvec3> hit_world;
};

/// A trace as read back.
struct Trace {
    std::vector<TraceRow> rows;
    /// The header has the study columns (mode, scale, hit_*); without them each row's
    /// mode, scale and hit are the defaults above (a head path only).
    bool study_columns = false;
};

/// The header line the writer writes (no line break).
inline constexpr std::string_view kTraceHeader =
    "t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,mode,scale,hit_x,hit_y,hit_z";

/// Largest trace file read (a 2 h trial at 90 Hz is about 100 MB).
inline constexpr std::size_t kMaxTraceBytes = std::size_t(512) << 20;

/// Most rows readTrace holds (3.2 h at 90 Hz; about 117 MB as TraceRow): a longer trace
/// is refused, naming the line past the bound (forEachTraceRow holds none and has none).
inline constexpr std::size_t kMaxTraceRows = std::size_t(1) << 20;

/// Latest t_s of a row, seconds (about 11.6 days, past any trial): a replay plays a trace
/// in real time, so a later time would hold it for as long.
inline constexpr double kMaxTraceTime_s = 1e6;

/// Largest zoom scale of a row (the viewer's own range is far narrower).
inline constexpr double kMaxTraceScale = 1e6;

/// One row as the writer writes it, line break included: times and positions with six
/// decimals, the quaternion with nine, the scale with up to nine significant digits.
std::string formatTraceRow(const TraceRow& row);

/// Parses a trace's text by the rules above; `name` is used in messages. Throws
/// core::Error "trace: <name>: line N, column <column>: <what>; allowed <what>" (the
/// column left out where the whole line is wrong).
Trace parseTrace(std::string_view text, const std::filesystem::path& name);
/// Reads a trace file (regular file, at most kMaxTraceBytes and kMaxTraceRows rows) as
/// parseTrace does, a block at a time (forEachTraceRow): what it holds is the rows, no
/// copy of the text. Throws as forEachTraceRow, "trace: <file>: <bytes> bytes; allowed
/// at most 536870912" or "trace: <file>: line N: more than 1048576 samples; allowed at most 1048576".
Trace readTrace(const std::filesystem::path& file);

/// Bytes read at a time by forEachTraceRow, and the longest line it accepts.
inline constexpr std::size_t kTraceBlockBytes = std::size_t(1) << 20;
inline constexpr std::size_t kMaxTraceLineBytes = std::size_t(1) << 20;

/// Reads a trace file of any length by the same rules as parseTrace, a block at a time,
/// handing each row to `visit` in order and holding no more than a block and a line: a
/// trace too long for readTrace is read in bounded memory. Throws as parseTrace (a row
/// handed on before a later line fails stays handed on), "trace: <file>: line N: longer
/// than 1048576 bytes" for a line beyond kMaxTraceLineBytes, or when the file is not a
/// regular file (platform::checkInputFile). Returns whether the
/// header has the study columns.
bool forEachTraceRow(const std::filesystem::path& file, const std::function<void(const TraceRow&)>& visit);

}  // namespace io
