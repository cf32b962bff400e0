// tests/stress/stress_scenes.hpp: scenes and helpers shared by the stress tests.
#pragma once
#include <engine/scene.hpp>
#include <mesh_builders.hpp>
#include <sim/generator.hpp>

#include <cstdio>
#include <filesystem>
#include <string>

namespace stress {

inline std::filesystem::path basicDir() {
    return std::filesystem::path(LADARVR_TEST_DATA_DIR) / "scenes" / "basic";
}

inline std::string num(double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

/// tests/data/scenes/basic's meshes (a 20 m ground scaled to 200 m, unit boxes scaled 2x
/// and 3x) placed around world point `offset`, with the local origin at `origin`:
/// the same geometry at any distance from the world origin.
inline std::string basicSceneJson(glm::dvec3 offset, glm::dvec3 origin) {
    const auto at = [&](double x, double y, double z) {
        return "[" + num(offset.x + x) + ", " + num(offset.y + y) + ", " + num(offset.z + z) + "]";
    };
    return "{\"origin\": [" + num(origin.x) + ", " + num(origin.y) + ", " + num(origin.z) +
           "],\n \"meshes\": [\n"
           "  {\"file\": \"ground.obj\", \"role\": \"ground\", \"position\": " + at(0, 0, 0) + ", \"scale\": 10},\n"
           "  {\"file\": \"box.obj\", \"role\": \"target\", \"position\": " + at(-1, -1, 0) + ", \"scale\": 2},\n"
           "  {\"file\": \"box.obj\", \"role\": \"environment\", \"position\": " + at(2.5, -1.5, 0) +
           ", \"scale\": 3, \"yaw_deg\": 30},\n"
           "  {\"file\": \"box.obj\", \"role\": \"environment\", \"position\": " + at(-12, 6, 0) +
           ", \"scale\": 5}\n ]}\n";
}

/// Loads basicSceneJson through engine::loadSceneJson (mesh paths resolve in basicDir()).
inline engine::Scene basicScene(glm::dvec3 offset, glm::dvec3 origin) {
    return engine::loadSceneJson(basicSceneJson(offset, origin), basicDir() / "stress_generated.json");
}

/// A small orbit over the 200 m basic ground: 48 x 48 px, 12 views, 40 m up.
inline sim::GenerateOptions smallOrbit() {
    sim::GenerateOptions o;
    o.orbit.altitude_m = 40.0;
    o.orbit.overlap_m = 2.0;
    o.orbit.fov_deg = 20.0;
    o.orbit.xres = 48;
    o.orbit.yres = 48;
    o.orbit.views = 12;
    return o;
}

using test_support::boxMesh;

/// A flat square [-half, half]^2 at height z made of two triangles.
inline engine::Mesh quadMesh(float half, float z, engine::Role role, std::string name) {
    engine::Mesh m;
    m.name = std::move(name);
    m.role = role;
    m.vertices = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

}  // namespace stress
