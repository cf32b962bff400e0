// viewer/src/ui/panel_quad.cpp: the headset panel's place and the pointer's hit on it.
#include "ui/panel_quad.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace viewer {

PanelQuad headsetPanelQuad(int width_px, int height_px) {
    PanelQuad q;
    q.centre = glm::dvec3(0.0, -0.6, -1.1);
    q.width_m = 0.8;
    q.height_m = q.width_m * height_px / std::max(1, width_px);
    return q;
}

std::array<glm::dvec3, 4> panelCorners(const PanelQuad& q) {
    const glm::dvec3 r = q.right * (q.width_m / 2), u = q.up * (q.height_m / 2);
    return {q.centre - r - u, q.centre + r - u, q.centre + r + u, q.centre - r + u};
}

std::optional<glm::dvec2> panelHit(const PanelQuad& q, const TrackingRay& ray) {
    const glm::dvec3 normal = glm::cross(q.right, q.up);  // towards the viewer
    const double facing = glm::dot(ray.direction, normal);
    if (!(facing < -1e-9)) return std::nullopt;  // parallel, from behind, or not a number
    const double t = glm::dot(q.centre - ray.origin, normal) / facing;
    if (!(t > 0.0) || !std::isfinite(t)) return std::nullopt;
    const glm::dvec3 local = ray.origin + t * ray.direction - q.centre;
    const double u = glm::dot(local, q.right) / q.width_m + 0.5;
    const double v = 0.5 - glm::dot(local, q.up) / q.height_m;
    if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) return std::nullopt;
    return glm::dvec2(u, v);
}

}  // namespace viewer
