// viewer/src/tools/cut_tool.cpp: the cutting volume's switch and radius.
#include "tools/cut_tool.hpp"

#include "ui/panel.hpp"

#include <algorithm>
#include <cmath>

namespace viewer {

void CutTool::update(const OperatorInput& in, const ToolFrame& frame) {
    if (in.toggle_cut) enabled_ = !enabled_;
    if (in.cut_radius_step != 0.0) radius_m_ = std::clamp(radius_m_ * std::pow(1.25, in.cut_radius_step), 1.0, 500.0);
    if (frame.cut) *frame.cut = volume(frame.designated);
}

void CutTool::describe(PanelView& v) {
    v.cut_enabled = &enabled_;
    v.cut_radius_m = &radius_m_;
}

CutVolume CutTool::volume(const std::optional<glm::dvec3>& designated_local) const {
    CutVolume cut;
    cut.enabled = enabled_ && designated_local.has_value();
    if (cut.enabled) {
        cut.centre_local = *designated_local;
        cut.radius_m = radius_m_;
    }
    return cut;
}

}  // namespace viewer
