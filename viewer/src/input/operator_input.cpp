// viewer/src/input/operator_input.cpp: merging the input sources of one frame.
#include "input/operator_input.hpp"

namespace viewer {

void merge(OperatorInput& into, const OperatorInput& from) {
    if (from.toggle_mode) {
        into.toggle_mode = true;
        into.toggle_source = from.toggle_source;
    }
    into.designate = into.designate || from.designate;
    into.confirm = into.confirm || from.confirm;
    into.reject = into.reject || from.reject;
    into.no_target = into.no_target || from.no_target;
    into.next = into.next || from.next;
    into.quit = into.quit || from.quit;
    into.reset_zoom = into.reset_zoom || from.reset_zoom;
    into.cycle_colour = into.cycle_colour || from.cycle_colour;
    into.toggle_cut = into.toggle_cut || from.toggle_cut;
    into.release_aim = into.release_aim || from.release_aim;
    into.replay_done = into.replay_done || from.replay_done;
    into.cut_radius_step += from.cut_radius_step;
    into.wheel += from.wheel;
    into.motion.forward += from.motion.forward;
    into.motion.right += from.motion.right;
    into.motion.up += from.motion.up;
    into.motion.turn += from.motion.turn;
    if (from.snap_turn != 0) into.snap_turn = from.snap_turn;
    if (from.set_scale) into.set_scale = from.set_scale;
    if (from.answer) into.answer = from.answer;
    if (from.point_answer) into.point_answer = from.point_answer;
    if (from.controller_ray) into.controller_ray = from.controller_ray;
    if (from.grab_hands) into.grab_hands = from.grab_hands;
    if (from.aim_world) into.aim_world = from.aim_world;
    if (from.replay) into.replay = from.replay;
    into.replay_marks.insert(into.replay_marks.end(), from.replay_marks.begin(), from.replay_marks.end());
}

}  // namespace viewer
