// scene: what a loaded scene holds, measured over its meshes.
#include <core/scene.hpp>

namespace core {

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
