// viewer/src/tools/tool.hpp: what every operator tool is: it updates from the frame's
// OperatorInput at its stage of the frame, draws into the overlay list, and says what the
// run log records of it and what the settings panel shows of it. The frame loop runs the
// tools through a ToolSet (tool_set.hpp) built from the one list in tool_list.cpp: a new
// tool is a new class here and one line there. A tool reads no device and decides
// nothing about the trial.
#pragma once
#include "input/operator_input.hpp"
#include "points/point_renderer.hpp"
#include "ui/overlay_renderer.hpp"

#include <viewer/mode_controller.hpp>
#include <viewer/viewer.hpp>
#include <viewer/world_zoom.hpp>

#include <nlohmann/json.hpp>

#include <optional>
#include <vector>

namespace viewer {

struct PanelView;  // ui/panel.hpp

/// A ray in the cloud's local frame.
struct LocalRay {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};  // unit length
};

/// When in the frame a tool updates. The frame loop runs the stages in this order, each
/// over the tools in the list's order, and does its own work between them.
enum class ToolStage {
    View,    // from the input alone, before the rig moves (zoom, colour, cutting volume)
    Motion,  // with the frame's motion scaled by the zoom, before the rig moves (comfort)
    Aim,     // along the frame's pointer ray, after the rig moved (pointer, candidates)
};

/// Where a tool's overlay goes: the trial's designation mark is drawn between the layers.
enum class ToolLayer { UnderDesignation, OverDesignation };

/// An action a tool asks the run log's decisions to record, with its values.
struct ToolAction {
    const char* action = "";
    nlohmann::json extra = nlohmann::json::object();
};

/// What a tool sees of the frame besides the operator's input.
struct ToolFrame {
    double dt_s = 0.0;
    double now_s = 0.0;                          // since the run started
    ModeController* modes = nullptr;             // the rig (the comfort tool turns it)
    WorldZoom* zoom = nullptr;                   // the world zoom (the zoom tool scales it)
    ViewStyle* style = nullptr;                  // the display settings (the colour tool cycles them)
    glm::dvec3 zoom_pivot_tracking{0.0};         // what the wheel and a script's scale zoom about
    Motion motion;                               // this frame's motion, scaled by the zoom (from Motion on)
    std::optional<LocalRay> ray;                 // the pointer's ray (Aim)
    std::optional<glm::dvec3> designated;        // the trial's designated point, local (none: none yet)
    CutVolume* cut = nullptr;                    // the cutting volume: the cut tool sets it (View), the
                                                 // candidates tool hides boxes outside it (Aim); null: none
    std::vector<ToolAction>* actions = nullptr;  // where a tool's actions go (null: dropped)
};

class Tool {
  public:
    virtual ~Tool() = default;
    virtual ToolStage stage() const = 0;
    virtual ToolLayer layer() const { return ToolLayer::OverDesignation; }
    /// The TrialTool bit a trial leaves the tool out with (viewer/trial.hpp); 0: always there.
    virtual unsigned trialTool() const { return 0; }
    /// Never throws.
    virtual void update(const OperatorInput& in, const ToolFrame& frame) = 0;
    /// Instead of update() while the trial leaves the tool out.
    virtual void withhold() {}
    /// A new trial starts: what the last one left on the tool goes.
    virtual void beginTrial() {}
    virtual void draw(OverlayList& /*out*/) const {}
    /// Adds what the run log records of the tool to a counted frame's record.
    virtual void logFrame(nlohmann::json& /*record*/) const {}
    /// Adds what the run log records of the tool at the end of the run (top-level keys).
    virtual void logRun(nlohmann::json& /*summary*/) const {}
    /// Fills the tool's part of the settings panel (its switches point into the tool).
    virtual void describe(PanelView& /*v*/) {}
};

}  // namespace viewer
