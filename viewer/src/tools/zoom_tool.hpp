// viewer/src/tools/zoom_tool.hpp: the world zoom as a tool (viewer/world_zoom.hpp has the
// maths; the zoom itself is the frame's, ToolFrame::zoom): the wheel about the pointer's
// hit (or the head), a script's grab_scale (recorded as an action), the two-hand grab,
// and the reset key / button.
#pragma once
#include "tools/tool.hpp"

#include <viewer/trial.hpp>

namespace viewer {

class ZoomTool final : public Tool {
  public:
    ToolStage stage() const override { return ToolStage::View; }
    unsigned trialTool() const override { return kToolZoom; }
    /// Scales frame.zoom; a script's scale adds the action {"grab_scale", {"scale": s}}.
    void update(const OperatorInput& in, const ToolFrame& frame) override;
};

}  // namespace viewer
