// tests/viewer/trial/questionnaire_flow_test.cpp: a study's questionnaires without a window:
// a gap's questions asked once, answers from a script, the panel and the headset checked
// and recorded, and a script's point_answer aimed at the rating's button on the headset
// panel (the item laid out by Dear ImGui on the CPU, nothing rendered).
#include "trial/questionnaire_flow.hpp"

#include "trial_fakes.hpp"

#include <imgui.h>

#include <doctest/doctest.h>

#include <string>
#include <vector>

using namespace viewer;
using viewer::test::FakeTrialObserver;
using viewer::test::FakeTrialSource;
using viewer::test::rating;

namespace {

/// A run's trial controller over a source with questions at gaps 0 and 2.
struct Study {
    Study() {
        source.asked[0] = {rating("before", 1, 2), rating("before", 2, 2)};
        source.asked[2] = {rating("after", 1, 1)};
    }
    RunLog log;
    FakeTrialSource source;
    FakeTrialObserver observer;
    TrialController trials{&source, &observer, log, true};
    QuestionnaireFlow flow{trials, log, true};
};

OperatorInput answer(const std::string& text) {
    OperatorInput in;
    in.answer = text;
    return in;
}

/// Dear ImGui with a built font atlas and no renderer: enough to lay the item out.
struct HeadlessImGui {
    HeadlessImGui() {
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.DisplaySize = ImVec2(1024.0f, 1024.0f);
        io.DeltaTime = 1.0f / 60.0f;
        io.IniFilename = nullptr;
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    }
    ~HeadlessImGui() { ImGui::DestroyContext(); }
    /// One panel frame of the questionnaire, as drawFramePanels draws it in the headset.
    void frame(QuestionnaireFlow& flow) {
        PanelFrame p;
        flow.describe(p);
        ImGui::NewFrame();
        if (std::optional<Answer> clicked = p.questionnaire->draw(true, p.panel_pointer)) *p.answered = clicked;
        ImGui::EndFrame();
    }
};

}  // namespace

TEST_CASE("a gap's questions are asked once and each answer is recorded with where it came from") {
    Study s;
    CHECK_FALSE(s.flow.active());
    s.flow.ask(0);
    REQUIRE(s.flow.active());
    CHECK(s.log.json()["events"].back() == "questionnaire at gap 0");
    const QuestionnaireFrame f{7, false, 0, 0, glm::dvec3(0.0)};
    s.flow.update(answer("2"), f);
    CHECK(s.observer.calls == std::vector<std::string>{"answer 0 0 2"});
    CHECK(s.trials.decisions().back() == nlohmann::json{{"frame", 7},
                                                        {"action", "answer"},
                                                        {"gap", 0},
                                                        {"question", 0},
                                                        {"response", "2"},
                                                        {"skipped", false},
                                                        {"source", "script"}});
    // Asking the same gap again does not start it over: the second item is still up.
    s.flow.ask(0);
    s.flow.update(answer("3"), f);
    CHECK(s.observer.calls == std::vector<std::string>{"answer 0 0 2", "answer 0 1 3"});
    CHECK_FALSE(s.flow.active());
    s.flow.ask(0);
    CHECK_FALSE(s.flow.active());
    // A gap without questions asks nothing; a later one with questions does.
    s.flow.ask(1);
    CHECK_FALSE(s.flow.active());
    s.flow.ask(2);
    CHECK(s.flow.active());
    CHECK(s.log.json()["events"].back() == "questionnaire at gap 2");
}

TEST_CASE("an answer that does not fit the item is refused and the item stays up") {
    Study s;
    s.flow.ask(0);
    const QuestionnaireFrame f{1, false, 0, 0, glm::dvec3(0.0)};
    s.flow.update(answer("7"), f);  // the ratings run from 0 to 3
    s.flow.update(answer("two"), f);
    CHECK(s.flow.active());
    CHECK(s.observer.calls.empty());
    CHECK(s.trials.decisions().empty());
}

TEST_CASE("the panel's answer is the mouse's on the desktop, and a text item in the headset is skipped") {
    Study s;
    Question text = rating("comments", 2, 2);
    text.free_text = true;
    s.source.asked[0][1] = text;
    s.flow.ask(0);
    PanelFrame p;
    s.flow.describe(p);
    REQUIRE(p.answered != nullptr);
    *p.answered = Answer{"1", false};  // what the panel frame's click gave
    s.flow.update(OperatorInput{}, {3, false, 0, 0, glm::dvec3(0.0)});
    CHECK(s.trials.decisions().back()["source"] == "mouse");
    CHECK(s.trials.decisions().back()["response"] == "1");
    // The text item in the headset: skipped without an answer.
    s.flow.update(OperatorInput{}, {4, true, 512, 512, glm::dvec3(0.0)});
    CHECK(s.observer.calls.back() == "answer 0 1  skipped");
    CHECK(s.trials.decisions().back()["source"] == "headset");
    CHECK_FALSE(s.flow.active());
}

TEST_CASE("a script's point_answer aims from the head at the rating's button and pulls the trigger") {
    HeadlessImGui imgui;
    Study s;
    s.flow.ask(0);
    const glm::dvec3 head(0.1, 1.6, 0.2);
    const QuestionnaireFrame f{10, true, 1024, 1024, head};
    // The item's buttons have their places once it was drawn (after its first frame).
    CHECK_FALSE(s.flow.awaitsPointAnswer());
    imgui.frame(s.flow);
    imgui.frame(s.flow);
    CHECK(s.flow.awaitsPointAnswer());
    PanelFrame drawn;
    s.flow.describe(drawn);
    const std::optional<glm::dvec2> button = drawn.questionnaire->buttonCentre(2);
    REQUIRE(button);

    OperatorInput point;
    point.point_answer = 2;
    s.flow.update(point, f);
    CHECK_FALSE(s.flow.awaitsPointAnswer());  // held until answered
    PanelFrame p;
    s.flow.describe(p);
    REQUIRE(p.panel_pointer);
    CHECK(p.panel_pointer->x == doctest::Approx(button->x).epsilon(1e-9));
    CHECK(p.panel_pointer->y == doctest::Approx(button->y).epsilon(1e-9));
    CHECK(p.panel_click);
    // The panel frame takes the click on the button: the answer is the pointer's.
    *p.answered = Answer{"2", false};
    s.flow.update(OperatorInput{}, f);
    CHECK(s.observer.calls == std::vector<std::string>{"answer 0 0 2"});
    CHECK(s.trials.decisions().back()["source"] == "pointer");
    CHECK(s.flow.active());  // the second item is up, not yet drawn
    CHECK_FALSE(s.flow.awaitsPointAnswer());

    // A rating the item does not have: a warning, and the next point_answer may come.
    imgui.frame(s.flow);
    imgui.frame(s.flow);
    point.point_answer = 9;
    s.flow.update(point, f);
    CHECK(s.flow.awaitsPointAnswer());
    PanelFrame none;
    s.flow.describe(none);
    CHECK_FALSE(none.panel_pointer);
    CHECK_FALSE(none.panel_click);
}
