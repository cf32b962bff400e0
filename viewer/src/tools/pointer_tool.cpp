// viewer/src/tools/pointer_tool.cpp: the laser pointer's pick and drawing.
#include "pointer_tool.hpp"

#include <core/scene.hpp>

#include <chrono>

namespace viewer {

void PointerTool::update(const std::optional<LocalRay>& ray) {
    ray_ = ray;
    hit_.reset();
    if (!ray_ || !index_) return;
    const auto t0 = std::chrono::steady_clock::now();
    hit_ = index_->pick(ray_->origin, ray_->direction, options_);
    pick_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
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
    return {{"hit", {hit_->local.x, hit_->local.y, hit_->local.z}},
            {"label", std::string(core::roleName(hit_->label))},
            {"distance_m", hit_->distance_m}};
}

}  // namespace viewer
