// scene_info: sizes, positions and the target's height above the ground, measured on
// the loaded (local-frame) meshes.
#include <core/error.hpp>
#include <core/scene_info.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace core {
namespace {

// Does the vertical line through (x, y) cross triangle abc? Then, via `z_out`, the
// height where it does: barycentric coordinates of (x, y) in the triangle seen from
// above (the xy projection), which weigh the corners' z.
bool verticalHit(double x, double y, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double& z_out) {
    const double d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
    if (std::abs(d) < 1e-12) return false;  // vertical or degenerate seen from above
    const double l0 = ((b.y - c.y) * (x - c.x) + (c.x - b.x) * (y - c.y)) / d;
    const double l1 = ((c.y - a.y) * (x - c.x) + (a.x - c.x) * (y - c.y)) / d;
    const double l2 = 1.0 - l0 - l1;
    constexpr double kEps = -1e-9;  // points on an edge belong to both triangles
    if (l0 < kEps || l1 < kEps || l2 < kEps) return false;
    z_out = l0 * a.z + l1 * b.z + l2 * c.z;
    return true;
}

Bounds triangleBounds(const Mesh& m) {
    Bounds b;
    for (const glm::uvec3& t : m.triangles)
        for (int k = 0; k < 3; ++k) b.extend(glm::dvec3(m.vertices[t[k]]));
    return b;
}

std::string metres(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f m", v);
    return buffer;
}

}  // namespace

std::optional<double> groundHeightAt(const Scene& scene, double x, double y) {
    std::optional<double> z;
    for (const Mesh& m : scene.meshes) {
        if (m.role != Role::Ground) continue;
        for (const glm::uvec3& t : m.triangles) {
            double zt;
            if (verticalHit(x, y, glm::dvec3(m.vertices[t.x]), glm::dvec3(m.vertices[t.y]), glm::dvec3(m.vertices[t.z]),
                            zt) &&
                (!z || zt > *z))
                z = zt;
        }
    }
    return z;
}

SceneSummary summarize(const Scene& scene) {
    SceneSummary s;
    s.origin = scene.origin;
    Bounds target;
    bool any_target = false;
    for (const Mesh& m : scene.meshes) {
        MeshSummary ms;
        ms.file = m.name;
        ms.role = m.role;
        ms.triangles = m.triangles.size();
        ms.position = m.position;
        ms.bounds = triangleBounds(m);
        s.bounds.extend(ms.bounds);
        s.triangles += ms.triangles;
        s.has_ground = s.has_ground || m.role == Role::Ground;
        if (m.role == Role::Target) {
            any_target = true;
            target.extend(ms.bounds);
        }
        s.meshes.push_back(std::move(ms));
    }
    if (any_target) {
        TargetSummary t;
        t.bounds = target;
        if (!target.empty()) {
            const glm::dvec3 c = target.centre();
            t.ground_z = groundHeightAt(scene, c.x, c.y);
            if (t.ground_z) t.height_above_ground_m = target.lo.z - *t.ground_z;
        }
        s.target = t;
    }
    return s;
}

std::vector<std::string> targetWarnings(const SceneSummary& s) {
    std::vector<std::string> out;
    if (!s.target || s.target->bounds.empty()) return out;
    const TargetSummary& t = *s.target;
    const glm::dvec3 size = t.bounds.size();
    const double largest = std::max({size.x, size.y, size.z});
    if (largest > kMaxTargetSize_m)
        out.push_back("the target is " + metres(size.x) + " x " + metres(size.y) + " x " + metres(size.z) +
                      ", larger than " + shownNumber(kMaxTargetSize_m) +
                      " m: is the mesh in millimetres or centimetres? ('scale' converts it)");
    if (t.height_above_ground_m && *t.height_above_ground_m > kMaxTargetGroundGap_m)
        out.push_back("the target floats " + metres(*t.height_above_ground_m) +
                      " above the ground under its centre (more than " + shownNumber(kMaxTargetGroundGap_m) +
                      " m): check its 'position'");
    if (t.height_above_ground_m && *t.height_above_ground_m < -kMaxTargetGroundGap_m)
        out.push_back("the target sinks " + metres(-*t.height_above_ground_m) +
                      " below the ground under its centre (more than " + shownNumber(kMaxTargetGroundGap_m) +
                      " m): check its 'position'");
    if (!t.ground_z && s.has_ground)
        out.push_back("no ground mesh lies under the target's centre: check its 'position'");
    return out;
}

}  // namespace core
