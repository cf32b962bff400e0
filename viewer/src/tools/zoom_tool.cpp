// viewer/src/tools/zoom_tool.cpp: wheel, script scale and two-hand grab.
#include "tools/zoom_tool.hpp"

#include <cmath>

namespace viewer {

void ZoomTool::update(const OperatorInput& in, const ToolFrame& frame) {
    WorldZoom& zoom = *frame.zoom;
    const glm::dvec3& pivot = frame.zoom_pivot_tracking;
    if (in.wheel != 0.0) zoom.scaleAbout(pivot, zoom.scale() * std::pow(1.15, in.wheel));
    if (in.set_scale) zoom.scaleAbout(pivot, *in.set_scale);
    if (in.grab_hands) {
        if (!zoom.grabbing())
            zoom.beginGrab(in.grab_hands->first, in.grab_hands->second);
        else
            zoom.updateGrab(in.grab_hands->first, in.grab_hands->second);
    } else if (zoom.grabbing()) {
        zoom.endGrab();
    }
    if (in.reset_zoom) zoom.reset();
    if (in.set_scale && frame.actions) frame.actions->push_back({"grab_scale", {{"scale", zoom.scale()}}});
}

}  // namespace viewer
