// viewer/src/tools/colour_tool.hpp: the colour mode key / controller button: the next
// colour mode the viewer knows (viewer/viewer.hpp's ColourMode), then the first again.
#pragma once
#include "tools/tool.hpp"

#include <viewer/trial.hpp>

namespace viewer {

class ColourTool final : public Tool {
  public:
    ToolStage stage() const override { return ToolStage::View; }
    unsigned trialTool() const override { return kToolColour; }
    /// On cycle_colour: frame.style's colour becomes the next mode colourModeName names.
    void update(const OperatorInput& in, const ToolFrame& frame) override;
};

}  // namespace viewer
