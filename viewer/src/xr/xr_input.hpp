// viewer/src/xr/xr_input.hpp: what the controllers said in one frame, as read from the
// OpenXR actions (xr_actions.cpp) and handed on by the session (xr_session.hpp) to the
// input mapping (input/xr_input_mapping.hpp). Plain values: no OpenXR type, so the
// session, the actions and the mapping each include it without including one another.
#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <array>
#include <optional>

namespace viewer {

/// One hand's aim pose in the session's reference space.
struct XrHandPose {
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 position{0.0};
};

/// Controller input after xrSyncActions (only meaningful while FOCUSED); the actions and
/// their bindings are in xr_actions.cpp.
struct XrInput {
    bool toggle_pressed = false;  // the mode button went down this frame
    bool designate_pressed = false;
    bool confirm_pressed = false;
    bool reject_pressed = false;
    bool no_target_pressed = false;
    bool cycle_colour_pressed = false;
    bool toggle_cut_pressed = false;
    std::array<bool, 2> grab_held{false, false};   // left, right
    glm::vec2 move{0.0f};                          // thumbstick/trackpad: x strafe, y forward
    float turn = 0.0f;                             // right thumbstick x
    std::array<std::optional<XrHandPose>, 2> aim;  // left, right: when tracked
    int last_designate_hand = 1;                   // the hand whose designate went down last (0 left, 1 right)
    /// Hands the runtime has bound to an interaction profile (0: it reports no controller).
    int hands_bound = 0;
};

}  // namespace viewer
