// viewer/src/tools/colour_tool.cpp: cycling the colour mode.
#include "tools/colour_tool.hpp"

#include <string>

namespace viewer {

void ColourTool::update(const OperatorInput& in, const ToolFrame& frame) {
    if (!in.cycle_colour) return;
    // The next mode colourModeName knows ("?" past the last), else the first again.
    ColourMode& colour = frame.style->colour;
    const auto next = static_cast<ColourMode>(static_cast<int>(colour) + 1);
    colour = std::string(colourModeName(next)) == "?" ? ColourMode::File : next;
}

}  // namespace viewer
