// viewer/src/xr/xr_actions.cpp: the action set, its bindings per interaction profile, and
// reading it each frame.
#include "xr/xr_actions.hpp"

#include "xr/xr_check.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

// OpenXR's idiom `XrFoo foo{XR_TYPE_FOO};` value-initialises the other members on purpose.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace viewer {

XrPath XrActions::path(const char* text) const {
    XrPath p = XR_NULL_PATH;
    XR_CHECK(instance_, xrStringToPath(instance_, text, &p));
    return p;
}

void XrActions::suggest(const char* profile, std::initializer_list<std::pair<XrAction, const char*>> bindings) const {
    std::vector<XrActionSuggestedBinding> list;
    for (const auto& [action, binding] : bindings) list.push_back({action, path(binding)});
    XrInteractionProfileSuggestedBinding suggested{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    suggested.interactionProfile = path(profile);
    suggested.countSuggestedBindings = static_cast<std::uint32_t>(list.size());
    suggested.suggestedBindings = list.data();
    // A runtime may not know every profile; that is not an error for the others.
    XR_LOG(instance_, xrSuggestInteractionProfileBindings(instance_, &suggested));
}

void XrActions::suggestBindings() const {
    // The simple controller has four buttons (select and menu per hand): designate (right
    // select), confirm (right menu), mode (left select), no target (left menu); reject is
    // on the other profiles and the desktop's Backspace.
    suggest("/interaction_profiles/khr/simple_controller", {{aim_, "/user/hand/left/input/aim/pose"},
                                                            {aim_, "/user/hand/right/input/aim/pose"},
                                                            {designate_, "/user/hand/right/input/select/click"},
                                                            {confirm_, "/user/hand/right/input/menu/click"},
                                                            {toggle_, "/user/hand/left/input/select/click"},
                                                            {no_target_, "/user/hand/left/input/menu/click"}});
    suggest("/interaction_profiles/oculus/touch_controller",
            {{aim_, "/user/hand/left/input/aim/pose"},
             {aim_, "/user/hand/right/input/aim/pose"},
             {designate_, "/user/hand/left/input/trigger/value"},
             {designate_, "/user/hand/right/input/trigger/value"},
             {grab_, "/user/hand/left/input/squeeze/value"},
             {grab_, "/user/hand/right/input/squeeze/value"},
             {confirm_, "/user/hand/right/input/a/click"},
             {reject_, "/user/hand/right/input/b/click"},
             {toggle_, "/user/hand/left/input/x/click"},
             {no_target_, "/user/hand/left/input/y/click"},
             {move_, "/user/hand/left/input/thumbstick"},
             {turn_, "/user/hand/right/input/thumbstick/x"},
             {cycle_colour_, "/user/hand/left/input/thumbstick/click"},
             {toggle_cut_, "/user/hand/right/input/thumbstick/click"}});
    suggest("/interaction_profiles/valve/index_controller", {{aim_, "/user/hand/left/input/aim/pose"},
                                                             {aim_, "/user/hand/right/input/aim/pose"},
                                                             {designate_, "/user/hand/left/input/trigger/click"},
                                                             {designate_, "/user/hand/right/input/trigger/click"},
                                                             {grab_, "/user/hand/left/input/squeeze/value"},
                                                             {grab_, "/user/hand/right/input/squeeze/value"},
                                                             {confirm_, "/user/hand/right/input/a/click"},
                                                             {reject_, "/user/hand/right/input/b/click"},
                                                             {toggle_, "/user/hand/left/input/a/click"},
                                                             {no_target_, "/user/hand/left/input/b/click"},
                                                             {move_, "/user/hand/left/input/thumbstick"},
                                                             {turn_, "/user/hand/right/input/thumbstick/x"},
                                                             {cycle_colour_, "/user/hand/left/input/thumbstick/click"},
                                                             {toggle_cut_, "/user/hand/right/input/thumbstick/click"}});
    suggest("/interaction_profiles/htc/vive_controller", {{aim_, "/user/hand/left/input/aim/pose"},
                                                          {aim_, "/user/hand/right/input/aim/pose"},
                                                          {designate_, "/user/hand/left/input/trigger/click"},
                                                          {designate_, "/user/hand/right/input/trigger/click"},
                                                          {grab_, "/user/hand/left/input/squeeze/click"},
                                                          {grab_, "/user/hand/right/input/squeeze/click"},
                                                          {confirm_, "/user/hand/right/input/trackpad/click"},
                                                          {reject_, "/user/hand/left/input/trackpad/click"},
                                                          {toggle_, "/user/hand/left/input/menu/click"},
                                                          {no_target_, "/user/hand/right/input/menu/click"},
                                                          {move_, "/user/hand/left/input/trackpad"},
                                                          {turn_, "/user/hand/right/input/trackpad/x"}});
}

void XrActions::create(XrInstance instance, XrSession session) {
    instance_ = instance;
    session_ = session;
    XrActionSetCreateInfo set_info{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(set_info.actionSetName, "viewer");
    std::strcpy(set_info.localizedActionSetName, "Point cloud viewer");
    XR_CHECK(instance, xrCreateActionSet(instance, &set_info, &set_));
    hands_ = {path("/user/hand/left"), path("/user/hand/right")};

    auto make = [&](const char* name, const char* label, XrActionType type, XrAction& out, bool per_hand) {
        XrActionCreateInfo info{XR_TYPE_ACTION_CREATE_INFO};
        std::strcpy(info.actionName, name);
        std::strcpy(info.localizedActionName, label);
        info.actionType = type;
        if (per_hand) {
            info.countSubactionPaths = 2;
            info.subactionPaths = hands_.data();
        }
        XR_CHECK(instance, xrCreateAction(set_, &info, &out));
    };
    make("toggle_mode", "Toggle automatic / free mode", XR_ACTION_TYPE_BOOLEAN_INPUT, toggle_, false);
    make("designate", "Designate the picked point / dismiss the ready screen", XR_ACTION_TYPE_BOOLEAN_INPUT, designate_,
         true);
    make("confirm", "Confirm: this is the target", XR_ACTION_TYPE_BOOLEAN_INPUT, confirm_, false);
    make("reject", "Reject: this candidate is not a target", XR_ACTION_TYPE_BOOLEAN_INPUT, reject_, false);
    make("no_target", "No target in this cloud", XR_ACTION_TYPE_BOOLEAN_INPUT, no_target_, false);
    make("grab", "Grab the world (both hands: scale)", XR_ACTION_TYPE_BOOLEAN_INPUT, grab_, true);
    make("move", "Move (free mode)", XR_ACTION_TYPE_VECTOR2F_INPUT, move_, false);
    make("turn", "Turn (free mode)", XR_ACTION_TYPE_FLOAT_INPUT, turn_, false);
    make("aim", "Laser pointer", XR_ACTION_TYPE_POSE_INPUT, aim_, true);
    make("cycle_colour", "Next colour mode", XR_ACTION_TYPE_BOOLEAN_INPUT, cycle_colour_, false);
    make("toggle_cut", "Cutting volume on / off", XR_ACTION_TYPE_BOOLEAN_INPUT, toggle_cut_, false);

    suggestBindings();

    for (int h = 0; h < 2; ++h) {
        XrActionSpaceCreateInfo space_info{XR_TYPE_ACTION_SPACE_CREATE_INFO};
        space_info.action = aim_;
        space_info.subactionPath = hands_[h];
        space_info.poseInActionSpace.orientation.w = 1.0f;
        XR_CHECK(instance, xrCreateActionSpace(session, &space_info, &aim_spaces_[h]));
    }
    XrSessionActionSetsAttachInfo attach{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    attach.countActionSets = 1;
    attach.actionSets = &set_;
    XR_CHECK(instance, xrAttachSessionActionSets(session, &attach));
}

void XrActions::destroy() {
    for (XrSpace& s : aim_spaces_) {
        if (s != XR_NULL_HANDLE) xrDestroySpace(s);
        s = XR_NULL_HANDLE;
    }
    if (set_ != XR_NULL_HANDLE) xrDestroyActionSet(set_);
    set_ = XR_NULL_HANDLE;
}

bool XrActions::pressed(XrAction action, XrPath hand, bool* changed_to_down) const {
    XrActionStateGetInfo get{XR_TYPE_ACTION_STATE_GET_INFO};
    get.action = action;
    get.subactionPath = hand;
    XrActionStateBoolean state{XR_TYPE_ACTION_STATE_BOOLEAN};
    if (XR_FAILED(xrGetActionStateBoolean(session_, &get, &state)) || !state.isActive) return false;
    if (changed_to_down) *changed_to_down = state.changedSinceLastSync && state.currentState;
    return state.currentState;
}

XrInput XrActions::sync(XrSpace space, XrTime time) {
    XrInput input;
    XrActiveActionSet active{set_, XR_NULL_PATH};
    XrActionsSyncInfo sync_info{XR_TYPE_ACTIONS_SYNC_INFO};
    sync_info.countActiveActionSets = 1;
    sync_info.activeActionSets = &active;
    if (!XR_LOG(instance_, xrSyncActions(session_, &sync_info))) return input;
    for (const XrPath hand : hands_) {
        XrInteractionProfileState profile{XR_TYPE_INTERACTION_PROFILE_STATE};
        if (XR_SUCCEEDED(xrGetCurrentInteractionProfile(session_, hand, &profile)) &&
            profile.interactionProfile != XR_NULL_PATH)
            ++input.hands_bound;
    }
    auto went_down = [&](XrAction action, XrPath hand = XR_NULL_PATH) {
        bool down = false;
        pressed(action, hand, &down);
        return down;
    };
    input.toggle_pressed = went_down(toggle_);
    input.confirm_pressed = went_down(confirm_);
    input.reject_pressed = went_down(reject_);
    input.no_target_pressed = went_down(no_target_);
    input.cycle_colour_pressed = went_down(cycle_colour_);
    input.toggle_cut_pressed = went_down(toggle_cut_);
    for (int h = 0; h < 2; ++h) {
        if (went_down(designate_, hands_[h])) {
            input.designate_pressed = true;
            input.last_designate_hand = h;
        }
        input.grab_held[h] = pressed(grab_, hands_[h], nullptr);
    }
    XrActionStateGetInfo get{XR_TYPE_ACTION_STATE_GET_INFO};
    get.action = move_;
    XrActionStateVector2f move{XR_TYPE_ACTION_STATE_VECTOR2F};
    if (XR_SUCCEEDED(xrGetActionStateVector2f(session_, &get, &move)) && move.isActive)
        input.move = {move.currentState.x, move.currentState.y};
    get.action = turn_;
    XrActionStateFloat turn{XR_TYPE_ACTION_STATE_FLOAT};
    if (XR_SUCCEEDED(xrGetActionStateFloat(session_, &get, &turn)) && turn.isActive) input.turn = turn.currentState;
    if (time > 0) {
        for (int h = 0; h < 2; ++h) {
            XrSpaceLocation location{XR_TYPE_SPACE_LOCATION};
            if (XR_FAILED(xrLocateSpace(aim_spaces_[h], space, time, &location))) continue;
            const XrSpaceLocationFlags need =
                XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT;
            if ((location.locationFlags & need) != need) continue;
            const XrPosef& p = location.pose;
            input.aim[h] = XrHandPose{glm::dquat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z),
                                      glm::dvec3(p.position.x, p.position.y, p.position.z)};
        }
    }
    return input;
}

}  // namespace viewer
