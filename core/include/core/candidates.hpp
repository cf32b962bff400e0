// core/candidates.hpp: candidate detections of a 3D ATR, for the operator to validate.
// Their file format: io/candidates_file.hpp.
#pragma once
#include <glm/vec3.hpp>

#include <string>

namespace core {

/// A box around a possible target. centre in world coordinates (metres, z up, the box's
/// centre); size_m the box's length along its own x, width along its y, height; yaw_deg
/// counter-clockwise about +z from +x; score in [0, 1], higher is more likely a target.
struct Candidate {
    std::string id;
    glm::dvec3 centre_world{0.0};
    glm::dvec3 size_m{0.0};
    double yaw_deg = 0.0;
    double score = 0.0;
};

}  // namespace core
