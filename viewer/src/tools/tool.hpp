// viewer/src/tools/tool.hpp: what every operator tool is: it updates from the frame's
// OperatorInput, draws into the overlay list, and says what the run log records of it.
// A new tool is a new class here that the frame loop updates, draws and logs with the
// others; it reads no device and decides nothing about the trial.
#pragma once
#include "input/operator_input.hpp"
#include "ui/overlay_renderer.hpp"

#include <viewer/mode_controller.hpp>

#include <nlohmann/json.hpp>

#include <optional>

namespace viewer {

/// A ray in the cloud's local frame.
struct LocalRay {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};  // unit length
};

/// What a tool sees of the frame besides the operator's input.
struct ToolFrame {
    double dt_s = 0.0;
    double now_s = 0.0;                   // since the run started
    ModeController* modes = nullptr;      // the rig (the comfort tool turns it)
    glm::dvec3 zoom_pivot_tracking{0.0};  // what the wheel and a script's scale zoom about
    Motion motion;                        // this frame's motion, scaled by the zoom
    std::optional<LocalRay> ray;          // the pointer's ray
};

class Tool {
  public:
    virtual ~Tool() = default;
    /// Never throws.
    virtual void update(const OperatorInput& in, const ToolFrame& frame) = 0;
    virtual void draw(OverlayList& /*out*/) const {}
    /// What the run log records of the tool (null: nothing).
    virtual nlohmann::json log() const { return nullptr; }
};

}  // namespace viewer
