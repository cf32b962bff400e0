// tests/common/mesh_builders.hpp: meshes with known geometry, built in code, shared by
// every test suite (engine::Mesh only, so any module's tests may use them).
#pragma once
#include <engine/scene.hpp>

#include <string>
#include <utility>

namespace test_support {

/// A closed axis-aligned box [lo, hi] (12 triangles, outward winding).
inline engine::Mesh boxMesh(glm::vec3 lo, glm::vec3 hi, engine::Role role, std::string name) {
    engine::Mesh m;
    m.name = std::move(name);
    m.role = role;
    for (int k = 0; k < 8; ++k)
        m.vertices.emplace_back(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    const unsigned f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& t : f) m.triangles.emplace_back(t[0], t[1], t[2]);
    return m;
}

}  // namespace test_support
