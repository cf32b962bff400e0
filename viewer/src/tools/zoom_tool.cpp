// viewer/src/tools/zoom_tool.cpp: wheel, script scale and two-hand grab.
#include "tools/zoom_tool.hpp"

#include <cmath>

namespace viewer {

void ZoomTool::update(const OperatorInput& in, const ToolFrame& frame) {
    const glm::dvec3& pivot = frame.zoom_pivot_tracking;
    if (in.wheel != 0.0) zoom_.scaleAbout(pivot, zoom_.scale() * std::pow(1.15, in.wheel));
    if (in.set_scale) zoom_.scaleAbout(pivot, *in.set_scale);
    if (in.grab_hands) {
        if (!zoom_.grabbing())
            zoom_.beginGrab(in.grab_hands->first, in.grab_hands->second);
        else
            zoom_.updateGrab(in.grab_hands->first, in.grab_hands->second);
    } else if (zoom_.grabbing()) {
        zoom_.endGrab();
    }
    if (in.reset_zoom) zoom_.reset();
}

}  // namespace viewer
