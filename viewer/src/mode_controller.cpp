// viewer/src/mode_controller.cpp: automatic orbit and free mode (paper §IV-A).
#include <viewer/mode_controller.hpp>

#include <core/error.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace viewer {

const char* modeName(ViewMode mode) { return mode == ViewMode::Automatic ? "automatic" : "free"; }

void validate(const ModeOptions& o) {
    render::validate(o.orbit);
    auto positive = [](double v, const char* name) {
        if (!(std::isfinite(v) && v > 0.0))
            throw core::Error(std::string("view: ") + name + " = " + std::to_string(v) +
                              ": allowed a finite value > 0");
    };
    positive(o.orbit_period_s, "orbit_period_s");
    positive(o.free_speed_mps, "free_speed_mps");
    positive(o.turn_speed_dps, "turn_speed_dps");
}

RigPose rigFromCamera(const render::CameraPose& camera) {
    const glm::dvec3 forward = glm::normalize(camera.look_at - camera.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
    const glm::dvec3 up = glm::cross(right, forward);
    RigPose rig;
    rig.rotation = glm::dmat3(right, up, -forward);  // columns: tracking x, y, z in local
    rig.position = camera.eye;
    return rig;
}

RigPose levelRig(const glm::dvec3& position, double heading_rad) {
    const glm::dvec3 forward(std::cos(heading_rad), std::sin(heading_rad), 0.0);
    const glm::dvec3 up(0.0, 0.0, 1.0);
    const glm::dvec3 right = glm::cross(forward, up);
    RigPose rig;
    rig.rotation = glm::dmat3(right, up, -forward);
    rig.position = position;
    return rig;
}

glm::dquat lookOrientation(double yaw_rad, double pitch_rad) {
    return glm::angleAxis(yaw_rad, glm::dvec3(0, 1, 0)) * glm::angleAxis(pitch_rad, glm::dvec3(1, 0, 0));
}

glm::dmat4 viewFromPose(const RigPose& eye) {
    glm::dmat4 camera_to_world(eye.rotation);
    camera_to_world[3] = glm::dvec4(eye.position, 1.0);
    return glm::inverse(camera_to_world);
}

glm::dmat4 projectionFromFov(double angle_left, double angle_right, double angle_up, double angle_down, double near_m,
                             double far_m) {
    const double l = std::tan(angle_left) * near_m, r = std::tan(angle_right) * near_m;
    const double t = std::tan(angle_up) * near_m, b = std::tan(angle_down) * near_m;
    return glm::frustum(l, r, b, t, near_m, far_m);
}

glm::mat4 chunkModelView(const glm::dmat4& view, const glm::dvec3& chunk_centre) {
    return glm::mat4(view * glm::translate(glm::dmat4(1.0), chunk_centre));
}

ModeOptions fittedToExtent(const ModeOptions& o, const glm::dvec3& size_m) {
    ModeOptions fitted = o;
    const double radius_m = std::max(0.5 * std::hypot(size_m.x, size_m.y), 1.0);
    if (!std::isfinite(radius_m)) return fitted;
    const double scale = radius_m / o.orbit.radius_m;
    fitted.orbit.radius_m = radius_m;
    fitted.orbit.altitude_m = o.orbit.altitude_m * scale;
    fitted.free_speed_mps = o.free_speed_mps * scale;
    // The far side of the cloud from the orbit, with room for its height and free flight.
    fitted.orbit.far_m = std::max(o.orbit.far_m, 10.0 * (radius_m + std::abs(fitted.orbit.altitude_m) + size_m.z));
    return fitted;
}

ModeController::ModeController(const ModeOptions& options, const glm::dvec3& centre)
    : given_(options), options_(options), centre_(centre) {
    angle_rad_ = options_.orbit.start_deg * std::numbers::pi / 180.0;
}

void ModeController::setCloudBounds(const glm::dvec3& lo, const glm::dvec3& hi) {
    centre_ = 0.5 * (lo + hi);
    if (given_.fit_to_cloud) options_ = fittedToExtent(given_, hi - lo);
}

RigPose ModeController::rig() const {
    if (mode_ == ViewMode::Automatic) return rigFromCamera(render::orbitPose(options_.orbit, centre_, angle_rad_));
    return levelRig(free_position_, free_heading_rad_);
}

void ModeController::snapTurn(double deg) {
    if (mode_ == ViewMode::Free && std::isfinite(deg)) free_heading_rad_ -= deg * std::numbers::pi / 180.0;
}

void ModeController::update(double dt_s, const Motion& motion, const RigPose& head) {
    if (!(dt_s > 0.0) || !std::isfinite(dt_s)) return;
    dt_s = std::min(dt_s, 0.25);  // a stalled frame must not teleport the user
    if (mode_ == ViewMode::Automatic) {
        angle_rad_ += 2.0 * std::numbers::pi * dt_s / options_.orbit_period_s;
        angle_rad_ = std::fmod(angle_rad_, 2.0 * std::numbers::pi);
        return;
    }
    free_heading_rad_ -= motion.turn * options_.turn_speed_dps * std::numbers::pi / 180.0 * dt_s;
    const RigPose r = rig();
    const glm::dvec3 gaze = r.rotation * (head.rotation * glm::dvec3(0, 0, -1));
    const glm::dvec3 right = r.rotation * (head.rotation * glm::dvec3(1, 0, 0));
    const glm::dvec3 velocity = motion.forward * gaze + motion.right * right + motion.up * glm::dvec3(0, 0, 1);
    free_position_ += velocity * options_.free_speed_mps * dt_s;
}

ViewMode ModeController::toggle(const RigPose& head) {
    const RigPose r = rig();
    const glm::dvec3 head_local = r.apply(head.position);
    if (mode_ == ViewMode::Automatic) {
        // Keep the gaze heading: world heading = rig heading - head yaw (right is clockwise).
        const glm::dvec3 gaze_t = head.rotation * glm::dvec3(0, 0, -1);
        const glm::dvec3 gaze_w = r.rotation * gaze_t;
        const double heading_w = std::atan2(gaze_w.y, gaze_w.x);
        const double head_yaw = std::atan2(gaze_t.x, -gaze_t.z);
        free_heading_rad_ =
            (std::abs(gaze_w.z) > 0.999) ? std::atan2(-r.rotation[2].y, -r.rotation[2].x) : heading_w + head_yaw;
        const RigPose level = levelRig(glm::dvec3(0.0), free_heading_rad_);
        free_position_ = head_local - level.rotation * head.position;
        mode_ = ViewMode::Free;
    } else {
        mode_ = ViewMode::Automatic;  // resume the orbit where it was
    }
    return mode_;
}

ViewMode ModeController::toggleDesktop(double& look_yaw_rad, double& look_pitch_rad) {
    const RigPose r = rig();
    const glm::dvec3 gaze_w =
        r.rotation * (glm::mat3_cast(lookOrientation(look_yaw_rad, look_pitch_rad)) * glm::dvec3(0, 0, -1));
    if (mode_ == ViewMode::Automatic) {
        free_position_ = r.position;
        free_heading_rad_ = std::atan2(gaze_w.y, gaze_w.x);
        look_yaw_rad = 0.0;
        look_pitch_rad = std::asin(std::clamp(gaze_w.z, -1.0, 1.0));
        mode_ = ViewMode::Free;
    } else {
        look_yaw_rad = 0.0;
        look_pitch_rad = 0.0;
        mode_ = ViewMode::Automatic;
    }
    return mode_;
}

}  // namespace viewer
