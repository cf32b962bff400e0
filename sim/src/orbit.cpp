// sim/orbit.cpp: drone flight and Ladar sensor geometry, paper §III-A, Fig. 1, eqs. (1)-(2).
#include <sim/orbit.hpp>

#include <core/error.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <string>

namespace sim {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

std::string num(double v) { return core::shownNumber(v); }

[[noreturn]] void fail(const std::string& parameter, double value, const std::string& allowed) {
    throw core::Error("orbit: " + parameter + " = " + num(value) + ": allowed " + allowed);
}

void requireFinite(const char* parameter, double value) {
    if (!std::isfinite(value)) fail(parameter, value, "a finite number");
}

}  // namespace

void validate(const OrbitOptions& o) {
    requireFinite("altitude_m (--altitude-m)", o.altitude_m);
    requireFinite("overlap_m (--overlap-m)", o.overlap_m);
    requireFinite("inclination_deg (alpha, --alpha-deg)", o.inclination_deg);
    requireFinite("fov_deg (--fov-deg)", o.fov_deg);
    // Drone positions are float ray origins in the local frame: keep them where floats
    // still step by at most a metre (core::kMaxLocalCoordinate_m).
    const double far_m = core::kMaxLocalCoordinate_m;
    if (!(o.altitude_m > 0.0 && o.altitude_m <= far_m))
        fail("altitude_m (--altitude-m)", o.altitude_m, "(0, " + num(far_m) + "]");
    if (!(std::abs(o.overlap_m) <= far_m))
        fail("overlap_m (--overlap-m)", o.overlap_m, "[-" + num(far_m) + ", " + num(far_m) + "]");
    if (!(o.fov_deg > 0.0 && o.fov_deg <= 170.0)) fail("fov_deg (--fov-deg)", o.fov_deg, "(0, 170]");
    if (!(o.inclination_deg >= 0.0 && o.inclination_deg < 90.0))
        fail("inclination_deg (alpha, --alpha-deg)", o.inclination_deg, "[0, 90)");
    if (!(o.inclination_deg + 0.5 * o.fov_deg < kMaxGrazingDeg))
        throw core::Error("orbit: inclination_deg + fov_deg/2 (--alpha-deg + --fov-deg/2) = " +
                          num(o.inclination_deg + 0.5 * o.fov_deg) + ": allowed < " + num(kMaxGrazingDeg) +
                          " (the top of the image must look below the horizon)");
    if (o.xres < 1 || o.xres > 65536) fail("xres (--xres)", o.xres, "[1, 65536]");
    if (o.yres < 1 || o.yres > 65536) fail("yres (--yres)", o.yres, "[1, 65536]");
    if (o.views < 1 || o.views > 65535) fail("views (NoV, --views)", o.views, "[1, 65535]");
    const double reach_m = std::tan((o.inclination_deg + 0.5 * o.fov_deg) * kDegToRad) * o.altitude_m;
    if (!(o.overlap_m < reach_m))
        fail("overlap_m (--overlap-m)", o.overlap_m,
             "< tan(inclination + fov/2) * altitude = " + num(reach_m) + " (the drone radius, eq. (1), must be > 0)");
    if (!(reach_m - o.overlap_m <= far_m))
        throw core::Error(
            "orbit: drone radius tan(inclination + fov/2) * altitude - overlap "
            "(--alpha-deg, --fov-deg, --altitude-m, --overlap-m) = " +
            num(reach_m - o.overlap_m) + ": allowed <= " + num(far_m) + " m (drone positions are float ray origins)");
}

void validatePlacement(const OrbitOptions& o, const glm::dvec3& centre_local) {
    validate(o);
    const double radius_m = std::tan((o.inclination_deg + 0.5 * o.fov_deg) * kDegToRad) * o.altitude_m - o.overlap_m;
    const double reach_m = std::max({std::abs(centre_local.x) + radius_m, std::abs(centre_local.y) + radius_m,
                                     std::abs(centre_local.z + o.altitude_m)});
    if (!(reach_m <= core::kMaxLocalCoordinate_m))
        throw core::Error("orbit: the drone flies " + num(reach_m) + " m from the scene's origin around C " +
                          "(--centre, --altitude-m, --overlap-m): allowed <= " + num(core::kMaxLocalCoordinate_m) +
                          " m (drone positions are float ray origins)");
}

double droneRadius(const OrbitOptions& o) {
    validate(o);
    return std::tan((o.inclination_deg + 0.5 * o.fov_deg) * kDegToRad) * o.altitude_m - o.overlap_m;
}

double lengthSensed(const OrbitOptions& o) {
    const double radius_m = droneRadius(o);
    return radius_m + o.overlap_m - std::tan((o.inclination_deg - 0.5 * o.fov_deg) * kDegToRad) * o.altitude_m;
}

double coverageDiameter(const OrbitOptions& o) {
    validate(o);
    // By symmetry every view covers the same footprint rotated about C; the disc's
    // radius is the farthest ground hit of the four pixel-corner rays of view 0.
    const glm::dvec3 centre(0.0);
    const core::Pose T_world_sensor = sensorPose(o, centre, 0);
    double radius_m = 0.0;
    const double corners[4][2] = {
        {0.0, 0.0}, {double(o.xres), 0.0}, {0.0, double(o.yres)}, {double(o.xres), double(o.yres)}};
    for (const auto& c : corners) {
        // pixelDirection adds 0.5 to reach a pixel centre; corners sit 0.5 before it.
        const glm::dvec3 d = T_world_sensor.applyDirection(pixelDirection(o, c[0] - 0.5, c[1] - 0.5));
        // The sensor's x axis is horizontal, so a corner ray descends exactly as steeply
        // as the centre of its image edge; validate() keeps the top edge below the horizon.
        assert(d.z < 0.0);
        const double t = -T_world_sensor.translation.z / d.z;
        const glm::dvec3 p = T_world_sensor.translation + t * d;
        radius_m = std::max(radius_m, std::hypot(p.x - centre.x, p.y - centre.y));
    }
    return 2.0 * radius_m;
}

core::Pose sensorPose(const OrbitOptions& o, const glm::dvec3& centre, int index) {
    const double radius_m = droneRadius(o);
    const double theta = 2.0 * std::numbers::pi * double(index) / double(o.views);
    const double alpha = o.inclination_deg * kDegToRad;
    const glm::dvec3 outward(std::cos(theta), std::sin(theta), 0.0);
    core::Pose T_world_sensor;
    T_world_sensor.translation = centre + radius_m * outward + glm::dvec3(0.0, 0.0, o.altitude_m);
    // Optical axis: horizontally towards C, pitched alpha from the vertical (Fig. 1).
    const glm::dvec3 forward = glm::dvec3(-outward.x * std::sin(alpha), -outward.y * std::sin(alpha), -std::cos(alpha));
    // Right = the horizontal tangent of the orbit (forward x up_world, normalised, for
    // alpha > 0), built from theta directly so that nadir (alpha = 0, forward = -z, where
    // that cross product is zero) gets a valid frame too; down = forward x right.
    const glm::dvec3 right(-std::sin(theta), std::cos(theta), 0.0);
    const glm::dvec3 down = glm::cross(forward, right);
    T_world_sensor.rotation = glm::dmat3(right, down, forward);  // columns: sensor x, y, z
    return T_world_sensor;
}

glm::dvec3 pixelDirection(const OrbitOptions& o, double px, double py) {
    // Focal length in pixels from the vertical FoV; square pixels, so the horizontal
    // FoV is 2 atan(tan(fov/2) * xres / yres).
    const double focal_px = 0.5 * double(o.yres) / std::tan(0.5 * o.fov_deg * kDegToRad);
    const glm::dvec3 d((px + 0.5 - 0.5 * double(o.xres)) / focal_px, (py + 0.5 - 0.5 * double(o.yres)) / focal_px, 1.0);
    return glm::normalize(d);
}

}  // namespace sim
