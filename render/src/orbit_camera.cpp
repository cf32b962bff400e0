// render/src/orbit_camera.cpp: orbit and camera maths (see orbit_camera.hpp; paper §IV-A/B).
#include <render/orbit_camera.hpp>

#include <core/error.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace render {
namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void invalid(const char* field, double value, const char* allowed) {
    std::ostringstream s;
    s << "orbit-camera: " << field << " = " << value << ": allowed " << allowed;
    throw core::Error(s.str());
}

}  // namespace

void validate(const OrbitCameraOptions& o) {
    if (!std::isfinite(o.radius_m) || o.radius_m <= 0.0) invalid("radius_m", o.radius_m, "> 0 metres");
    if (!std::isfinite(o.altitude_m)) invalid("altitude_m", o.altitude_m, "a finite number of metres");
    if (!std::isfinite(o.vfov_deg) || o.vfov_deg <= 0.0 || o.vfov_deg > 170.0)
        invalid("vfov_deg", o.vfov_deg, "(0, 170] degrees");
    if (o.views < 1 || o.views > 65535) invalid("views", o.views, "1..65535");
    if (!std::isfinite(o.start_deg)) invalid("start_deg", o.start_deg, "a finite angle in degrees");
    if (!std::isfinite(o.near_m) || o.near_m <= 0.0) invalid("near_m", o.near_m, "> 0 metres");
    if (!std::isfinite(o.far_m) || o.far_m <= o.near_m) invalid("far_m", o.far_m, "> near_m");
}

double orbitAngleRad(const OrbitCameraOptions& o, int view) {
    return (o.start_deg + 360.0 * static_cast<double>(view) / static_cast<double>(o.views)) * kPi / 180.0;
}

CameraPose orbitPose(const OrbitCameraOptions& o, const glm::dvec3& centre, double angle_rad) {
    CameraPose pose;
    const glm::dvec3 radial{std::cos(angle_rad), std::sin(angle_rad), 0.0};
    pose.eye = centre + o.radius_m * radial + glm::dvec3(0.0, 0.0, o.altitude_m);
    pose.look_at = centre;
    const glm::dvec3 forward = glm::normalize(pose.look_at - pose.eye);
    glm::dvec3 up{0.0, 0.0, 1.0};
    if (glm::length(glm::cross(forward, up)) < 1e-9) up = -radial;  // looking straight down/up
    pose.up = glm::normalize(up - glm::dot(up, forward) * forward);
    return pose;
}

CameraPose orbitView(const OrbitCameraOptions& o, const glm::dvec3& centre, int view) {
    return orbitPose(o, centre, orbitAngleRad(o, view));
}

glm::dmat4 viewMatrix(const CameraPose& pose) { return glm::lookAtRH(pose.eye, pose.look_at, pose.up); }

glm::dmat4 projectionMatrix(double vfov_deg, double aspect, double near_m, double far_m) {
    return glm::perspectiveRH_NO(vfov_deg * kPi / 180.0, aspect, near_m, far_m);
}

glm::dmat4 subRectProjection(const glm::dmat4& projection, int width, int height, const PixelRect& rect) {
    // NDC of the rect [x0,x1] -> [-1,1]: x' = sx * x + tx, applied after the projection.
    const double sx = static_cast<double>(width) / rect.width();
    const double sy = static_cast<double>(height) / rect.height();
    const double tx = sx * (1.0 - 2.0 * rect.x0 / width) - 1.0;  // maps ndc(x0) = 2x0/w-1 to -1
    const double ty = sy * (1.0 - 2.0 * rect.y0 / height) - 1.0;
    glm::dmat4 crop(1.0);
    crop[0][0] = sx;
    crop[1][1] = sy;
    crop[3][0] = tx;
    crop[3][1] = ty;
    return crop * projection;
}

PixelRect projectBounds(const glm::dmat4& view_projection, const core::Bounds& bounds, int width, int height,
                        double margin_px) {
    PixelRect none{};
    if (bounds.empty()) return none;
    if (!Frustum::fromMatrix(view_projection).intersects(bounds)) return none;
    double lo_x = 1e300, lo_y = 1e300, hi_x = -1e300, hi_y = -1e300;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p{(corner & 1) ? bounds.hi.x : bounds.lo.x, (corner & 2) ? bounds.hi.y : bounds.lo.y,
                           (corner & 4) ? bounds.hi.z : bounds.lo.z};
        const glm::dvec4 clip = view_projection * glm::dvec4(p, 1.0);
        if (clip.w <= 1e-9) return PixelRect{0, 0, width, height};  // crosses the eye plane
        const double x = (clip.x / clip.w * 0.5 + 0.5) * width;
        const double y = (clip.y / clip.w * 0.5 + 0.5) * height;
        lo_x = std::min(lo_x, x);
        hi_x = std::max(hi_x, x);
        lo_y = std::min(lo_y, y);
        hi_y = std::max(hi_y, y);
    }
    auto clampi = [](double v, int hi) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(hi))); };
    PixelRect r;
    constexpr double kRound = 1e-6;  // pixel edges hit exactly must not grow the rect
    r.x0 = clampi(std::floor(lo_x - margin_px + kRound), width);
    r.x1 = clampi(std::ceil(hi_x + margin_px - kRound), width);
    r.y0 = clampi(std::floor(lo_y - margin_px + kRound), height);
    r.y1 = clampi(std::ceil(hi_y + margin_px - kRound), height);
    return r.empty() ? none : r;
}

glm::dvec3 pixelCentreDirection(const CameraPose& pose, double vfov_deg, int width, int height, int px, int py) {
    const glm::dvec3 forward = glm::normalize(pose.look_at - pose.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, pose.up));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tan_half = std::tan(vfov_deg * kPi / 360.0);
    const double aspect = static_cast<double>(width) / height;
    const double ndc_x = (px + 0.5) / width * 2.0 - 1.0;
    const double ndc_y = (py + 0.5) / height * 2.0 - 1.0;
    return glm::normalize(forward + ndc_x * tan_half * aspect * right + ndc_y * tan_half * up);
}

Frustum Frustum::fromMatrix(const glm::dmat4& m) {
    // Rows of the matrix (glm is column-major: m[col][row]).
    auto row = [&](int r) { return glm::dvec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
    Frustum f;
    f.planes[0] = row(3) + row(0);  // left
    f.planes[1] = row(3) - row(0);  // right
    f.planes[2] = row(3) + row(1);  // bottom
    f.planes[3] = row(3) - row(1);  // top
    f.planes[4] = row(3) + row(2);  // near
    f.planes[5] = row(3) - row(2);  // far
    return f;
}

bool Frustum::intersects(const core::Bounds& b) const {
    if (b.empty()) return false;
    for (const glm::dvec4& p : planes) {
        // The box corner farthest along the plane normal.
        const glm::dvec3 v{p.x >= 0 ? b.hi.x : b.lo.x, p.y >= 0 ? b.hi.y : b.lo.y, p.z >= 0 ? b.hi.z : b.lo.z};
        if (p.x * v.x + p.y * v.y + p.z * v.z + p.w < 0.0) return false;
    }
    return true;
}

}  // namespace render
