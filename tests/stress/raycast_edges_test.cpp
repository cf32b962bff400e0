// tests/stress/raycast_edges_test.cpp: "rays that graze long thin triangles, and
// rays that hit exactly on shared vertices and edges of the ground, never pass through".
// sim::RayCaster builds its BVH with RTC_SCENE_FLAG_ROBUST (watertight traversal); these
// tests pin that: zero leaks, and the hit distance is the plane's.
#include <scene_builders.hpp>

#include <sim/raycaster.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

/// A ground of `strips` long thin slivers: strips of `width_m` across y, each `length_m`
/// long in x, cut into two triangles by a diagonal (aspect ratio length / width), all
/// vertices shared between neighbouring strips.
core::Mesh sliverGround(int strips, float width_m, float length_m) {
    core::Mesh m;
    m.name = "slivers";
    m.role = core::Role::Ground;
    const float y0 = -0.5f * float(strips) * width_m;
    for (int j = 0; j <= strips; ++j) {
        m.vertices.emplace_back(-0.5f * length_m, y0 + float(j) * width_m, 0.0f);
        m.vertices.emplace_back(0.5f * length_m, y0 + float(j) * width_m, 0.0f);
    }
    for (int j = 0; j < strips; ++j) {
        const unsigned a = unsigned(2 * j), b = a + 1, c = a + 3, d = a + 2;
        m.triangles.emplace_back(a, b, c);
        m.triangles.emplace_back(a, c, d);
    }
    return m;
}

/// A fan of `n` triangles around the centre vertex: all share one vertex and pairwise share
/// an edge; rays aimed at the centre, at the spokes and at the rim vertices.
core::Mesh fanGround(int n, float radius_m) {
    core::Mesh m;
    m.name = "fan";
    m.role = core::Role::Ground;
    m.vertices.emplace_back(0.0f, 0.0f, 0.0f);
    for (int k = 0; k < n; ++k) {
        const double a = 2.0 * 3.14159265358979323846 * k / n;
        m.vertices.emplace_back(float(radius_m * std::cos(a)), float(radius_m * std::sin(a)), 0.0f);
    }
    for (int k = 0; k < n; ++k) m.triangles.emplace_back(0u, unsigned(1 + k), unsigned(1 + (k + 1) % n));
    return m;
}

struct Traced {
    std::size_t rays = 0, misses = 0, wrong_t = 0;
    double worst_rel_t = 0.0;
};

/// Traces each ray and checks a hit at the plane z = 0: t = -origin.z / direction.z.
Traced traceToPlane(const core::Scene& scene, const std::vector<sim::Ray>& rays) {
    sim::RayCaster caster(scene);
    std::vector<sim::Hit> hits(rays.size());
    caster.intersect(rays, hits);
    Traced r;
    r.rays = rays.size();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!hits[i].hit()) {
            ++r.misses;
            continue;
        }
        const double expected = -double(rays[i].origin.z) / double(rays[i].direction.z);
        const double rel = std::abs(double(hits[i].t) - expected) / expected;
        r.worst_rel_t = std::max(r.worst_rel_t, rel);
        r.wrong_t += rel > 1e-3;
    }
    return r;
}

}  // namespace

TEST_CASE("grazing rays over 2 km x 1 cm slivers (aspect 200,000): no leak, right distance") {
    core::Scene scene;
    scene.source = "slivers (in code)";
    scene.meshes.push_back(sliverGround(400, 0.01f, 2000.0f));  // 4 m wide, 2 km long
    std::vector<sim::Ray> rays;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f), along(-400.0f, 400.0f);
    // (1) Rays nearly parallel to the slivers, 0.1 to 5 degrees above grazing, landing at
    // random points; (2) rays across the slivers at the same angles; (3) rays landing
    // exactly on the shared long edges (y = k * 1 cm), straight down and slanted.
    for (const double elevation_deg : {0.1, 0.5, 1.0, 5.0}) {
        const double e = elevation_deg * 3.14159265358979323846 / 180.0;
        for (int i = 0; i < 2000; ++i) {
            const glm::vec3 target(along(rng), u(rng), 0.0f);
            for (const glm::dvec3 horizontal : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0.6, 0.8, 0)}) {
                const glm::dvec3 dir = glm::normalize(horizontal * std::cos(e) - glm::dvec3(0, 0, std::sin(e)));
                // Along the slivers: 2 m above the ground; across: a 1 m horizontal run.
                const double run_m = horizontal.x == 1.0 ? 2.0 / std::tan(e) : 1.0;
                const double back = run_m / std::cos(e);
                sim::Ray r;
                r.origin = glm::vec3(glm::dvec3(target) - back * dir);
                r.direction = glm::vec3(dir);
                // Only rays whose whole path to the ground stays over the slivers.
                if (std::abs(r.origin.y) < 1.9f && std::abs(r.origin.x) < 990.0f) rays.push_back(r);
            }
        }
    }
    for (int k = -150; k <= 150; ++k) {
        const float y = float(k) * 0.01f;
        for (const glm::vec3 dir : {glm::vec3(0, 0, -1), glm::vec3(0.3f, 0, -1), glm::vec3(0, 0.001f, -1)}) {
            sim::Ray r;
            r.origin = glm::vec3(float(k) * 3.0f - 10.0f * dir.x / -dir.z, y - 10.0f * dir.y / -dir.z, 10.0f);
            r.direction = dir;
            rays.push_back(r);
        }
    }
    REQUIRE(rays.size() > 10000);
    const Traced t = traceToPlane(scene, rays);
    MESSAGE(t.rays << " rays over slivers: " << t.misses << " misses, worst relative t error " << t.worst_rel_t);
    CHECK(t.misses == 0);
    CHECK(t.wrong_t == 0);
}

TEST_CASE("rays exactly on the shared centre vertex, spokes and rim of a 64-triangle fan: no leak") {
    core::Scene scene;
    scene.source = "fan (in code)";
    scene.meshes.push_back(fanGround(64, 10.0f));
    // A second ring outside the fan so rim rays have a neighbour on both sides.
    core::Mesh outer = test_support::quadMesh(30.0f, -1.0f, core::Role::Environment, "below");
    scene.meshes.push_back(outer);
    const core::Mesh& fan = scene.meshes[0];
    std::vector<sim::Ray> rays;
    for (std::size_t v = 0; v < fan.vertices.size(); ++v) {
        const glm::vec3 p = fan.vertices[v];
        for (int k = 0; k < 8; ++k) {
            // Aimed at the vertex from 8 directions (straight down and 7 slanted), and at the
            // midpoints of the spokes (shared edges).
            const float a = 0.785398f * float(k);
            const glm::vec3 dir =
                k == 0 ? glm::vec3(0, 0, -1) : glm::vec3(0.5f * std::cos(a), 0.5f * std::sin(a), -1.0f);
            sim::Ray r;
            r.direction = dir;
            const glm::vec3 aim = v == 0 || k % 2 ? p : 0.5f * p;  // vertex, or spoke midpoint
            r.origin = aim - 5.0f * dir;
            if (v != 0 && glm::length(glm::vec2(aim)) > 9.99f) continue;  // rim: may fall off the fan
            rays.push_back(r);
        }
    }
    REQUIRE(rays.size() > 200);
    sim::RayCaster caster(scene);
    std::vector<sim::Hit> hits(rays.size());
    caster.intersect(rays, hits);
    std::size_t leaks = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        // Every ray must stop on the fan (mesh 0) at t = 5 (|dir.z| = 1, origin 5 above).
        leaks += hits[i].mesh != 0;
        if (hits[i].mesh == 0) CHECK(hits[i].t == doctest::Approx(5.0f).epsilon(1e-5));
    }
    CHECK(leaks == 0);
}

TEST_CASE("a wall of 1 cm x 20 m vertical slivers stops rays that skim it at 0.05 degrees") {
    // 1000 slivers 1 cm wide (x) and 20 m tall (aspect 2000) side by side form a 10 m wall
    // in the plane y = 0; rays start 5 mm in front of it and run ~5.7 m along it, crossing
    // hundreds of shared vertical edges before they meet it.
    core::Mesh wall;
    wall.name = "wall";
    wall.role = core::Role::Environment;
    for (int i = 0; i <= 1000; ++i) {
        wall.vertices.emplace_back(float(i) * 0.01f, 0.0f, 0.0f);
        wall.vertices.emplace_back(float(i) * 0.01f, 0.0f, 20.0f);
    }
    for (int i = 0; i < 1000; ++i) {
        const unsigned a = unsigned(2 * i);
        wall.triangles.emplace_back(a, a + 2, a + 3);
        wall.triangles.emplace_back(a, a + 3, a + 1);
    }
    core::Scene scene;
    scene.source = "wall (in code)";
    scene.meshes.push_back(wall);
    std::vector<sim::Ray> rays;
    const double e = 0.05 * 3.14159265358979323846 / 180.0;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(0.5, 3.5), uz(1.0, 19.0);
    for (int i = 0; i < 5000; ++i) {
        sim::Ray r;
        r.origin = glm::vec3(float(ux(rng)), 0.005f, float(uz(rng)));
        const double tilt = i % 2 ? 0.0 : 0.02;  // half also climb slowly
        r.direction = glm::vec3(glm::normalize(glm::dvec3(std::cos(e), -std::sin(e), tilt)));
        rays.push_back(r);
    }
    sim::RayCaster caster(scene);
    std::vector<sim::Hit> hits(rays.size());
    caster.intersect(rays, hits);
    std::size_t leaks = 0, wrong_t = 0;
    double worst = 0.0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!hits[i].hit()) {
            ++leaks;
            continue;
        }
        const double expected = double(rays[i].origin.y) / -double(rays[i].direction.y);
        const double rel = std::abs(double(hits[i].t) - expected) / expected;
        worst = std::max(worst, rel);
        wrong_t += rel > 1e-3;
    }
    MESSAGE("skimming rays: " << leaks << " leaks, worst relative t error " << worst);
    CHECK(leaks == 0);
    CHECK(wrong_t == 0);
}
