// viewer/mode_controller.hpp: the two viewing modes of paper §IV-A as pure camera maths.
//
// Frames: the *tracking* frame is OpenXR's reference space (x right, y up, -z forward,
// metres; the HMD's head and eyes live in it). The *rig* maps it into the cloud's local
// frame (z up): T_local_tracking. An eye's pose in the cloud is T_local_tracking * T_tracking_eye.
// - Automatic: the rig rides the orbit camera of render/orbit_camera.hpp (the same
//   defaults as the metric's virtual camera), circling the cloud's centre and looking at
//   it; head tracking adds rotation and small head motion on top; the user cannot translate.
// - Free: the rig is level (tracking y = local z) at a position the user moves with the
//   keyboard or thumbstick, flying along the gaze; physical walking adds on top.
// On the desktop there is no HMD: the "head" is a mouse-look orientation at the rig origin.
#pragma once
#include <render/orbit_camera.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace viewer {

enum class ViewMode { Automatic, Free };

/// "automatic" or "free".
const char* modeName(ViewMode mode);

/// A pose: rotation and position, double precision.
struct RigPose {
    glm::dmat3 rotation{1.0};
    glm::dvec3 position{0.0};
    glm::dvec3 apply(const glm::dvec3& p) const { return rotation * p + position; }
};

/// Options of the two modes; defaults shared with the metric's orbit camera.
struct ModeOptions {
    render::OrbitCameraOptions orbit;  // radius, altitude, vfov, near/far of the automatic mode
    double orbit_period_s = 60.0;      // one turn of the automatic orbit (> 0)
    double free_speed_mps = 15.0;      // keyboard / thumbstick speed in free mode (> 0)
    double turn_speed_dps = 90.0;      // thumbstick turn rate in free mode
    /// Fit the orbit's radius and height, the start pose and the free-mode speed to the
    /// cloud's extent (fittedToExtent) as its bounds arrive; off keeps the values above.
    bool fit_to_cloud = false;
};

/// `o` scaled to a cloud of extent `size_m` (its bounds' hi - lo): the orbit radius becomes
/// half the cloud's horizontal diagonal, so the camera circles above the cloud's edge and
/// the cloud fills the view; the height and free-mode speed keep their ratio to the radius,
/// the far plane reaches past the cloud. A radius under 1 m is taken as 1 m.
ModeOptions fittedToExtent(const ModeOptions& o, const glm::dvec3& size_m);

/// Throws core::Error("view: <field> = <value>: allowed ...") on bad values.
void validate(const ModeOptions& o);

/// Free-mode motion request for one frame: components in [-1, 1].
struct Motion {
    double forward = 0.0;  // along the gaze
    double right = 0.0;
    double up = 0.0;    // along local z
    double turn = 0.0;  // positive turns right (thumbstick)
};

/// The rig of both modes and the switch between them.
class ModeController {
  public:
    /// `centre` is the orbit centre in the cloud's local frame (the cloud's bounds centre).
    ModeController(const ModeOptions& options, const glm::dvec3& centre);

    ViewMode mode() const { return mode_; }
    const ModeOptions& options() const { return options_; }
    double orbitAngleRad() const { return angle_rad_; }
    void setCentre(const glm::dvec3& centre) { centre_ = centre; }
    /// Centres the orbit on the cloud's bounds and, when fit_to_cloud is on, fits the modes
    /// to its extent (from the options given at construction, so growing bounds refit).
    void setCloudBounds(const glm::dvec3& lo, const glm::dvec3& hi);
    const glm::dvec3& centre() const { return centre_; }

    /// Advances by dt: the orbit angle in automatic mode, the position/heading in free mode
    /// (`head` is the tracking-frame head pose, whose gaze gives the direction of travel).
    void update(double dt_s, const Motion& motion, const RigPose& head);
    /// Free mode: turns the rig's heading by `deg` at once (positive turns right), the
    /// comfort option of headsets (snap turn); automatic mode: nothing.
    void snapTurn(double deg);
    /// T_local_tracking for the current mode.
    RigPose rig() const;
    /// Switches mode keeping the head's position and gaze heading in the cloud (no jump in
    /// position; entering free mode levels the rig). Returns the new mode.
    ViewMode toggle(const RigPose& head);
    /// The desktop variant: the head is the mouse look (yaw, pitch) at the rig origin. The
    /// look angles are rewritten so the view does not jump (free: level rig + pitch;
    /// automatic: look straight at the orbit centre again).
    ViewMode toggleDesktop(double& look_yaw_rad, double& look_pitch_rad);

  private:
    ModeOptions given_;  // as constructed: what a fit starts from
    ModeOptions options_;
    glm::dvec3 centre_;
    ViewMode mode_ = ViewMode::Automatic;
    double angle_rad_ = 0.0;
    glm::dvec3 free_position_{0.0};
    double free_heading_rad_ = 0.0;  // world heading of tracking -z, from +x towards +y
};

/// The orbit rig: tracking -z looks from the orbit camera's eye at its look_at point.
RigPose rigFromCamera(const render::CameraPose& camera);
/// A level rig at `position` whose tracking -z points at heading `heading_rad`.
RigPose levelRig(const glm::dvec3& position, double heading_rad);
/// A tracking-frame orientation from desktop mouse-look angles (yaw about y, then pitch about x).
glm::dquat lookOrientation(double yaw_rad, double pitch_rad);
/// World-to-eye GL view matrix for an eye whose pose in the cloud is `eye` (-z forward, y up).
glm::dmat4 viewFromPose(const RigPose& eye);
/// GL projection (depth -1..1) from OpenXR's asymmetric FoV angles (radians).
glm::dmat4 projectionFromFov(double angle_left, double angle_right, double angle_up, double angle_down, double near_m,
                             double far_m);
/// The model-view of a chunk stored relative to `chunk_centre` (local frame): computed in
/// double, then cast, so float vertices near the chunk centre stay exact far from the origin.
glm::mat4 chunkModelView(const glm::dmat4& view, const glm::dvec3& chunk_centre);

}  // namespace viewer
