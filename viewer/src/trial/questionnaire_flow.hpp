// viewer/src/trial/questionnaire_flow.hpp: a study's questionnaires in the run (beside the
// TrialController): the questions of a gap between trials asked once, each item's answer
// taken from a script, a click or typing on the panel, or the controller's pointer on the
// headset's panel, checked and handed to the trial controller to report; a script's
// point_answer aims a ray from the head at the rating's button and pulls the trigger.
// The screen itself (ui/questionnaire_screen.hpp) draws the item.
#pragma once
#include "input/operator_input.hpp"
#include "run_log.hpp"
#include "trial/trial_controller.hpp"
#include "ui/panel.hpp"
#include "ui/questionnaire_screen.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace viewer {

/// What the flow reads of the frame.
struct QuestionnaireFrame {
    long frame = 0;
    bool headset = false;                   // an OpenXR session exists
    int panel_width = 0, panel_height = 0;  // the headset panel's texture (0: none drawn yet)
    glm::dvec3 head_tracking{0.0};          // the head between the eyes of the last XR frame
};

class QuestionnaireFlow {
  public:
    QuestionnaireFlow(TrialController& trials, RunLog& log, bool quiet);

    /// An item is up (the loop does nothing else then).
    bool active() const { return screen_.active(); }
    /// An item is up and drawn, and no script's point_answer is held (a script's next
    /// point_answer may come: ScriptClock::questionnaire_point).
    bool awaitsPointAnswer() const { return screen_.active() && screen_.shown() && !script_point_; }
    /// Asks the trial source's questions of gap `gap` unless a gap this far was asked
    /// already; stays inactive when the gap has none.
    void ask(int gap);
    /// While an item is up: a script's answer, else what was clicked or typed on the panel
    /// in the last panel frame, is checked and reported (a text item in the headset is
    /// skipped); then the controller's (or a script's) pointer is placed on the headset
    /// panel for the next panel frame.
    void update(const OperatorInput& in, const QuestionnaireFrame& f);
    /// The panel frame's part: the screen, where its answer goes, the pointer on the panel.
    void describe(PanelFrame& p);

  private:
    /// A script's answer, else the panel's; and the source it came from.
    std::optional<Answer> takeAnswer(const OperatorInput& in, const QuestionnaireFrame& f, const char*& source);
    void report(const Answer& answer, const char* source, long frame);
    /// The ray from the head to a script's rating's button on the headset panel, pulled
    /// again every few frames while the item stays up.
    void aimScript(const OperatorInput& in, const QuestionnaireFrame& f, bool& click);

    TrialController* trials_;
    RunLog* log_;
    bool quiet_ = false;
    QuestionnaireScreen screen_;
    int asked_gap_ = -1;                           // the last gap whose questions were asked
    std::optional<Answer> panel_answer_;           // clicked or typed in the last panel frame
    std::optional<glm::dvec2> panel_pointer_;      // the controller's pointer on the headset panel
    bool panel_click_ = false;                     // its trigger went down this frame
    std::optional<int> script_point_;              // a script's point_answer rating, until answered
    int script_wait_frames_ = 0;                   // frames since its trigger
    std::optional<TrackingRay> script_panel_ray_;  // a script's point_answer, held until answered
};

}  // namespace viewer
