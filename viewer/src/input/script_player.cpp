// viewer/src/input/script_player.cpp: a --script's lines as operator input.
#include "input/script_player.hpp"

namespace viewer {

OperatorInput ScriptPlayer::take(const ScriptClock& clock) {
    OperatorInput in;
    bool barrier = false;
    while (next_ < events_.size() && !barrier) {
        const ScriptEvent& ev = events_[next_];
        const long base = ev.after_desktop    ? clock.desktop_since_frame
                          : ev.after_loaded   ? clock.loaded_since_frame
                          : ev.after_pickable ? clock.pickable_since_frame
                          : ev.relative       ? last_frame_
                                              : 0;
        // Compared without a sum: neither side can overflow, whatever the event's frame.
        if (base < 0 || ev.frame > clock.frame - base) break;
        if (ev.key == ScriptEvent::Key::Next && (clock.ready_screen_waiting || clock.questionnaire_up)) break;
        if ((ev.key == ScriptEvent::Key::Answer || ev.key == ScriptEvent::Key::PointAnswer) && !clock.question_up)
            break;
        ++next_;
        last_frame_ = clock.frame;
        barrier = ev.key == ScriptEvent::Key::Next || ev.key == ScriptEvent::Key::Confirm ||
                  ev.key == ScriptEvent::Key::NoTarget || ev.key == ScriptEvent::Key::Answer ||
                  ev.key == ScriptEvent::Key::PointAnswer;
        switch (ev.key) {
            case ScriptEvent::Key::Space:
                in.toggle_mode = true;
                in.toggle_source = "script";
                break;
            case ScriptEvent::Key::Escape: in.quit = true; break;
            case ScriptEvent::Key::Aim: in.aim_world = glm::dvec3(ev.point[0], ev.point[1], ev.point[2]); break;
            case ScriptEvent::Key::Designate: in.designate = true; break;
            case ScriptEvent::Key::Confirm: in.confirm = true; break;
            case ScriptEvent::Key::Reject: in.reject = true; break;
            case ScriptEvent::Key::NoTarget: in.no_target = true; break;
            case ScriptEvent::Key::GrabScale: in.set_scale = ev.value; break;
            case ScriptEvent::Key::Next: in.next = true; break;
            case ScriptEvent::Key::Answer: in.answer = ev.text; break;
            case ScriptEvent::Key::PointAnswer: in.point_answer = static_cast<int>(ev.value); break;
            case ScriptEvent::Key::Cut: in.toggle_cut = true; break;
            case ScriptEvent::Key::Colour: in.cycle_colour = true; break;
        }
    }
    return in;
}

}  // namespace viewer
