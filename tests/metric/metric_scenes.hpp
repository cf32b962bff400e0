// tests/metric/metric_scenes.hpp: scenes with closed-form visibility, built in code.
#pragma once
#include <engine/scene.hpp>
#include <mesh_builders.hpp>

#include <string>

namespace metric_test {

/// The box-behind-wall scene: a cube target of half-size a centred on (0, 0, 0) inside a
/// square enclosure of four thin walls at distance D (|x| = D or |y| = D) whose tops are at
/// z = wall_top and bottoms at z = -a - 1. A camera at (R, 0, 0) looking at the cube's
/// centre (orbit altitude 0, any of the 4 axis-aligned views) sees only the cube's front face
/// (on axis), and the front wall hides the face where z < wall_top (R - a) / (R - D); so
///   visible fraction = (a - wall_top (R - a) / (R - D)) / (2 a).
/// With `roof`, a lid closes the enclosure: the target is fully hidden from everywhere.
/// The origin is far from zero to exercise the local frame.
inline engine::Scene boxBehindWall(float a, float distance_d, float wall_top, bool roof = false) {
    engine::Scene s;
    s.source = "box-behind-wall (in code)";
    s.origin = glm::dvec3(651000.0, 6862000.0, 85.0);
    s.meshes.push_back(test_support::boxMesh({-a, -a, -a}, {a, a, a}, engine::Role::Target, "cube"));
    const float t = 0.1f, d = distance_d, bottom = -a - 1.0f;
    const float top = wall_top;
    s.meshes.push_back(test_support::boxMesh({d, -d, bottom}, {d + t, d, top}, engine::Role::Environment, "wall+x"));
    s.meshes.push_back(test_support::boxMesh({-d - t, -d, bottom}, {-d, d, top}, engine::Role::Environment, "wall-x"));
    s.meshes.push_back(test_support::boxMesh({-d, d, bottom}, {d, d + t, top}, engine::Role::Environment, "wall+y"));
    s.meshes.push_back(test_support::boxMesh({-d, -d - t, bottom}, {d, -d, top}, engine::Role::Environment, "wall-y"));
    if (roof) s.meshes.push_back(test_support::boxMesh({-d - t, -d - t, top}, {d + t, d + t, top + t}, engine::Role::Environment, "roof"));
    return s;
}

inline double closedFormVisible(double a, double distance_d, double wall_top, double radius_r) {
    return (a - wall_top * (radius_r - a) / (radius_r - distance_d)) / (2.0 * a);
}

}  // namespace metric_test
