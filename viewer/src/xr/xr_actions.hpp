// viewer/src/xr/xr_actions.hpp: the viewer's OpenXR actions and their suggested bindings on
// every controller profile, in one place (hello_xr's input split). The session
// (xr_session.cpp) creates them once and syncs them each frame; the input mapping
// (input/xr_input_mapping.hpp) turns what it read into an OperatorInput.
//
// Actions: toggle_mode, designate (also dismisses the ready screen), confirm, reject,
// no_target, grab (both hands held: grab-and-scale), move (free mode), turn (snap turn
// in free mode), cycle_colour, toggle_cut (the cutting volume), and an aim pose per hand
// (the laser pointer). docs/viewer.md has the
// table of buttons per profile.
#pragma once
#include "xr/xr_input.hpp"

#include <openxr/openxr.h>

#include <array>
#include <initializer_list>
#include <utility>

namespace viewer {

class XrActions {
  public:
    /// Creates the action set, the actions and the aim spaces, suggests bindings for
    /// every known profile and attaches the set to `session`. Throws core::Error.
    void create(XrInstance instance, XrSession session);
    void destroy();
    /// xrSyncActions and reads every action; aim poses located in `space` at `time`.
    /// Never throws; returns a zeroed input on a runtime error (logged).
    XrInput sync(XrSpace space, XrTime time);

  private:
    XrPath path(const char* text) const;
    void suggest(const char* profile, std::initializer_list<std::pair<XrAction, const char*>> bindings) const;
    /// Suggests the bindings on every known profile (docs/viewer.md's table).
    void suggestBindings() const;
    bool pressed(XrAction action, XrPath hand, bool* changed_to_down) const;

    XrInstance instance_ = XR_NULL_HANDLE;
    XrSession session_ = XR_NULL_HANDLE;
    XrActionSet set_ = XR_NULL_HANDLE;
    XrAction toggle_ = XR_NULL_HANDLE, designate_ = XR_NULL_HANDLE, confirm_ = XR_NULL_HANDLE, reject_ = XR_NULL_HANDLE,
             no_target_ = XR_NULL_HANDLE, grab_ = XR_NULL_HANDLE, move_ = XR_NULL_HANDLE, turn_ = XR_NULL_HANDLE,
             aim_ = XR_NULL_HANDLE, cycle_colour_ = XR_NULL_HANDLE, toggle_cut_ = XR_NULL_HANDLE;
    std::array<XrPath, 2> hands_{XR_NULL_PATH, XR_NULL_PATH};
    std::array<XrSpace, 2> aim_spaces_{XR_NULL_HANDLE, XR_NULL_HANDLE};
};

}  // namespace viewer
