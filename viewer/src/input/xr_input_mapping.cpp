// viewer/src/input/xr_input_mapping.cpp: buttons, thumbsticks, aim poses and grips to an
// OperatorInput.
#include "input/xr_input_mapping.hpp"

#include <cmath>
#include <utility>

namespace viewer {

OperatorInput XrInputMapping::map(const XrInput& xin, bool snap_turn) {
    OperatorInput in;
    if (xin.toggle_pressed) {
        in.toggle_mode = true;
        in.toggle_source = "controller";
    }
    in.designate = xin.designate_pressed;
    in.next = xin.designate_pressed;  // the trigger starts a trial
    in.confirm = xin.confirm_pressed;
    in.reject = xin.reject_pressed;
    in.no_target = xin.no_target_pressed;
    in.cycle_colour = xin.cycle_colour_pressed;
    in.toggle_cut = xin.toggle_cut_pressed;
    in.motion.forward = xin.move.y;
    in.motion.right = xin.move.x;
    if (snap_turn) {
        if (std::abs(xin.turn) > 0.7f) in.snap_turn = xin.turn > 0 ? 1 : -1;
    } else {
        in.motion.turn = xin.turn;
    }
    if (xin.designate_pressed) pointer_hand_ = xin.last_designate_hand;
    const auto& aim = xin.aim[pointer_hand_] ? xin.aim[pointer_hand_] : xin.aim[1 - pointer_hand_];
    if (aim) {
        in.controller_ray = TrackingRay{aim->position, glm::mat3_cast(aim->orientation) * glm::dvec3(0, 0, -1)};
        in.release_aim = xin.designate_pressed;  // a controller took over from a script
    }
    if (xin.grab_held[0] && xin.grab_held[1] && xin.aim[0] && xin.aim[1])
        in.grab_hands = std::make_pair(xin.aim[0]->position, xin.aim[1]->position);
    return in;
}

}  // namespace viewer
