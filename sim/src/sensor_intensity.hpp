// sim/src/sensor_intensity.hpp: intensity by the lidar range equation for an extended
// Lambertian target (the beam footprint lies wholly on the surface):
//   P_r = P_t * D_r^2 * eta * rho * cos(theta) / (4 R^2),
// with every system constant folded into one reference range R0 at which a target of
// reflectance 1 at normal incidence reads full scale (65535):
//   I = 65535 * min(1, rho * cos(theta) * (R0 / R)^2).
// Inline: the sensor evaluates it for every echo of every sub-ray.
#pragma once
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace sim::sensor_model {

/// cos of the angle between a ray and a surface of geometric normal `normal` (any length,
/// either side); 1 for a degenerate normal.
inline double cosIncidence(const glm::dvec3& ray, const glm::dvec3& normal) {
    const double n = glm::length(normal) * glm::length(ray);
    if (!(n > 0.0)) return 1.0;
    return std::min(1.0, std::abs(glm::dot(ray, normal)) / n);
}
/// Received power of an extended Lambertian target as a fraction of full scale:
/// reflectance * cos(incidence) * (R0 / range)^2, unclamped (R0: the reference range).
inline double echoPower(double reflectance, double cos_incidence, double range_m, double reference_range_m) {
    const double r = std::max(range_m, 1e-6);
    const double q = reference_range_m / r;
    return reflectance * cos_incidence * q * q;
}
/// The LAS intensity of a power fraction: round(65535 * min(1, power)).
inline std::uint16_t intensityCounts(double power) {
    return std::uint16_t(std::lround(65535.0 * std::clamp(power, 0.0, 1.0)));
}

}  // namespace sim::sensor_model
