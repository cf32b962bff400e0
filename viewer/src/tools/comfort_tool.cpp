// viewer/src/tools/comfort_tool.cpp: snap turn and vignette.
#include "tools/comfort_tool.hpp"

#include "ui/panel.hpp"

#include <algorithm>
#include <cmath>

namespace viewer {

void ComfortTool::update(const OperatorInput& in, const ToolFrame& frame) {
    const bool free = frame.modes && frame.modes->mode() == ViewMode::Free;
    if (in.snap_turn != 0 && free && frame.now_s - last_snap_s_ >= options_.snap_turn_debounce_s) {
        frame.modes->snapTurn(in.snap_turn * options_.snap_turn_deg);
        last_snap_s_ = frame.now_s;
    }
    const Motion& m = frame.motion;
    const bool moving = free && (std::abs(m.forward) + std::abs(m.right) + std::abs(m.up) + std::abs(m.turn) > 1e-3 ||
                                 in.snap_turn != 0);
    strength_ = std::clamp(strength_ + (moving ? frame.dt_s / 0.2 : -frame.dt_s / 0.3), 0.0, 1.0);
}

void ComfortTool::draw(OverlayList& out) const {
    if (options_.vignette)
        out.vignette =
            VignetteStyle{float(options_.vignette_aperture), float(options_.vignette_feather), float(strength_)};
}

void ComfortTool::describe(PanelView& v) {
    v.snap_turn = &options_.snap_turn;
    v.vignette = &options_.vignette;
}

}  // namespace viewer
