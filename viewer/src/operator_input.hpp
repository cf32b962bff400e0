// viewer/src/operator_input.hpp: what the operator asked for in one frame, whatever the
// source (OpenXR actions, desktop keys and mouse, a --script). The frame loop merges the
// sources into one OperatorInput and hands it to the tools; no tool reads a device.
#pragma once
#include <viewer/camera_rig.hpp>

#include <glm/vec3.hpp>

#include <optional>

namespace viewer {

/// A pointer ray in the tracking frame (before the zoom and the rig).
struct TrackingRay {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};
};

struct OperatorInput {
    bool toggle_mode = false;
    const char* toggle_source = "key";   // logged with the mode switch
    bool designate = false;
    bool confirm = false;
    bool reject = false;
    bool no_target = false;
    bool next = false;            // dismiss the ready screen
    bool quit = false;
    bool reset_zoom = false;
    bool cycle_colour = false;
    bool toggle_cut = false;
    double cut_radius_step = 0.0; // +1 / -1: grow / shrink the cutting volume
    double wheel = 0.0;           // mouse wheel steps (+ zooms in)
    std::optional<double> set_scale;   // script grab_scale
    Motion motion;
    /// Snap turn request this frame: +1 right, -1 left (free mode, headset).
    int snap_turn = 0;
    /// The controller pointer, when a hand's aim pose is tracked (tracking frame).
    std::optional<TrackingRay> controller_ray;
    /// Both hands' positions while both grab (tracking frame), for grab-and-scale.
    std::optional<std::pair<glm::dvec3, glm::dvec3>> grab_hands;
};

}  // namespace viewer
