// viewer/src/tools/colour_tool.hpp: the colour mode key / controller button: the next
// colour mode the viewer knows (viewer/viewer.hpp's ColourMode), then the first again; and
// the one warning when above-ground colours meet a cloud without heights above ground.
#pragma once
#include "tools/tool.hpp"

#include <viewer/trial.hpp>

namespace viewer {

/// The mode the points are drawn in for `wanted`: above-ground on a cloud that holds no
/// height above ground (no terrain was fitted: whitened by RANSAC, or a file from
/// elsewhere) shows the height colours, as the point shader does; the others as they are.
ColourMode shownColourMode(ColourMode wanted, bool cloud_has_height);

class ColourTool final : public Tool {
  public:
    ToolStage stage() const override { return ToolStage::View; }
    unsigned trialTool() const override { return kToolColour; }
    /// On cycle_colour: frame.style's colour becomes the next mode colourModeName names.
    void update(const OperatorInput& in, const ToolFrame& frame) override;
    /// Once the cloud's fields are known, each frame: the first time `wanted` is shown as
    /// another mode (shownColourMode), one warning line on stderr saying so, once a run
    /// (whatever the trial); the run log's `colour_fallback` records it.
    void noteCloud(ColourMode wanted, bool cloud_has_height);
    void logRun(nlohmann::json& summary) const override;

  private:
    bool fell_back_ = false;
};

}  // namespace viewer
