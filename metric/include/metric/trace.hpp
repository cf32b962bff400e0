// metric/trace.hpp: the operator's head path from a study's trace_<trial>.csv (read by
// io/trace_file.hpp, whose rules docs/metric.md repeats), as camera poses for the
// visibility metric: how visible the target was from where the operator actually looked,
// instead of from the automatic orbit. Only the head columns (t_s, head_x..z, head_q*)
// are used; a trace of those eight columns alone is a head path too.
#pragma once
#include <io/trace_file.hpp>
#include <render/orbit_camera.hpp>

#include <cstddef>
#include <filesystem>
#include <vector>

namespace metric {

/// The camera of a trace row (world frame): eye at the head, looking along the head's
/// -z, with the head's y as up (roll kept).
render::CameraPose cameraFromHead(const io::TraceRow& sample);

/// The first row, then each row at least `step_s` (>= 0) after the last one kept: a long
/// trace subsampled in time. step_s = 0 keeps every row.
std::vector<io::TraceRow> everyStep(const std::vector<io::TraceRow>& samples, double step_s);

/// The poses of a trace file: the camera of every row everyStep would keep, read with
/// io::forEachTraceRow so that only the kept poses are held, never the file or its
/// rows. `samples` gets the file's row count. Throws core::Error as the reader does,
/// or "metric: --trace <file>: more than <max_poses> samples are at least <step_s> s
/// apart; allowed at most <max_poses> views (raise --trace-step-s)" as soon as one more
/// pose than max_poses would be kept.
std::vector<render::CameraPose> tracePoses(const std::filesystem::path& file, double step_s, std::size_t max_poses,
                                           std::size_t& samples);

}  // namespace metric
