// viewer/src/tools/zoom_tool.hpp: the world zoom as a tool (viewer/world_zoom.hpp has the
// maths): the wheel about the pointer's hit (or the head), a script's grab_scale, the
// two-hand grab, and the reset key / button.
#pragma once
#include "tools/tool.hpp"

#include <viewer/world_zoom.hpp>

namespace viewer {

class ZoomTool final : public Tool {
  public:
    void update(const OperatorInput& in, const ToolFrame& frame) override;
    /// {"scale": s}.
    nlohmann::json log() const override { return {{"scale", zoom_.scale()}}; }
    const WorldZoom& zoom() const { return zoom_; }
    void reset() { zoom_.reset(); }

  private:
    WorldZoom zoom_;
};

}  // namespace viewer
