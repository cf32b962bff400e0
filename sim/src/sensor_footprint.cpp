// sim/src/sensor_footprint.cpp: the beam footprint sampled by sub-rays, as HELIOS++ does:
// the axis plus q - 1 concentric rings, ring k holding int(2 pi k) sub-rays equally spaced
// in angle (q = 3: 1 + 6 + 12 = 19). Here the rings are spread up to the divergence's half
// angle (the 1/e^2 edge of a Gaussian beam), with independent half angles across (x) and
// down (y) the image for an elliptical footprint, and each sub-ray carries the Gaussian
// profile's share of the pulse energy, exp(-2 (r / r_edge)^2), normalised to sum 1.
#include <sim/sensor.hpp>

#include <cmath>
#include <numbers>

namespace sim {

std::vector<SubRay> footprintPattern(const SensorOptions& o) {
    std::vector<SubRay> rays;
    rays.push_back(SubRay{0.0, 0.0, 1.0});
    if (!(o.beam_divergence_mrad > 0.0)) return rays;
    const double half_x = 0.5e-3 * o.beam_divergence_mrad;
    const double half_y = 0.5e-3 * (o.beam_divergence_y_mrad > 0.0 ? o.beam_divergence_y_mrad : o.beam_divergence_mrad);
    const int q = o.footprint_quality;
    for (int k = 1; k < q; ++k) {
        const double r = double(k) / double(q - 1);  // fraction of the 1/e^2 edge
        const int n = int(2.0 * std::numbers::pi * double(k));
        const double w = std::exp(-2.0 * r * r);
        for (int j = 0; j < n; ++j) {
            const double phi = 2.0 * std::numbers::pi * double(j) / double(n);
            rays.push_back(SubRay{half_x * r * std::cos(phi), half_y * r * std::sin(phi), w});
        }
    }
    double total = 0.0;
    for (const SubRay& s : rays) total += s.weight;
    for (SubRay& s : rays) s.weight /= total;
    return rays;
}

BeamFrame beamFrame(const glm::dvec3& axis) {
    // Across: perpendicular to the axis in the plane of the axis and the image's x axis;
    // down: completes the frame (the image's y axis for the boresight).
    BeamFrame f;
    f.axis = axis;
    glm::dvec3 across = glm::dvec3(1.0, 0.0, 0.0) - axis * axis.x;
    const double len = glm::length(across);
    f.across = len > 1e-12 ? across / len : glm::dvec3(0.0, 1.0, 0.0);
    f.down = glm::cross(axis, f.across);
    return f;
}

glm::dvec3 subRayDirection(const BeamFrame& f, double tan_dx, double tan_dy) {
    if (tan_dx == 0.0 && tan_dy == 0.0) return f.axis;
    return glm::normalize(f.axis + tan_dx * f.across + tan_dy * f.down);
}

glm::dvec3 subRayDirection(const glm::dvec3& axis, const SubRay& s) {
    return subRayDirection(beamFrame(axis), std::tan(s.dx_rad), std::tan(s.dy_rad));
}

}  // namespace sim
