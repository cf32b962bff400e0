// scene: what a loaded scene holds, measured over its meshes.
#include <core/scene.hpp>

#include <cmath>
#include <numbers>

namespace core {

glm::dvec3 tilt(const glm::dvec3& v, double pitch_deg, double roll_deg) {
    glm::dvec3 p = v;
    if (roll_deg != 0.0) {  // about x: y towards z
        const double a = roll_deg * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
        p = glm::dvec3(p.x, c * p.y - s * p.z, s * p.y + c * p.z);
    }
    if (pitch_deg != 0.0) {  // about y: z towards x
        const double a = pitch_deg * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
        p = glm::dvec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
    }
    return p;
}

Bounds Scene::bounds(RoleMask roles) const {
    Bounds b;
    for (const Mesh& m : meshes) {
        if (!roles.has(m.role)) continue;
        for (const glm::vec3& v : m.vertices) b.extend(glm::dvec3(v));
    }
    return b;
}

std::size_t Scene::triangleCount() const {
    std::size_t n = 0;
    for (const Mesh& m : meshes) n += m.triangles.size();
    return n;
}

bool Scene::hasRole(Role r) const {
    for (const Mesh& m : meshes)
        if (m.role == r) return true;
    return false;
}

}  // namespace core
