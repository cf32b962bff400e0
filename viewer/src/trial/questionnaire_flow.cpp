// viewer/src/trial/questionnaire_flow.cpp: asking a gap's questions, taking and checking
// each answer, and the pointer on the headset's panel.
#include "trial/questionnaire_flow.hpp"

#include "ui/panel_quad.hpp"

#include <platform/safe_file.hpp>

#include <cstdio>
#include <string>

namespace viewer {

QuestionnaireFlow::QuestionnaireFlow(TrialController& trials, RunLog& log, bool quiet)
    : trials_(&trials), log_(&log), quiet_(quiet) {}

void QuestionnaireFlow::ask(int gap) {
    if (gap <= asked_gap_) return;
    asked_gap_ = gap;
    screen_.start(gap, trials_->questions(gap));
    if (!screen_.active()) return;
    log_->event("questionnaire at gap " + std::to_string(gap));
    if (!quiet_) std::fprintf(stderr, "ladarvr: study: questionnaire: %s\n", screen_.current().title.c_str());
}

std::optional<Answer> QuestionnaireFlow::takeAnswer(const OperatorInput& in, const QuestionnaireFrame& f,
                                                    const char*& source) {
    std::optional<Answer> answer;
    source = "script";
    if (in.answer) {
        answer = Answer{*in.answer, false};
    } else if (panel_answer_) {
        answer = panel_answer_;
        source = f.headset && panel_pointer_ ? "pointer" : "mouse";
    }
    panel_answer_.reset();
    if (screen_.current().free_text && f.headset) {  // no keyboard in the headset
        answer = Answer{"", true};
        source = "headset";
    }
    return answer;
}

void QuestionnaireFlow::report(const Answer& answer, const char* source, long frame) {
    const Question& q = screen_.current();
    if (const std::string why = screen_.check(answer); !why.empty()) {
        platform::printMessage("warning",
                               "study: answer '" + answer.response + "' to '" + q.text + "' refused: " + why);
        return;
    }
    trials_->answered(screen_.gap(), screen_.index(), answer, source, frame);
    script_panel_ray_.reset();
    script_point_.reset();
    if (!quiet_)
        std::fprintf(stderr, "ladarvr: study: question %d of %d answered (%s)%s\n", q.number, q.count, source,
                     answer.skipped ? ": skipped" : "");
    screen_.advance();
    if (!screen_.active()) {
        if (!quiet_) std::fprintf(stderr, "ladarvr: study: questionnaire done\n");
        if (trials_->readyScreen()) trials_->restartReadyClock();  // the break starts now
    } else if (!quiet_ && screen_.current().number == 1) {
        std::fprintf(stderr, "ladarvr: study: questionnaire: %s\n", screen_.current().title.c_str());
    }
}

void QuestionnaireFlow::aimScript(const OperatorInput& in, const QuestionnaireFrame& f, bool& click) {
    // A script standing in for the controller: a ray from the head to the rating's button
    // where the panel shows it, held until the item is answered, and a trigger; pulled
    // again every few frames while the item stays up (a window that moved meanwhile).
    if (in.point_answer) {
        script_point_ = *in.point_answer;
        script_wait_frames_ = 0;
    } else if (script_point_ && ++script_wait_frames_ >= 4) {
        script_wait_frames_ = 0;
    }
    if (!script_point_ || script_wait_frames_ != 0) return;
    if (const auto uv = screen_.buttonCentre(*script_point_)) {
        const PanelQuad quad = headsetPanelQuad(f.panel_width, f.panel_height);
        const glm::dvec3 on_panel =
            quad.centre + quad.right * ((uv->x - 0.5) * quad.width_m) + quad.up * ((0.5 - uv->y) * quad.height_m);
        script_panel_ray_ = TrackingRay{f.head_tracking, glm::normalize(on_panel - f.head_tracking)};
        click = true;
    } else {
        platform::printMessage(
            "warning", "study: point_answer " + std::to_string(*script_point_) + ": no such rating on the item up");
        script_point_.reset();
        script_panel_ray_.reset();
    }
}

void QuestionnaireFlow::update(const OperatorInput& in, const QuestionnaireFrame& f) {
    const char* source = "script";
    if (const std::optional<Answer> answer = takeAnswer(in, f, source)) report(*answer, source, f.frame);
    panel_pointer_.reset();
    panel_click_ = false;
    if (!f.headset || f.panel_width <= 0 || !screen_.active()) {
        script_panel_ray_.reset();
        script_point_.reset();
        return;
    }
    std::optional<TrackingRay> ray = in.controller_ray;
    bool click = in.designate;
    aimScript(in, f, click);
    if (script_panel_ray_) ray = script_panel_ray_;
    if (ray)
        if (const auto uv = panelHit(headsetPanelQuad(f.panel_width, f.panel_height), *ray)) {
            panel_pointer_ = *uv;
            panel_click_ = click;
        }
}

void QuestionnaireFlow::describe(PanelFrame& p) {
    p.questionnaire = &screen_;
    p.answered = &panel_answer_;
    p.panel_pointer = panel_pointer_;
    p.panel_click = panel_click_;
}

}  // namespace viewer
