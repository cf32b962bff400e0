// viewer/src/tools/comfort_tool.hpp: comfort in free mode in the headset: snap turns (a
// step per thumbstick flick, at most one per debounce time) and a vignette that darkens
// the edges of the view while moving (docs/viewer.md).
#pragma once
#include "tools/tool.hpp"

#include <viewer/viewer.hpp>

namespace viewer {

struct ComfortOptions {
    bool snap_turn = true;
    double snap_turn_deg = 45.0;
    double snap_turn_debounce_s = 0.5;
    bool vignette = true;
    double vignette_aperture = 0.7;
    double vignette_feather = 0.2;
    static ComfortOptions of(const ViewerOptions& o) {
        return {o.snap_turn, o.snap_turn_deg,     o.snap_turn_debounce_s,
                o.vignette,  o.vignette_aperture, o.vignette_feather};
    }
};

class ComfortTool final : public Tool {
  public:
    explicit ComfortTool(const ComfortOptions& options) : options_(options) {}
    ToolStage stage() const override { return ToolStage::Motion; }
    /// Turns frame.modes on a snap turn in free mode; eases the vignette in over 0.2 s of
    /// motion (or a snap) and out over 0.3 s at rest.
    void update(const OperatorInput& in, const ToolFrame& frame) override;
    /// The vignette, while it is switched on (the eye renderer draws it in the headset).
    void draw(OverlayList& out) const override;
    /// The panel's snap turn and vignette switches.
    void describe(PanelView& v) override;
    bool& snapTurn() { return options_.snap_turn; }
    bool& vignette() { return options_.vignette; }

  private:
    ComfortOptions options_;
    double last_snap_s_ = -1e9;
    double strength_ = 0.0;  // 0 at rest, 1 while moving
};

}  // namespace viewer
