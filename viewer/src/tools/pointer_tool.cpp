// viewer/src/tools/pointer_tool.cpp: the laser pointer's pick and drawing.
#include "tools/pointer_tool.hpp"

#include "ui/panel.hpp"

#include <core/scene.hpp>

#include <chrono>
#include <cmath>
#include <numbers>

namespace viewer {

std::optional<LocalRay> pointerRayOf(const PointerSources& p) {
    const RigPose& head = p.head_local;
    if (p.aim_local) {
        const glm::dvec3 d = *p.aim_local - head.position;
        if (glm::length(d) > 0.0) return LocalRay{head.position, glm::normalize(d)};
    }
    if (p.controller) {
        const glm::dvec3 o = p.rig.apply(p.zoom->apply(p.controller->origin));
        return LocalRay{o, glm::normalize(p.rig.rotation * p.controller->direction)};
    }
    if (p.replay || !p.cursor_px || p.window_w <= 0 || p.window_h <= 0) return std::nullopt;
    const double t = std::tan(p.vfov_deg * std::numbers::pi / 360.0);
    const double w = p.window_w, h = p.window_h;
    const double nx = 2.0 * p.cursor_px->x / w - 1.0, ny = 1.0 - 2.0 * p.cursor_px->y / h;
    const glm::dvec3 dir_eye(nx * t * w / h, ny * t, -1.0);
    return LocalRay{head.position, glm::normalize(head.rotation * dir_eye)};
}

void PointerTool::update(const std::optional<LocalRay>& ray) {
    ray_ = ray;
    hit_.reset();
    if (!ray_ || !index_) return;
    const auto t0 = std::chrono::steady_clock::now();
    hit_ = index_->pick(ray_->origin, ray_->direction, options_);
    pick_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void PointerTool::update(const OperatorInput& in, const ToolFrame& frame) {
    from_eye_ = !in.controller_ray;
    update(frame.ray);
}

void PointerTool::draw(OverlayList& out, double miss_length_m, bool from_eye) const {
    if (!ray_) return;
    const glm::vec4 beam(0.3f, 1.0f, 0.4f, 0.8f), dot(1.0f, 1.0f, 0.2f, 1.0f);
    if (!from_eye) {
        const glm::dvec3 end = hit_ ? hit_->local : ray_->origin + ray_->direction * miss_length_m;
        out.line(ray_->origin, end, beam);
    }
    if (hit_) out.dots.push_back({hit_->local, dot});
}

nlohmann::json PointerTool::log() const {
    if (!hit_) return {{"hit", nullptr}};
    nlohmann::json out = {{"hit", {hit_->local.x, hit_->local.y, hit_->local.z}},
                          {"label", std::string(core::roleName(hit_->label))},
                          {"distance_m", hit_->distance_m}};
    if (hit_->level >= 0) out["level"] = hit_->level;  // an octree source: the picked node's level
    return out;
}

void PointerTool::logFrame(nlohmann::json& record) const {
    record["pointer"] = log();
    record["pick_ms"] = pick_ms_;
    record["pick_ready"] = ready();
}

void PointerTool::beginTrial() {
    setIndex(nullptr);
    update(std::nullopt);
}

void PointerTool::describe(PanelView& v) {
    v.picking_ready = ready();
    v.pick_ms = pick_ms_;
}

}  // namespace viewer
