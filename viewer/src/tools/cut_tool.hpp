// viewer/src/tools/cut_tool.hpp: the cutting volume: only the points within a radius of the
// designated point are drawn (the point shader tests each point, so changes cost no
// upload). V / a controller button toggles it, [ ] shrink and grow it, the panel edits it.
#pragma once
#include "points/point_renderer.hpp"
#include "tools/tool.hpp"

#include <viewer/trial.hpp>

namespace viewer {

class CutTool final : public Tool {
  public:
    CutTool(bool enabled, double radius_m) : enabled_(enabled), radius_m_(radius_m) {}
    ToolStage stage() const override { return ToolStage::View; }
    unsigned trialTool() const override { return kToolCut; }
    /// Toggles and resizes it, then puts the volume around the frame's designated point
    /// into the frame's cut (for the candidates tool).
    void update(const OperatorInput& in, const ToolFrame& frame) override;
    /// Off while the trial leaves it out (the panel's switch too).
    void withhold() override { enabled_ = false; }
    void beginTrial() override { enabled_ = false; }
    /// Whether it is on (the frame record's "cut").
    void logFrame(nlohmann::json& record) const override { record["cut"] = enabled_; }
    /// The panel's switch and radius.
    void describe(PanelView& v) override;
    /// The volume around `designated_local`; off without a designation.
    CutVolume volume(const std::optional<glm::dvec3>& designated_local) const;
    bool& enabled() { return enabled_; }
    double& radiusM() { return radius_m_; }

  private:
    bool enabled_ = false;
    double radius_m_ = 15.0;
};

}  // namespace viewer
