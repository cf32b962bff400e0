// viewer/src/input/operator_input.hpp: what the operator asked for in one frame, whatever the
// source (desktop keys and mouse in desktop_input.cpp, the OpenXR actions through
// xr_input_mapping.cpp, a --script in script_player.cpp, a recorded trace in
// replay_player.cpp, all in input/).
// Each source returns one OperatorInput; the frame loop merges them and hands the result
// to the tools and the trial controller; no tool reads a device.
#pragma once
#include <viewer/mode_controller.hpp>
#include <viewer/trial.hpp>

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace viewer {

/// A pointer ray in the tracking frame (before the zoom and the rig).
struct TrackingRay {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};
};

struct OperatorInput {
    bool toggle_mode = false;
    const char* toggle_source = "key";  // logged with the mode switch
    bool designate = false;
    bool confirm = false;
    bool reject = false;
    bool no_target = false;
    bool next = false;  // dismiss the ready screen
    bool quit = false;
    bool reset_zoom = false;
    bool cycle_colour = false;
    bool toggle_cut = false;
    double cut_radius_step = 0.0;     // +1 / -1: grow / shrink the cutting volume
    double wheel = 0.0;               // mouse wheel steps (+ zooms in)
    std::optional<double> set_scale;  // script grab_scale
    /// A script's answer to the questionnaire item on screen (a rating's number or text).
    std::optional<std::string> answer;
    /// A script standing in for the controller: aim at this rating's button on the headset
    /// panel and pull the trigger.
    std::optional<int> point_answer;
    Motion motion;
    /// Snap turn request this frame: +1 right, -1 left (free mode, headset).
    int snap_turn = 0;
    /// The controller pointer, when a hand's aim pose is tracked (tracking frame).
    std::optional<TrackingRay> controller_ray;
    /// Both hands' positions while both grab (tracking frame), for grab-and-scale.
    std::optional<std::pair<glm::dvec3, glm::dvec3>> grab_hands;
    /// A script's aim: the pointer runs from the head to this world point from now on.
    std::optional<glm::dvec3> aim_world;
    /// A controller's designate takes the pointer back from a script's aim.
    bool release_aim = false;
    /// A replayed trace: the sample to show this frame, and whether its last one was shown.
    std::optional<TraceSample> replay;
    bool replay_done = false;
    /// A replay's recorded marks (designations, verdicts) that came due this frame, in order.
    std::vector<TrialMark> replay_marks;
};

/// Adds `from` to `into`: flags are or-ed, steps and motion summed, and what `from` sets
/// (a toggle's source, a scale, a ray, a grab, an aim, a replay sample) replaces `into`'s.
void merge(OperatorInput& into, const OperatorInput& from);

}  // namespace viewer
