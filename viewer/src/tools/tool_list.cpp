// viewer/src/tools/tool_list.cpp: the one list of the viewer's tools. A new tool is a new
// class in tools/ and one line here, at the place in the order its update and drawing
// need (the loop runs each stage and layer in this order).
#include "tools/candidates_tool.hpp"
#include "tools/colour_tool.hpp"
#include "tools/comfort_tool.hpp"
#include "tools/cut_tool.hpp"
#include "tools/pointer_tool.hpp"
#include "tools/tool_set.hpp"
#include "tools/zoom_tool.hpp"

#include <memory>

namespace viewer {

ToolSet viewerTools(const ViewerOptions& options) {
    ToolSet tools;
    tools.add(std::make_unique<ZoomTool>());
    tools.add(std::make_unique<ColourTool>());
    tools.add(std::make_unique<CutTool>(options.cut_enabled, options.cut_radius_m));
    tools.add(std::make_unique<ComfortTool>(ComfortOptions::of(options)));
    tools.add(std::make_unique<PointerTool>(options.pick));
    tools.add(std::make_unique<CandidatesTool>());
    return tools;
}

}  // namespace viewer
