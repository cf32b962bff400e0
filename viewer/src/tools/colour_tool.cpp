// viewer/src/tools/colour_tool.cpp: cycling the colour mode, and the above-ground fallback.
#include "tools/colour_tool.hpp"

#include <platform/safe_file.hpp>

#include <string>

namespace viewer {

ColourMode shownColourMode(ColourMode wanted, bool cloud_has_height) {
    return wanted == ColourMode::AboveGround && !cloud_has_height ? ColourMode::HeightJet : wanted;
}

void ColourTool::update(const OperatorInput& in, const ToolFrame& frame) {
    if (!in.cycle_colour) return;
    // The next mode colourModeName knows ("?" past the last), else the first again.
    ColourMode& colour = frame.style->colour;
    const auto next = static_cast<ColourMode>(static_cast<int>(colour) + 1);
    colour = std::string(colourModeName(next)) == "?" ? ColourMode::File : next;
}

void ColourTool::noteCloud(ColourMode wanted, bool cloud_has_height) {
    if (fell_back_ || shownColourMode(wanted, cloud_has_height) == wanted) return;
    fell_back_ = true;
    platform::printMessage("warning",
                           "view: colour above-ground: the cloud holds no height above ground (no terrain was "
                           "fitted: make it with `generate --ground smrf|csf` or `ladarvr ground`); showing height "
                           "colours instead");
}

void ColourTool::logRun(nlohmann::json& summary) const {
    if (fell_back_) summary["colour_fallback"] = {{"wanted", "above-ground"}, {"shown", "height"}};
}

}  // namespace viewer
