// viewer/src/tools/pointer_tool.hpp: the laser pointer: a ray from the controller's aim
// pose (or the mouse cursor, or a script's aim at a world point), the cloud point it
// picks (viewer/pick_index.hpp), drawn as a thin ray with a dot on the hit.
#pragma once
#include "../overlay_renderer.hpp"

#include <viewer/pick_index.hpp>

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>

namespace viewer {

/// A ray in the cloud's local frame.
struct LocalRay {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};   // unit length
};

class PointerTool {
public:
    explicit PointerTool(const PickOptions& options) : options_(options) {}

    /// The index to pick from (null: the cloud is still loading, nothing is picked).
    void setIndex(std::shared_ptr<const PickIndex> index) { index_ = std::move(index); }
    bool ready() const { return index_ != nullptr; }
    /// Picks along `ray`, or clears the pointer without one. Never throws.
    void update(const std::optional<LocalRay>& ray);
    const std::optional<LocalRay>& ray() const { return ray_; }
    const std::optional<PickHit>& hit() const { return hit_; }
    /// Milliseconds the last pick took.
    double lastPickMs() const { return pick_ms_; }
    /// The ray (to the hit, or `miss_length_m` long) and the hit's dot. `from_eye`: the
    /// ray starts at the eye (desktop, script): only the dot is drawn.
    void draw(OverlayList& out, double miss_length_m, bool from_eye) const;
    /// {"hit": [x, y, z] local, "label", "distance_m"} or {"hit": null}.
    nlohmann::json log() const;

private:
    PickOptions options_;
    std::shared_ptr<const PickIndex> index_;
    std::optional<LocalRay> ray_;
    std::optional<PickHit> hit_;
    double pick_ms_ = 0.0;
};

}  // namespace viewer
