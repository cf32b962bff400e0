// viewer/src/tools/tool_set.hpp: the operator's tools as one list the frame loop runs:
// each stage's updates, each layer's drawing, the run log's records, the settings panel
// and a new trial go to every tool in the list's order, and a trial's TrialTool bits
// leave tools out. The loop never names a tool; where it needs one tool's state (the
// pointer's hit, the candidates for the trial, the cutting volume for the eyes), it asks
// for that tool by type (get<T>()). viewerTools (tool_list.cpp) is the list.
#pragma once
#include "tools/tool.hpp"

#include <viewer/trial.hpp>
#include <viewer/viewer.hpp>

#include <cassert>
#include <cstddef>
#include <memory>
#include <vector>

namespace viewer {

class ToolSet {
  public:
    /// Appends `tool`: it updates and draws after those added before it.
    void add(std::unique_ptr<Tool> tool) { tools_.push_back(std::move(tool)); }
    std::size_t size() const { return tools_.size(); }
    /// The trial's TrialTool bits (kAllTrialTools for a plain run).
    void offer(unsigned trial_tools) { offered_ = trial_tools; }
    bool offered(const Tool& tool) const { return tool.trialTool() == 0 || (offered_ & tool.trialTool()) != 0; }

    /// Updates the tools of `stage` (withholds those the trial leaves out). Never throws.
    void update(ToolStage stage, const OperatorInput& in, const ToolFrame& frame);
    /// Draws the tools of `layer` into `out`.
    void draw(ToolLayer layer, OverlayList& out) const;
    void beginTrial();
    /// Every tool's keys of a counted frame's record.
    void logFrame(nlohmann::json& record) const;
    /// Every tool's keys at the end of the run.
    void logRun(nlohmann::json& summary) const;
    /// Every tool's part of the settings panel.
    void describe(PanelView& v);

    /// The first tool of type T, or null.
    template <class T>
    T* find() const {
        for (const std::unique_ptr<Tool>& t : tools_)
            if (T* typed = dynamic_cast<T*>(t.get())) return typed;
        return nullptr;
    }
    /// The tool of type T; the list must hold one.
    template <class T>
    T& get() const {
        T* typed = find<T>();
        assert(typed != nullptr);
        return *typed;
    }

  private:
    std::vector<std::unique_ptr<Tool>> tools_;
    unsigned offered_ = kAllTrialTools;
};

/// The viewer's tools, in the order they update within a stage and draw within a layer:
/// zoom, colour, cutting volume, comfort, pointer, candidates.
ToolSet viewerTools(const ViewerOptions& options);

}  // namespace viewer
