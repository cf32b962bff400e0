// viewer/src/tools/pointer_tool.hpp: the laser pointer: a ray from the controller's aim
// pose (or the mouse cursor, or a script's aim at a world point), the cloud point it
// picks (viewer/pick_index.hpp), drawn as a thin ray with a dot on the hit.
#pragma once
#include "ui/overlay_renderer.hpp"
#include "tools/tool.hpp"

#include <viewer/pick_index.hpp>
#include <viewer/world_zoom.hpp>

#include <glm/vec2.hpp>

#include <nlohmann/json.hpp>

#include <memory>
#include <optional>

namespace viewer {

/// Where this frame's pointer ray can come from.
struct PointerSources {
    RigPose rig;         // the mode's rig
    RigPose head_local;  // the head in the cloud's local frame
    const WorldZoom* zoom = nullptr;
    std::optional<glm::dvec3> aim_local;    // a script's aim point
    std::optional<TrackingRay> controller;  // a controller's aim (tracking frame)
    std::optional<glm::dvec2> cursor_px;    // the desktop cursor (from the window's top left)
    int window_w = 0, window_h = 0;
    double vfov_deg = 60.0;  // the desktop view's vertical field of view
    /// A replay: the pointer shown is the recorded one, so the live cursor picks nothing.
    bool replay = false;
};
/// A script's aim (from the head to its point), else the controller's ray (through the
/// zoom and the rig), else the cursor's ray through the desktop view (not in a replay);
/// none without any.
std::optional<LocalRay> pointerRayOf(const PointerSources& p);

class PointerTool final : public Tool {
  public:
    explicit PointerTool(const PickOptions& options) : options_(options) {}
    ToolStage stage() const override { return ToolStage::Aim; }
    /// Under the designation mark (a designation's dot lies on the pointer's).
    ToolLayer layer() const override { return ToolLayer::UnderDesignation; }

    /// The per-node indexes to pick from (null: the cloud is still loading, nothing is picked).
    void setIndex(std::shared_ptr<const PickSet> index) { index_ = std::move(index); }
    bool ready() const { return index_ != nullptr; }
    /// Picks along `ray`, or clears the pointer without one. Never throws.
    void update(const std::optional<LocalRay>& ray);
    /// update(frame.ray); the beam is drawn only from a controller (else the ray starts at
    /// the eye and only the dot shows).
    void update(const OperatorInput& in, const ToolFrame& frame) override;
    const std::optional<LocalRay>& ray() const { return ray_; }
    const std::optional<PickHit>& hit() const { return hit_; }
    /// Milliseconds the last pick took.
    double lastPickMs() const { return pick_ms_; }
    /// The ray (to the hit, or `miss_length_m` long) and the hit's dot. `from_eye`: the
    /// ray starts at the eye (desktop, script): only the dot is drawn.
    void draw(OverlayList& out, double miss_length_m, bool from_eye) const;
    /// draw(out, 200 m, whether the last update's ray came from the eye).
    void draw(OverlayList& out) const override { draw(out, 200.0, from_eye_); }
    /// {"hit": [x, y, z] local, "label", "distance_m"} or {"hit": null}.
    nlohmann::json log() const;
    /// The frame record's "pointer" (log()), "pick_ms" and "pick_ready".
    void logFrame(nlohmann::json& record) const override;
    /// No index and no ray until the new trial's cloud can be picked.
    void beginTrial() override;
    /// The panel's picking state.
    void describe(PanelView& v) override;

  private:
    PickOptions options_;
    std::shared_ptr<const PickSet> index_;
    std::optional<LocalRay> ray_;
    std::optional<PickHit> hit_;
    double pick_ms_ = 0.0;
    bool from_eye_ = true;
};

}  // namespace viewer
