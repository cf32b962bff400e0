// metric/trace.hpp: the operator's head path from a study's trace_<trial>.csv, as camera
// poses for the visibility metric: how visible the target was from where the operator
// actually looked, instead of from the automatic orbit.
//
// The trace's first eight columns are, in this order (viewer/trial.hpp):
//   t_s, head_x, head_y, head_z, head_qw, head_qx, head_qy, head_qz
// t_s in seconds since the trial started (never decreasing); head_x..z the point between
// the eyes in world coordinates (metres, z up); head_q* a unit quaternion rotating the
// head frame (OpenXR view space: x right, y up, -z forward) into the world frame. Further
// columns (mode, scale, hit_x, ...) are allowed and ignored, but every row has as many
// fields as the header.
#pragma once
#include <render/orbit_camera.hpp>

#include <glm/gtc/quaternion.hpp>

#include <cstddef>
#include <filesystem>
#include <string_view>
#include <vector>

namespace metric {

struct HeadSample {
    double t_s = 0.0;
    glm::dvec3 head_world{0.0};
    glm::dquat head_orientation{1.0, 0.0, 0.0, 0.0};  // normalised
};

/// Largest trace file read (a 2 h trial at 90 Hz is about 100 MB).
inline constexpr std::size_t kMaxTraceBytes = std::size_t(512) << 20;

/// Reads a trace CSV strictly (regular file, at most kMaxTraceBytes). Throws core::Error
/// "trace: <file>: line N, column <name>: <what>; allowed <what>" for a wrong header, a
/// field that is not a finite number, a row with too few or too many fields, a quaternion
/// whose norm is not within 1e-3 of 1, t_s decreasing or negative, or no samples.
std::vector<HeadSample> readTrace(const std::filesystem::path& file);
/// As readTrace, from the file's text; `name` is used in messages.
std::vector<HeadSample> parseTrace(std::string_view text, const std::filesystem::path& name);

/// The camera of a head sample (world frame): eye at the head, looking along the head's
/// -z, with the head's y as up (roll kept).
render::CameraPose cameraFromHead(const HeadSample& sample);

/// The first sample, then each sample at least `step_s` (>= 0) after the last one kept:
/// a long trace subsampled in time. step_s = 0 keeps every sample.
std::vector<HeadSample> everyStep(const std::vector<HeadSample>& samples, double step_s);

}  // namespace metric
