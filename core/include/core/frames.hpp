// core/frames.hpp: coordinate frames and the naming rule for transforms.
//
// World: metres, right-handed, z up. A scene may be georeferenced far from the
// origin, so everything in memory is held in a *local* frame: local = world - origin,
// where `origin` is a double-precision vec3 carried by the Scene and the PointCloud
// (and stored in every output file). Float precision is then enough for centimetre
// accuracy 10^6 m from the world origin.
//
// Transforms are named by frames: T_a_b maps points expressed in frame b into frame
// a, so T_world_sensor * p_sensor = p_world and T_a_b * T_b_c = T_a_c.
// Sensor (camera) frame: x right, y down, z forward (optical axis), as a pinhole.
#pragma once
#include <glm/glm.hpp>

namespace core {

/// Largest |world coordinate| accepted (scene positions and origin, orbit centre): far
/// past any Earth-centred (6.4e6 m) or projected (1e7 m) coordinate, and double still
/// resolves steps under a micrometre there. Beyond it a run would silently lose the scene.
inline constexpr double kMaxWorldCoordinate_m = 1e9;
/// Largest |local coordinate| accepted (mesh vertices, drone positions): floats step by
/// at most 1 m up to 1e7 m (2^23 < 1e7 < 2^24); farther out rays and points fall apart.
inline constexpr double kMaxLocalCoordinate_m = 1e7;

/// A rigid transform (rotation + translation) in double precision.
struct Pose {
    glm::dmat3 rotation{1.0};
    glm::dvec3 translation{0.0};

    glm::dvec3 apply(const glm::dvec3& p) const { return rotation * p + translation; }
    glm::dvec3 applyDirection(const glm::dvec3& d) const { return rotation * d; }
};

/// Axis-aligned bounds; empty() until the first extend().
struct Bounds {
    glm::dvec3 lo{1e300};
    glm::dvec3 hi{-1e300};

    bool empty() const { return lo.x > hi.x; }
    void extend(const glm::dvec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Bounds& b) {
        if (!b.empty()) {
            extend(b.lo);
            extend(b.hi);
        }
    }
    glm::dvec3 centre() const { return 0.5 * (lo + hi); }
    glm::dvec3 size() const { return empty() ? glm::dvec3(0.0) : hi - lo; }
};

}  // namespace core
