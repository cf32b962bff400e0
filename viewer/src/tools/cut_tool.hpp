// viewer/src/tools/cut_tool.hpp: the cutting volume: only the points within a radius of the
// designated point are drawn (the point shader tests each point, so changes cost no
// upload). V / a controller button toggles it, [ ] shrink and grow it, the panel edits it.
#pragma once
#include "points/point_renderer.hpp"
#include "tools/tool.hpp"

namespace viewer {

class CutTool final : public Tool {
  public:
    CutTool(bool enabled, double radius_m) : enabled_(enabled), radius_m_(radius_m) {}
    void update(const OperatorInput& in, const ToolFrame& frame) override;
    /// Whether it is on (the frame record's "cut").
    nlohmann::json log() const override { return enabled_; }
    /// The volume around `designated_local`; off without a designation.
    CutVolume volume(const std::optional<glm::dvec3>& designated_local) const;
    bool& enabled() { return enabled_; }
    double& radiusM() { return radius_m_; }

  private:
    bool enabled_ = false;
    double radius_m_ = 15.0;
};

}  // namespace viewer
