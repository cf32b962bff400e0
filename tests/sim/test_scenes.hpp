// tests/sim/test_scenes.hpp: small scenes built in code, with known geometry.
#pragma once
#include <engine/scene.hpp>
#include <mesh_builders.hpp>

#include <cmath>
#include <string>

namespace sim_test {

/// A flat square grid at height z, centred on (cx, cy), `cells` x `cells` squares of
/// `cell_m`, two triangles each (alternating diagonals), all vertices shared.
inline engine::Mesh gridMesh(double cx, double cy, double z, int cells, double cell_m,
                             engine::Role role = engine::Role::Ground, std::string name = "grid") {
    engine::Mesh m;
    m.name = std::move(name);
    m.role = role;
    const double half = 0.5 * cells * cell_m;
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i)
            m.vertices.emplace_back(float(cx - half + i * cell_m), float(cy - half + j * cell_m), float(z));
    const auto idx = [&](int i, int j) { return unsigned(j * (cells + 1) + i); };
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const unsigned a = idx(i, j), b = idx(i + 1, j), c = idx(i + 1, j + 1), d = idx(i, j + 1);
            if ((i + j) % 2 == 0) {
                m.triangles.emplace_back(a, b, c);
                m.triangles.emplace_back(a, c, d);
            } else {
                m.triangles.emplace_back(a, b, d);
                m.triangles.emplace_back(b, c, d);
            }
        }
    return m;
}

using test_support::boxMesh;

/// Ground grid (0.5 m cells over `size_m`), a 7 x 3.5 x 2.4 m target at (0, 0) and a
/// ring of box buildings around it; origin far from zero to exercise the local frame.
inline engine::Scene townScene(double size_m = 160.0, double cell_m = 0.5) {
    engine::Scene s;
    s.source = "town (in code)";
    s.origin = glm::dvec3(500000.0, 4000000.0, 120.0);
    s.meshes.push_back(gridMesh(0.0, 0.0, 0.0, int(size_m / cell_m), cell_m));
    s.meshes.push_back(boxMesh({-3.5f, -1.75f, 0.0f}, {3.5f, 1.75f, 2.4f}, engine::Role::Target, "tank"));
    for (int k = 0; k < 8; ++k) {
        const float a = float(k) * 0.785398f;
        const float x = 25.0f * std::cos(a), y = 25.0f * std::sin(a);
        s.meshes.push_back(boxMesh({x - 5.0f, y - 4.0f, 0.0f}, {x + 5.0f, y + 4.0f, 6.0f + float(k)},
                                   engine::Role::Environment, "house" + std::to_string(k)));
    }
    return s;
}

}  // namespace sim_test
