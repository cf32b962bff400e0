// viewer/src/tools/cut_tool.hpp: the cutting volume: only the points within a radius of the
// designated point are drawn (the point shader tests each point, so changes cost no
// upload). V / a controller button toggles it, [ ] shrink and grow it, the panel edits it.
#pragma once
#include "points/point_renderer.hpp"
#include "tools/tool.hpp"

#include <viewer/trial.hpp>

#include <optional>

namespace viewer {

class CutTool final : public Tool {
  public:
    /// `enabled`: on from the start of the run and of each trial (--cut).
    CutTool(bool enabled, double radius_m) : run_enabled_(enabled), enabled_(enabled), radius_m_(radius_m) {}
    ToolStage stage() const override { return ToolStage::View; }
    unsigned trialTool() const override { return kToolCut; }
    /// Toggles and resizes it, then puts the volume around the frame's designated point
    /// into the frame's cut (for the candidates tool).
    void update(const OperatorInput& in, const ToolFrame& frame) override;
    /// Off while the trial leaves it out (the panel's switch too), unless the trial turned
    /// it on itself (startTrial): then it stays on, out of the operator's reach.
    void withhold() override { enabled_ = trial_on_; }
    /// As the run started (--cut).
    void beginTrial() override {
        enabled_ = run_enabled_;
        trial_on_ = false;
    }
    /// A trial's own start (a study's condition): on or off, and the radius; unset: as
    /// beginTrial left them.
    void startTrial(std::optional<bool> on, std::optional<double> radius_m) {
        if (on) enabled_ = *on;
        trial_on_ = on.value_or(false);
        if (radius_m) radius_m_ = *radius_m;
    }
    /// Whether it is on (the frame record's "cut").
    void logFrame(nlohmann::json& record) const override { record["cut"] = enabled_; }
    /// The panel's switch and radius.
    void describe(PanelView& v) override;
    /// The volume around `designated_local`; off without a designation.
    CutVolume volume(const std::optional<glm::dvec3>& designated_local) const;
    bool& enabled() { return enabled_; }
    double& radiusM() { return radius_m_; }

  private:
    bool run_enabled_ = false;  // --cut
    bool trial_on_ = false;     // the trial's condition turned it on
    bool enabled_ = false;
    double radius_m_ = 15.0;
};

}  // namespace viewer
