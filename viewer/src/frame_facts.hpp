// viewer/src/frame_facts.hpp: what the run log (run_log.hpp, --log-json) records of each
// counted frame and of the whole run; docs/viewer.md lists the keys.
#pragma once
#include "ui/eye_frame_renderer.hpp"
#include "run_log.hpp"

#include <viewer/mode_controller.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <optional>

namespace viewer {

nlohmann::json jsonOf(const glm::dvec3& v);

/// One counted frame.
struct FrameFacts {
    long frame = 0;
    double t_s = 0.0;  // since the run started
    ViewMode mode = ViewMode::Automatic;
    glm::dvec3 orbit_centre_local{0.0};
    bool xr = false;
    std::size_t points_drawn = 0, points_uploaded = 0, points_arrived = 0;
    double frame_ms = 0.0;
    double scale = 1.0;
    const char* colour = "";
    int trial = -1;        // -1: a plain run
    double gpu_ms = -1.0;  // < 0: not timed
    const FrameResult* result = nullptr;
    nlohmann::json tools = nlohmann::json::object();  // the tools' keys (ToolSet::logFrame)
    std::size_t points_drawn_per_eye = 0;             // the most one eye drew (points_drawn: the sum)
};
nlohmann::json frameRecord(const FrameFacts& f);

/// The run as it ended.
struct RunSummary {
    std::string exit_reason, fallback;
    long frames = 0, frames_submitted = 0, first_points_frame = -1;
    std::size_t points_arrived = 0, points_uploaded = 0, point_budget = 0, lod_cells = 0;
    bool cull = true, xr_active_at_end = false, headset_panel = false;
    ViewMode mode = ViewMode::Automatic;
    glm::dvec3 orbit_centre_local{0.0}, origin{0.0};
    nlohmann::json actions;
    double scale = 1.0;
    std::optional<glm::dvec3> designated_world;
    nlohmann::json tools = nlohmann::json::object();  // the tools' keys (ToolSet::logRun)
};
void recordSummary(RunLog& log, const RunSummary& s);

}  // namespace viewer
