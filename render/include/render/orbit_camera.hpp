// render/orbit_camera.hpp: the virtual camera that circles the scene, shared by the
// viewer's automatic mode (paper §IV-A) and the visibility metric (paper §IV-B: "we
// segment the circular rotation into 100 images, rotating the virtual camera as in the
// first mode of the immersive visualization"), plus the camera maths both need.
//
// Conventions: positions are in the scene's local frame (world - origin, z up, metres,
// core/frames.hpp). GL camera: looks down -z, y up; pixel (px, py) counts from the
// bottom-left corner of the image, its centre is at (px + 0.5, py + 0.5).
#pragma once
#include <core/frames.hpp>

#include <glm/glm.hpp>

namespace render {

/// Orbit of the automatic mode and of the metric. The paper gives no radius or height for
/// the VR orbit; the defaults put a ~7 m target at ~5 degrees, a few thousand pixels at
/// 512x512 like the paper's Fig. 3 (6908 px), with the whole 125 m scene in view.
struct OrbitCameraOptions {
    double radius_m = 60.0;    // horizontal distance from the orbit centre (> 0)
    double altitude_m = 40.0;  // eye height above the orbit centre (any finite value)
    double vfov_deg = 30.0;    // vertical field of view, paper §IV-B (0, 170]
    int views = 100;           // images per turn, paper §IV-B (1..65535)
    double start_deg = 0.0;    // azimuth of view 0, from +x towards +y
    double near_m = 0.1;       // clip planes (0 < near < far)
    double far_m = 20000.0;
};

/// Throws core::Error("orbit-camera: <field> = <value>: allowed <range>") for any field
/// outside the ranges given above or non-finite.
void validate(const OrbitCameraOptions& o);

/// A look-at camera in the local frame; `up` is a unit vector orthogonal to the view axis.
struct CameraPose {
    glm::dvec3 eye{0.0};
    glm::dvec3 look_at{0.0, 0.0, -1.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
};

/// Azimuth of view k: start + 360 * k / views degrees, in radians.
double orbitAngleRad(const OrbitCameraOptions& o, int view);
/// The camera at azimuth `angle_rad` around `centre`: eye = centre + (r cos, r sin, altitude),
/// looking at `centre`, up = world z projected orthogonal to the view axis (straight down
/// with radius 0 uses the azimuth direction as up).
CameraPose orbitPose(const OrbitCameraOptions& o, const glm::dvec3& centre, double angle_rad);
/// orbitPose at orbitAngleRad(o, view).
CameraPose orbitView(const OrbitCameraOptions& o, const glm::dvec3& centre, int view);

/// Right-handed GL view matrix (world-to-camera, camera looks down -z), double precision.
glm::dmat4 viewMatrix(const CameraPose& pose);
/// GL perspective projection (depth -1..1) for a vertical FoV in degrees and width/height.
glm::dmat4 projectionMatrix(double vfov_deg, double aspect, double near_m, double far_m);

/// An axis-aligned pixel rectangle [x0, x1) x [y0, y1), bottom-left origin.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    long long area() const { return empty() ? 0 : 1LL * width() * height(); }
};

/// The projection that maps only the pixels of `rect` of a width x height image onto the
/// whole viewport: draw with glViewport(0, 0, rect.width(), rect.height()) and this
/// matrix and each pixel lands exactly where it would at (px - x0, py - y0).
glm::dmat4 subRectProjection(const glm::dmat4& projection, int width, int height, const PixelRect& rect);

/// Screen rectangle covered by `bounds` (local frame) under `view_projection`, grown by
/// `margin_px` and clipped to the image. Empty if the box is outside the frustum; the
/// whole image if the box crosses the eye plane (conservative).
PixelRect projectBounds(const glm::dmat4& view_projection, const core::Bounds& bounds, int width, int height,
                        double margin_px);

/// Unit direction (local frame) of the ray from the eye through pixel centre
/// (px + 0.5, py + 0.5) of a width x height image: the same pixel grid GL rasterises.
glm::dvec3 pixelCentreDirection(const CameraPose& pose, double vfov_deg, int width, int height, int px, int py);

/// Six planes of a view-projection matrix (GL clip space), for conservative box culling.
struct Frustum {
    glm::dvec4 planes[6];
    /// Planes from `view_projection` (Gribb-Hartmann), normals pointing inwards.
    static Frustum fromMatrix(const glm::dmat4& view_projection);
    /// False only if the box is certainly outside (entirely behind one plane).
    bool intersects(const core::Bounds& bounds) const;
};

}  // namespace render
