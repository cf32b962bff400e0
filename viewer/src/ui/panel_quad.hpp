// viewer/src/ui/panel_quad.hpp: where the headset's panel hangs (a quad in the tracking frame
// textured with the desktop mirror's ImGui windows) and where a controller's ray meets
// it, so the laser pointer can click the panel's buttons.
#pragma once
#include "input/operator_input.hpp"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <optional>

namespace viewer {

/// A flat rectangle: its centre, unit axes along its width (right) and height (up), and
/// its size in metres; it faces along right x up.
struct PanelQuad {
    glm::dvec3 centre{0.0};
    glm::dvec3 right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0};
    double width_m = 0.8, height_m = 0.45;
};

/// The headset panel for a texture of `width_px` x `height_px`: 1.1 m ahead of the
/// tracking origin (the head at the session's start), its centre 0.6 m below eye level
/// (below the gaze, where the target is not), 0.8 m wide, facing the origin.
PanelQuad headsetPanelQuad(int width_px, int height_px);

/// Its corners: bottom left, bottom right, top right, top left (the texture's (0,0),
/// (1,0), (1,1), (0,1)).
std::array<glm::dvec3, 4> panelCorners(const PanelQuad& quad);

/// Where `ray` meets the quad's front, as a point of the panel's image from its top left
/// (0..1 across, 0..1 down: ImGui's coordinates over the display size); nullopt when the
/// ray misses, runs parallel to it, meets it behind its origin or from behind.
std::optional<glm::dvec2> panelHit(const PanelQuad& quad, const TrackingRay& ray);

}  // namespace viewer
