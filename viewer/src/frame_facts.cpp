// viewer/src/frame_facts.cpp: the run log's frame records and summary.
#include "frame_facts.hpp"

namespace viewer {

namespace {
nlohmann::json quat(const glm::dquat& q) { return {q.w, q.x, q.y, q.z}; }
}  // namespace

nlohmann::json jsonOf(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json frameRecord(const FrameFacts& f) {
    nlohmann::json j = {{"frame", f.frame},
                        {"t_s", f.t_s},
                        {"mode", modeName(f.mode)},
                        {"orbit_centre_local", jsonOf(f.orbit_centre_local)},
                        {"xr", f.xr},
                        {"points_drawn", f.points_drawn},
                        {"points_drawn_per_eye", f.points_drawn_per_eye},
                        {"points_uploaded", f.points_uploaded},
                        {"points_arrived", f.points_arrived},
                        {"cpu_ms", f.result->cpu_ms},
                        {"frame_ms", f.frame_ms},
                        {"scale", f.scale},
                        {"colour", f.colour}};
    for (const auto& [key, value] : f.tools.items()) j[key] = value;
    if (f.trial >= 0) j["trial"] = f.trial;
    if (f.gpu_ms >= 0.0) j["gpu_ms"] = f.gpu_ms;
    nlohmann::json tracking = nlohmann::json::array(), local = nlohmann::json::array();
    const FrameResult& r = *f.result;
    for (int i = 0; i < (f.xr ? 2 : 1); ++i) {
        nlohmann::json e = {{"position", jsonOf(r.eyes_tracking[i].position)},
                            {"orientation", quat(glm::quat_cast(r.eyes_tracking[i].rotation))}};
        if (f.xr) {
            const XrEye& x = r.xr_frame.eyes[i];
            e["fov_rad"] = {x.angle_left, x.angle_right, x.angle_up, x.angle_down};
        }
        tracking.push_back(e);
        local.push_back({{"position", jsonOf(r.eyes_local[i].position)},
                         {"gaze", jsonOf(r.eyes_local[i].rotation * glm::dvec3(0, 0, -1))}});
    }
    j["eyes_tracking"] = tracking;
    j["eyes_local"] = local;
    if (f.xr) {
        j["display_time_ns"] = r.xr_frame.display_time_ns;
        j["display_period_ns"] = r.xr_frame.display_period_ns;
        j["input_time_ns"] = r.xr_frame.input_time_ns;
        j["depth_submitted"] = r.depth_range.has_value();
    }
    return j;
}

void recordSummary(RunLog& log, const RunSummary& s) {
    log.set("exit", s.exit_reason);
    log.set("frames_counted", s.frames);
    log.set("frames_submitted", s.frames_submitted);
    log.set("first_points_frame", s.first_points_frame);
    log.set("points_arrived", s.points_arrived);
    log.set("points_uploaded", s.points_uploaded);
    log.set("point_budget", s.point_budget);
    log.set("cull", s.cull);
    log.set("lod_cells", s.lod_cells);
    log.set("mode_final", modeName(s.mode));
    log.set("fallback", s.fallback);
    log.set("xr_active_at_end", s.xr_active_at_end);
    log.set("orbit_centre_local", jsonOf(s.orbit_centre_local));
    log.set("origin", jsonOf(s.origin));
    log.set("actions", s.actions);
    log.set("scale_final", s.scale);
    log.set("headset_panel", s.headset_panel);
    if (s.designated_world) log.set("designated_world", jsonOf(*s.designated_world));
    for (const auto& [key, value] : s.tools.items()) log.set(key, value);
}

}  // namespace viewer
