// tests/viewer/tools/tool_set_test.cpp: the tools as one list (tools/tool_set.hpp): each
// stage and layer in the list's order, the trial's bits leaving tools out, every tool's
// log keys; then the viewer's own list driven with synthetic input, no window and no GL.
#include "tools/candidates_tool.hpp"
#include "tools/comfort_tool.hpp"
#include "tools/cut_tool.hpp"
#include "tools/pointer_tool.hpp"
#include "tools/tool_set.hpp"
#include "ui/panel.hpp"

#include <doctest/doctest.h>

#include <memory>
#include <string>
#include <vector>

using namespace viewer;

namespace {

/// A tool that writes what is asked of it into a shared list, as "name.call".
class RecordingTool final : public Tool {
  public:
    RecordingTool(std::string name, ToolStage stage, ToolLayer layer, unsigned bit, std::vector<std::string>& calls)
        : name_(std::move(name)), stage_(stage), layer_(layer), bit_(bit), calls_(&calls) {}
    ToolStage stage() const override { return stage_; }
    ToolLayer layer() const override { return layer_; }
    unsigned trialTool() const override { return bit_; }
    void update(const OperatorInput&, const ToolFrame&) override { calls_->push_back(name_ + ".update"); }
    void withhold() override { calls_->push_back(name_ + ".withhold"); }
    void beginTrial() override { calls_->push_back(name_ + ".beginTrial"); }
    void draw(OverlayList& out) const override {
        calls_->push_back(name_ + ".draw");
        out.dots.push_back({glm::dvec3(0.0), glm::vec4(1.0f)});
    }
    void logFrame(nlohmann::json& record) const override { record[name_] = "frame"; }
    void logRun(nlohmann::json& summary) const override { summary[name_] = "run"; }

  private:
    std::string name_;
    ToolStage stage_;
    ToolLayer layer_;
    unsigned bit_;
    std::vector<std::string>* calls_;
};

using Calls = std::vector<std::string>;

}  // namespace

TEST_CASE("the tool set runs each stage and draws each layer in the list's order") {
    Calls calls;
    ToolSet tools;
    const ToolLayer over = ToolLayer::OverDesignation, under = ToolLayer::UnderDesignation;
    tools.add(std::make_unique<RecordingTool>("a", ToolStage::View, over, 0u, calls));
    tools.add(std::make_unique<RecordingTool>("b", ToolStage::Aim, under, 0u, calls));
    tools.add(std::make_unique<RecordingTool>("c", ToolStage::View, over, kToolCut, calls));
    tools.add(std::make_unique<RecordingTool>("d", ToolStage::Motion, over, 0u, calls));
    tools.add(std::make_unique<RecordingTool>("e", ToolStage::Aim, over, kToolZoom, calls));
    CHECK(tools.size() == 5);
    const OperatorInput in;
    const ToolFrame frame;
    for (ToolStage stage : {ToolStage::View, ToolStage::Motion, ToolStage::Aim}) tools.update(stage, in, frame);
    CHECK(calls == Calls{"a.update", "c.update", "d.update", "b.update", "e.update"});

    calls.clear();
    OverlayList overlay;
    tools.draw(under, overlay);
    tools.draw(over, overlay);
    CHECK(calls == Calls{"b.draw", "a.draw", "c.draw", "d.draw", "e.draw"});
    CHECK(overlay.dots.size() == 5);

    calls.clear();
    tools.beginTrial();
    CHECK(calls == Calls{"a.beginTrial", "b.beginTrial", "c.beginTrial", "d.beginTrial", "e.beginTrial"});
}

TEST_CASE("a trial that leaves a tool out withholds it instead of updating it") {
    Calls calls;
    ToolSet tools;
    tools.add(std::make_unique<RecordingTool>("zoom", ToolStage::View, ToolLayer::OverDesignation, kToolZoom, calls));
    tools.add(std::make_unique<RecordingTool>("cut", ToolStage::View, ToolLayer::OverDesignation, kToolCut, calls));
    tools.add(std::make_unique<RecordingTool>("pointer", ToolStage::View, ToolLayer::OverDesignation, 0u, calls));
    tools.offer(kToolZoom);
    tools.update(ToolStage::View, OperatorInput{}, ToolFrame{});
    CHECK(calls == Calls{"zoom.update", "cut.withhold", "pointer.update"});
    // A tool without a bit stays whatever the trial offers.
    calls.clear();
    tools.offer(0u);
    tools.update(ToolStage::View, OperatorInput{}, ToolFrame{});
    CHECK(calls == Calls{"zoom.withhold", "cut.withhold", "pointer.update"});
    calls.clear();
    tools.offer(kAllTrialTools);
    tools.update(ToolStage::View, OperatorInput{}, ToolFrame{});
    CHECK(calls == Calls{"zoom.update", "cut.update", "pointer.update"});
}

TEST_CASE("every tool's log keys go into the frame record and the run's summary") {
    Calls calls;
    ToolSet tools;
    tools.add(std::make_unique<RecordingTool>("a", ToolStage::View, ToolLayer::OverDesignation, 0u, calls));
    tools.add(std::make_unique<RecordingTool>("b", ToolStage::Aim, ToolLayer::OverDesignation, kToolCut, calls));
    nlohmann::json record = {{"frame", 7}};
    tools.logFrame(record);
    CHECK(record == nlohmann::json{{"frame", 7}, {"a", "frame"}, {"b", "frame"}});
    nlohmann::json summary = nlohmann::json::object();
    tools.logRun(summary);
    CHECK(summary == nlohmann::json{{"a", "run"}, {"b", "run"}});
    CHECK(tools.find<RecordingTool>() != nullptr);
    CHECK(tools.find<CutTool>() == nullptr);
}

TEST_CASE("the viewer's tools through the set: a script's scale, the cut switch and the colour key") {
    ViewerOptions options;
    ToolSet tools = viewerTools(options);
    CHECK(tools.size() == 6);
    ModeController modes(options.modes, glm::dvec3(0.0));
    WorldZoom zoom;
    ViewStyle style;
    std::vector<ToolAction> actions;
    ToolFrame f;
    f.modes = &modes;
    f.zoom = &zoom;
    f.style = &style;
    f.actions = &actions;

    OperatorInput in;
    in.set_scale = 2.0;
    in.toggle_cut = true;
    in.cycle_colour = true;
    tools.update(ToolStage::View, in, f);
    CHECK(zoom.scale() == doctest::Approx(2.0));
    REQUIRE(actions.size() == 1);
    CHECK(std::string(actions[0].action) == "grab_scale");
    CHECK(actions[0].extra == nlohmann::json{{"scale", 2.0}});
    CHECK(tools.get<CutTool>().enabled());
    CHECK(style.colour == ColourMode::HeightJet);
    nlohmann::json record = nlohmann::json::object();
    tools.logFrame(record);
    CHECK(record["cut"] == true);
    CHECK(record["pointer"] == nlohmann::json{{"hit", nullptr}});
    CHECK(record["pick_ready"] == false);

    // The colour key runs through every mode the viewer names and back to the file's.
    OperatorInput colour;
    colour.cycle_colour = true;
    for (int i = 0; i < 6; ++i) tools.update(ToolStage::View, colour, f);
    CHECK(style.colour == ColourMode::Return);
    tools.update(ToolStage::View, colour, f);
    CHECK(style.colour == ColourMode::File);

    // A trial offering only the zoom: the cutting volume goes off, the colour key does nothing.
    actions.clear();
    tools.offer(kToolZoom);
    in.set_scale = 4.0;
    tools.update(ToolStage::View, in, f);
    CHECK(zoom.scale() == doctest::Approx(4.0));
    CHECK(actions.size() == 1);
    CHECK_FALSE(tools.get<CutTool>().enabled());
    CHECK(style.colour == ColourMode::File);
    // Without the zoom, a script's scale changes nothing and records nothing.
    actions.clear();
    tools.offer(kToolCut);
    in.set_scale = 8.0;
    tools.update(ToolStage::View, in, f);
    CHECK(zoom.scale() == doctest::Approx(4.0));
    CHECK(actions.empty());
}

TEST_CASE("the viewer's tools through the set: the pointer's ray meets a candidate box, drawn over the designation") {
    ViewerOptions options;
    ToolSet tools = viewerTools(options);
    std::vector<core::Candidate> list(1);
    list[0].id = "box";
    list[0].centre_world = {1000.0, 0.0, 0.0};
    list[0].size_m = {4.0, 4.0, 4.0};
    tools.get<CandidatesTool>().set(list, glm::dvec3(900.0, 0.0, 0.0));  // the box 100 m along x, local
    ToolFrame f;
    f.ray = LocalRay{glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0)};
    tools.update(ToolStage::Aim, OperatorInput{}, f);
    CHECK(tools.get<CandidatesTool>().pointed() == std::optional<std::size_t>(0));
    // No pick index yet: the pointer has its ray and no hit; from the eye, it draws nothing.
    CHECK(tools.get<PointerTool>().ray().has_value());
    CHECK_FALSE(tools.get<PointerTool>().hit().has_value());
    OverlayList under, over;
    tools.draw(ToolLayer::UnderDesignation, under);
    tools.draw(ToolLayer::OverDesignation, over);
    CHECK(under.lines.empty());
    CHECK(under.dots.empty());
    CHECK(over.lines.size() == 24);    // the box's 12 edges
    CHECK(over.vignette.has_value());  // the comfort tool's (on by default)

    PanelView v;
    tools.describe(v);
    CHECK(v.candidates == 1);
    CHECK(v.cut_enabled == &tools.get<CutTool>().enabled());
    CHECK(v.snap_turn == &tools.get<ComfortTool>().snapTurn());
    CHECK_FALSE(v.picking_ready);
    nlohmann::json summary = nlohmann::json::object();
    tools.logRun(summary);
    CHECK(summary == nlohmann::json{{"candidates", {{{"id", "box"}, {"verdict", "unreviewed"}}}}});

    // A new trial: no candidates, no ray.
    tools.beginTrial();
    CHECK(tools.get<CandidatesTool>().empty());
    CHECK_FALSE(tools.get<PointerTool>().ray().has_value());
}

TEST_CASE("the viewer's tools through the set: boxes wholly outside the cutting volume are hidden") {
    ViewerOptions options;
    options.cut_radius_m = 15.0;
    ToolSet tools = viewerTools(options);
    std::vector<core::Candidate> list(3);
    list[0].id = "inside";  // 10 m along x
    list[0].centre_world = {10.0, 0.0, 0.0};
    list[1].id = "meets";  // its centre 16 m out, its near face 14 m: within 15 m
    list[1].centre_world = {0.0, 16.0, 0.0};
    list[2].id = "outside";  // 100 m along x
    list[2].centre_world = {100.0, 0.0, 0.0};
    for (core::Candidate& c : list) c.size_m = {4.0, 4.0, 4.0};
    tools.get<CandidatesTool>().set(list, glm::dvec3(0.0));
    ModeController modes(options.modes, glm::dvec3(0.0));
    WorldZoom zoom;
    ViewStyle style;
    CutVolume cut;
    ToolFrame f;
    f.modes = &modes;
    f.zoom = &zoom;
    f.style = &style;
    f.designated = glm::dvec3(0.0);
    f.cut = &cut;
    f.ray = LocalRay{glm::dvec3(50.0, 0.0, 0.0), glm::dvec3(1.0, 0.0, 0.0)};  // towards the far box
    auto frame = [&](bool toggle) {
        OperatorInput in;
        in.toggle_cut = toggle;
        for (ToolStage stage : {ToolStage::View, ToolStage::Motion, ToolStage::Aim}) tools.update(stage, in, f);
        OverlayList over;
        tools.draw(ToolLayer::OverDesignation, over);
        return over.lines.size();
    };
    // The volume off: every box drawn, the far one pointed at.
    CHECK(frame(false) == 3 * 24);
    CHECK(tools.get<CandidatesTool>().pointed() == std::optional<std::size_t>(2));
    // V: the box outside goes (and cannot be pointed at); the two that meet the sphere stay.
    CHECK(frame(true) == 2 * 24);
    CHECK(cut.enabled);
    CHECK_FALSE(tools.get<CandidatesTool>().shown(2));
    CHECK(tools.get<CandidatesTool>().shown(1));
    CHECK_FALSE(tools.get<CandidatesTool>().pointed());
    // V again: all three back.
    CHECK(frame(true) == 3 * 24);
    // Without a designated point there is no volume: nothing hidden.
    f.designated.reset();
    CHECK(frame(true) == 3 * 24);
}
