// sim/src/sensor_pose.cpp: GNSS/INS error. A drone's trajectory comes from a GNSS/INS
// solution with a position error of a few centimetres and an attitude error of a fraction
// of a milliradian; each view's points are placed with the logged (nominal) pose while the
// rays left from the pose actually flown, so views no longer register perfectly. The error
// is the sum of a per-flight bias (drawn once per seed) and a per-view error.
#include "sensor_models.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <numbers>

namespace sim::sensor_model {
namespace {

// Rotation by small angles (radians) about the sensor's x, y, z axes, in that order.
glm::dmat3 smallRotation(double rx, double ry, double rz) {
    const glm::dmat4 r =
        glm::rotate(glm::rotate(glm::rotate(glm::dmat4(1.0), rz, glm::dvec3(0, 0, 1)), ry, glm::dvec3(0, 1, 0)), rx,
                    glm::dvec3(1, 0, 0));
    return glm::dmat3(r);
}

}  // namespace

core::Pose actualPose(const SensorOptions& o, std::uint64_t seed, int view, const core::Pose& nominal) {
    const double position_m[2] = {o.pose_bias_m, o.pose_noise_m};
    const double attitude_rad[2] = {o.attitude_bias_deg * std::numbers::pi / 180.0,
                                    o.attitude_noise_deg * std::numbers::pi / 180.0};
    if (position_m[0] <= 0.0 && position_m[1] <= 0.0 && attitude_rad[0] <= 0.0 && attitude_rad[1] <= 0.0)
        return nominal;
    glm::dvec3 shift(0.0), angles(0.0);
    for (int part = 0; part < 2; ++part) {  // 0: the flight's bias, 1: this view's error
        const std::uint64_t k =
            part == 0 ? key(seed, Stream::PoseFlight, 0, 0) : key(seed, Stream::PoseView, std::uint64_t(view), 0);
        for (int axis = 0; axis < 3; ++axis) {
            shift[axis] += position_m[part] * gaussian(k, std::uint64_t(axis));
            angles[axis] += attitude_rad[part] * gaussian(k, std::uint64_t(3 + axis));
        }
    }
    core::Pose actual = nominal;
    actual.translation += shift;
    actual.rotation = nominal.rotation * smallRotation(angles.x, angles.y, angles.z);
    return actual;
}

}  // namespace sim::sensor_model
