// viewer/src/tools/tool_set.cpp: the loops over the tools.
#include "tools/tool_set.hpp"

namespace viewer {

void ToolSet::update(ToolStage stage, const OperatorInput& in, const ToolFrame& frame) {
    for (const std::unique_ptr<Tool>& t : tools_) {
        if (t->stage() != stage) continue;
        if (offered(*t))
            t->update(in, frame);
        else
            t->withhold();
    }
}

void ToolSet::draw(ToolLayer layer, OverlayList& out) const {
    for (const std::unique_ptr<Tool>& t : tools_)
        if (t->layer() == layer) t->draw(out);
}

void ToolSet::beginTrial() {
    for (const std::unique_ptr<Tool>& t : tools_) t->beginTrial();
}

void ToolSet::logFrame(nlohmann::json& record) const {
    for (const std::unique_ptr<Tool>& t : tools_) t->logFrame(record);
}

void ToolSet::logRun(nlohmann::json& summary) const {
    for (const std::unique_ptr<Tool>& t : tools_) t->logRun(summary);
}

void ToolSet::describe(PanelView& v) {
    for (const std::unique_ptr<Tool>& t : tools_) t->describe(v);
}

}  // namespace viewer
