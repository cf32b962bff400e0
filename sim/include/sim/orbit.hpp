// sim/orbit.hpp: drone flight and Ladar sensor geometry (paper §III-A, Fig. 1).
#pragma once
#include <core/frames.hpp>

#include <cstdint>
#include <vector>

namespace sim {

/// Flight and sensor parameters; defaults are the paper's values (§III-A).
struct OrbitOptions {
    double altitude_m = 300.0;      // drone height above the centre C
    double overlap_m = 10.0;        // CO in Fig. 1: how far past C the footprint reaches
    double inclination_deg = 45.0;  // alpha: angle of the optical axis from the vertical
    double fov_deg = 6.5;           // sensor field of view (square pixels; vertical FoV)
    int xres = 128;                 // pixels across
    int yres = 128;                 // pixels down
    int views = 100;                // NoV: drone positions equally spaced on the circle
};

/// Validates every field; throws core::Error("orbit: <parameter> = <value> ...: allowed ...")
/// for alpha + fov/2 >= kMaxGrazingDeg, fov outside (0, 170], resolution or views < 1
/// (or views > 65535), altitude outside (0, 1e7], |overlap| > 1e7, a drone radius over
/// 1e7 m (core::kMaxLocalCoordinate_m), or any non-finite value.
void validate(const OrbitOptions& o);

/// validate(o), then that every drone position around `centre_local` (C in the scene's
/// local frame) lies within core::kMaxLocalCoordinate_m of the local origin.
void validatePlacement(const OrbitOptions& o, const glm::dvec3& centre_local);

/// Largest accepted alpha + fov/2, degrees. Past it the drone radius exceeds ~11,000x the
/// altitude and the footprint is meaningless; the bound is documented in docs/generator.md.
inline constexpr double kMaxGrazingDeg = 89.99;

/// Drone radius, paper eq. (1): tan(alpha + fov/2) * altitude - CO.
double droneRadius(const OrbitOptions& o);
/// Length sensed on the ground, paper eq. (2): radius + CO - tan(alpha - fov/2) * altitude.
double lengthSensed(const OrbitOptions& o);
/// Diameter of the disc covered on flat ground by the whole orbit, counting the
/// footprint's corners (the paper's "125 m"): twice the largest distance from C of the
/// ground hit of a pixel-corner ray of the pinhole.
double coverageDiameter(const OrbitOptions& o);

/// Pose of the sensor at view `index` (0..views-1) around centre C (local frame):
/// drone at C + (r cos t, r sin t, altitude) with t = 2 pi index / views, optical axis
/// towards the ground point at distance CO past C, pitched alpha from the vertical.
/// Returns T_world_sensor (sensor frame: x right, y down, z forward).
core::Pose sensorPose(const OrbitOptions& o, const glm::dvec3& centre, int index);

/// Unit direction, in the sensor frame, of the ray through pixel (px, py)'s centre
/// ((px + 0.5, py + 0.5) in pixel units), for a pinhole whose vertical FoV is fov_deg.
glm::dvec3 pixelDirection(const OrbitOptions& o, double px, double py);

}  // namespace sim
