// tests/common/scene_builders.hpp: meshes and scenes with known geometry, built in code,
// shared by every test suite (core types and the scene loader only, so any module's tests may use them).
#pragma once
#include <test_paths.hpp>
#include <io/scene_file.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

namespace test_support {

// --- meshes ------------------------------------------------------------------

/// A closed axis-aligned box [lo, hi] (12 triangles, outward winding).
inline core::Mesh boxMesh(glm::vec3 lo, glm::vec3 hi, core::Role role, std::string name) {
    core::Mesh m;
    m.name = std::move(name);
    m.role = role;
    for (int k = 0; k < 8; ++k) m.vertices.emplace_back(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    const unsigned f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& t : f) m.triangles.emplace_back(t[0], t[1], t[2]);
    return m;
}

/// A flat square grid at height z, centred on (cx, cy), `cells` x `cells` squares of
/// `cell_m`, two triangles each (alternating diagonals), all vertices shared.
inline core::Mesh gridMesh(double cx, double cy, double z, int cells, double cell_m,
                           core::Role role = core::Role::Ground, std::string name = "grid") {
    core::Mesh m;
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

/// gridMesh's grid with each vertex lifted by `height_m(x, y)` (local metres): terrain.
template <class HeightFn>
inline core::Mesh terrainMesh(int cells, double cell_m, HeightFn height_m, std::string name = "terrain") {
    core::Mesh m = gridMesh(0.0, 0.0, 0.0, cells, cell_m, core::Role::Ground, std::move(name));
    for (glm::vec3& v : m.vertices) v.z = float(height_m(double(v.x), double(v.y)));
    return m;
}

/// A flat square [-half, half]^2 at height z made of two triangles (a one-cell grid).
inline core::Mesh quadMesh(float half, float z, core::Role role, std::string name) {
    return gridMesh(0.0, 0.0, z, 1, 2.0 * half, role, std::move(name));
}

/// Four environment walls of thickness `t` on the square |x| = d, |y| = d (their inner
/// faces), from z = `bottom` to z = `top`; with `roof`, a lid of the same thickness on top
/// closes the enclosure, so nothing inside is visible from outside.
inline void addEnclosure(core::Scene& s, float d, float t, float bottom, float top, bool roof) {
    const core::Role env = core::Role::Environment;
    s.meshes.push_back(boxMesh({d, -d, bottom}, {d + t, d, top}, env, "wall+x"));
    s.meshes.push_back(boxMesh({-d - t, -d, bottom}, {-d, d, top}, env, "wall-x"));
    s.meshes.push_back(boxMesh({-d, d, bottom}, {d, d + t, top}, env, "wall+y"));
    s.meshes.push_back(boxMesh({-d, -d - t, bottom}, {d, -d, top}, env, "wall-y"));
    if (roof) s.meshes.push_back(boxMesh({-d - t, -d - t, top}, {d + t, d + t, top + t}, env, "roof"));
}

// --- scenes ------------------------------------------------------------------

/// Ground grid (0.5 m cells over `size_m`), a 7 x 3.5 x 2.4 m target at (0, 0) and a
/// ring of box buildings around it; origin far from zero to exercise the local frame.
inline core::Scene townScene(double size_m = 160.0, double cell_m = 0.5) {
    core::Scene s;
    s.source = "town (in code)";
    s.origin = glm::dvec3(500000.0, 4000000.0, 120.0);
    s.meshes.push_back(gridMesh(0.0, 0.0, 0.0, int(size_m / cell_m), cell_m));
    s.meshes.push_back(boxMesh({-3.5f, -1.75f, 0.0f}, {3.5f, 1.75f, 2.4f}, core::Role::Target, "tank"));
    for (int k = 0; k < 8; ++k) {
        const float a = float(k) * 0.785398f;
        const float x = 25.0f * std::cos(a), y = 25.0f * std::sin(a);
        s.meshes.push_back(boxMesh({x - 5.0f, y - 4.0f, 0.0f}, {x + 5.0f, y + 4.0f, 6.0f + float(k)},
                                   core::Role::Environment, "house" + std::to_string(k)));
    }
    return s;
}

/// Rolling terrain (about 10 m of relief over 160 m, no plane holds a view's 3 m band)
/// with townScene's target and houses on it: RANSAC's planes, hence the whitening, depend
/// on its seed here, unlike on a flat ground.
inline core::Scene hillyTownScene() {
    core::Scene s = townScene(160.0, 1.0);
    s.source = "hilly town (in code)";
    s.meshes[0] = terrainMesh(160, 1.0, [](double x, double y) {
        return 3.0 * std::sin(x / 13.0) * std::cos(y / 9.0) + 2.0 * std::sin((x + 2.0 * y) / 23.0);
    });
    return s;
}

/// Thickness of boxBehindWall's walls, metres.
inline constexpr float kWallThickness_m = 0.1f;

/// The box-behind-wall scene: a cube target of half-size a centred on (0, 0, 0) inside a
/// square enclosure of four thin walls at distance D (|x| = D or |y| = D) whose tops are at
/// z = wall_top and bottoms at z = -a - 1, kWallThickness_m thick outwards (|x| in [D, D + t]).
/// A camera at (R, 0, 0) looking at the cube's centre (orbit altitude 0, any of the 4
/// axis-aligned views) sees only the cube's front face (on axis), and the front wall's outer
/// top edge (x = D + t, z = wall_top) hides the face where z < wall_top (R - a) / (R - D - t); so
///   visible fraction = (a - wall_top (R - a) / (R - D - t)) / (2 a)   (closedFormVisible).
/// With `roof`, a lid closes the enclosure: the target is fully hidden from everywhere.
/// The origin is far from zero to exercise the local frame.
inline core::Scene boxBehindWall(float a, float distance_d, float wall_top, bool roof = false) {
    core::Scene s;
    s.source = "box-behind-wall (in code)";
    s.origin = glm::dvec3(651000.0, 6862000.0, 85.0);
    s.meshes.push_back(boxMesh({-a, -a, -a}, {a, a, a}, core::Role::Target, "cube"));
    addEnclosure(s, distance_d, kWallThickness_m, -a - 1.0f, wall_top, roof);
    return s;
}

inline double closedFormVisible(double a, double distance_d, double wall_top, double radius_r) {
    const double outer_d = distance_d + double(kWallThickness_m);
    return (a - wall_top * (radius_r - a) / (radius_r - outer_d)) / (2.0 * a);
}

/// tests/data/scenes/basic, where basicScene's mesh files live.
inline std::filesystem::path basicDir() { return std::filesystem::path(test_support::dataDir()) / "scenes" / "basic"; }

/// tests/data/scenes/basic's meshes (a 20 m ground scaled to 200 m, unit boxes scaled 2x
/// and 3x) placed around world point `offset`, with the local origin at `origin`, as scene
/// JSON: the same geometry at any distance from the world origin.
inline std::string basicSceneJson(glm::dvec3 offset, glm::dvec3 origin) {
    const auto num = [](double v) {
        char b[64];
        std::snprintf(b, sizeof b, "%.17g", v);
        return std::string(b);
    };
    const auto at = [&](double x, double y, double z) {
        return "[" + num(offset.x + x) + ", " + num(offset.y + y) + ", " + num(offset.z + z) + "]";
    };
    return "{\"origin\": [" + num(origin.x) + ", " + num(origin.y) + ", " + num(origin.z) +
           "],\n \"meshes\": [\n"
           "  {\"file\": \"ground.obj\", \"role\": \"ground\", \"position\": " +
           at(0, 0, 0) +
           ", \"scale\": 10},\n"
           "  {\"file\": \"box.obj\", \"role\": \"target\", \"position\": " +
           at(-1, -1, 0) +
           ", \"scale\": 2},\n"
           "  {\"file\": \"box.obj\", \"role\": \"environment\", \"position\": " +
           at(2.5, -1.5, 0) +
           ", \"scale\": 3, \"yaw_deg\": 30},\n"
           "  {\"file\": \"box.obj\", \"role\": \"environment\", \"position\": " +
           at(-12, 6, 0) + ", \"scale\": 5}\n ]}\n";
}

/// Loads basicSceneJson through io::loadSceneJson (mesh paths resolve in basicDir()).
inline core::Scene basicScene(glm::dvec3 offset, glm::dvec3 origin) {
    return io::loadSceneJson(basicSceneJson(offset, origin), basicDir() / "stress_generated.json");
}

}  // namespace test_support
