// viewer/world_zoom.hpp: zooming the world (grab-and-scale with two controllers, the
// mouse wheel, a script's grab_scale) as a similarity of the tracking frame.
//
// The zoom maps a tracking-frame point p to p / scale + offset, and the modes' rig maps
// that into the cloud (viewer/mode_controller.hpp): a scale of 4 makes the cloud look four
// times larger. The eyes' view matrices carry the scale (computed in double), so
// camera-relative precision holds at every scale. Pure maths, no GL.
#pragma once
#include <viewer/mode_controller.hpp>

#include <glm/vec3.hpp>

namespace viewer {

struct ZoomOptions {
    double min_scale = 0.05;   // the cloud at most 20 times smaller than life
    double max_scale = 200.0;  // at most 200 times larger
};

class WorldZoom {
  public:
    explicit WorldZoom(const ZoomOptions& options = {}) : options_(options) {}

    double scale() const { return scale_; }
    const glm::dvec3& offset() const { return offset_; }
    /// The zoomed tracking point of tracking point `p`.
    glm::dvec3 apply(const glm::dvec3& p) const { return p / scale_ + offset_; }
    /// The tracking point whose zoomed point is `q`.
    glm::dvec3 unapply(const glm::dvec3& q) const { return (q - offset_) * scale_; }
    /// A tracking-frame pose in the zoomed frame (orientation kept).
    RigPose apply(const RigPose& p) const { return {p.rotation, apply(p.position)}; }

    /// Sets the scale (clamped to the options' range) keeping the tracking point `pivot`
    /// on the same zoomed point: what is under the pivot stays under it.
    void scaleAbout(const glm::dvec3& pivot, double new_scale);

    /// Two-handed grab: begin with both hands' tracking positions, then update with their
    /// positions each frame. The scale follows the ratio of the hands' distances and the
    /// point between the hands at the start stays between them (scaled about the
    /// midpoint, moved with it). A begin with hands closer than 1 cm is ignored.
    void beginGrab(const glm::dvec3& left, const glm::dvec3& right);
    void updateGrab(const glm::dvec3& left, const glm::dvec3& right);
    void endGrab() { grabbing_ = false; }
    bool grabbing() const { return grabbing_; }

    /// Back to life size, no offset.
    void reset();

  private:
    ZoomOptions options_;
    double scale_ = 1.0;
    glm::dvec3 offset_{0.0};
    bool grabbing_ = false;
    double grab_scale_ = 1.0, grab_distance_m_ = 1.0;
    glm::dvec3 grab_point_{0.0};  // the zoomed point between the hands at the start
};

}  // namespace viewer
