// tests/sim/raycaster_test.cpp: Embree first-hit casting, watertight shared edges.
#include <scene_builders.hpp>

#include <sim/raycaster.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <vector>

TEST_CASE("first hit: distance, mesh index, role, and misses report mesh -1") {
    core::Scene s;
    s.meshes.push_back(test_support::gridMesh(0, 0, 0, 4, 10.0));
    s.meshes.push_back(test_support::boxMesh({-1, -1, 0}, {1, 1, 3}, core::Role::Target, "box"));
    const sim::RayCaster caster(s);
    CHECK(caster.triangleCount() == 32 + 12);
    std::vector<sim::Ray> rays(3);
    rays[0].origin = {0, 0, 10};    // onto the box top (z = 3)
    rays[1].origin = {10, 10, 10};  // onto the ground
    rays[2].origin = {100, 0, 10};  // past the grid: miss
    rays[2].direction = {0, 0, -2};
    std::vector<sim::Hit> hits(3);
    caster.intersect(rays, hits);
    CHECK(hits[0].mesh == 1);
    CHECK(hits[0].role == core::Role::Target);
    CHECK(hits[0].t == doctest::Approx(7.0));
    CHECK(hits[1].mesh == 0);
    CHECK(hits[1].role == core::Role::Ground);
    CHECK(hits[1].t == doctest::Approx(10.0));
    CHECK_FALSE(hits[2].hit());

    // Without the box's role, the same ray goes through to the ground.
    const sim::RayCaster ground_only(s, core::RoleMask::of({core::Role::Ground}));
    ground_only.intersect(std::span(rays).first(1), std::span(hits).first(1));
    CHECK(hits[0].mesh == 0);
    CHECK(hits[0].t == doctest::Approx(10.0));
    const core::Bounds b = ground_only.bounds();
    CHECK(b.hi.z == doctest::Approx(0.0));
}

TEST_CASE("no ray leaks through the shared edges and vertices of a finely tessellated ground") {
    core::Scene s;
    const int cells = 64;
    const double cell_m = 0.5;
    s.meshes.push_back(test_support::gridMesh(0, 0, 0, cells, cell_m));
    const sim::RayCaster caster(s);
    std::vector<sim::Ray> rays;
    const double half = 0.5 * cells * cell_m;
    // Every vertex, every edge midpoint (horizontal, vertical, diagonal) of the inner grid,
    // from straight above and along three slanted directions.
    const glm::vec3 directions[4] = {{0, 0, -1}, {0.3f, 0.2f, -1}, {-0.7f, 0.7f, -0.2f}, {1, 0, -1}};
    for (int j = 1; j < cells - 1; ++j)
        for (int i = 1; i < cells - 1; ++i)
            for (const glm::vec2 offset : {glm::vec2(0, 0), glm::vec2(0.5f, 0), glm::vec2(0, 0.5f),
                                           glm::vec2(0.5f, 0.5f), glm::vec2(0.25f, 0.25f)}) {
                const glm::vec3 target(float(-half + (i + offset.x) * cell_m), float(-half + (j + offset.y) * cell_m),
                                       0.0f);
                for (const glm::vec3& d : directions) {
                    sim::Ray r;
                    r.direction = d;
                    r.origin = target - d * (7.0f / -d.z);  // 7 m above the ground
                    rays.push_back(r);
                }
            }
    std::vector<sim::Hit> hits(rays.size());
    caster.intersect(rays, hits);
    std::size_t misses = 0;
    for (std::size_t k = 0; k < hits.size(); ++k) {
        misses += !hits[k].hit();
        if (hits[k].hit()) CHECK(hits[k].t == doctest::Approx(7.0 / -rays[k].direction.z).epsilon(1e-4));
    }
    CHECK(rays.size() == 62 * 62 * 5 * 4);
    CHECK(misses == 0);
}

TEST_CASE("embree errors become core::Error naming the mesh") {
    core::Scene s;
    core::Mesh m = test_support::gridMesh(0, 0, 0, 1, 1.0);
    m.name = "broken.obj";
    m.triangles.push_back({0, 1, 99});
    s.meshes.push_back(m);
    CHECK_THROWS_WITH_AS(sim::RayCaster{s}, doctest::Contains("broken.obj"), core::Error);
}

TEST_CASE("intersect16 gives the hits of intersect, with a partial last packet") {
    core::Scene s;
    s.meshes.push_back(test_support::gridMesh(0, 0, 0, 8, 2.0));
    s.meshes.push_back(test_support::boxMesh({-1, -1, 0}, {1, 1, 3}, core::Role::Target, "box"));
    const sim::RayCaster caster(s);
    std::vector<sim::Ray> rays;
    for (int k = 0; k < 37; ++k) {  // two full packets and 5 rays; some on the box, some miss
        sim::Ray r;
        // Off the grid's edges and vertices, where the two may pick either adjacent triangle.
        r.origin = {float(k) - 17.63f, 0.3f * float(k % 5) + 0.11f, 10.0f};
        r.direction = {0.05f * float(k % 3), 0.0f, -1.0f};
        if (k == 7) r.t_far = 2.0f;     // stops before the ground: a miss
        if (k == 20) r.t_far = 10.01f;  // reaches the ground (t = 10) with 1 cm to spare
        rays.push_back(r);
    }
    std::vector<sim::Hit> one(rays.size()), packets(rays.size(), sim::Hit{99.0f, 5, 5});
    caster.intersect(rays, one);
    caster.intersect16(rays, packets);
    std::size_t hits = 0, box = 0;
    for (std::size_t k = 0; k < rays.size(); ++k) {
        CHECK(packets[k].mesh == one[k].mesh);
        CHECK(packets[k].triangle == one[k].triangle);
        CHECK(packets[k].role == one[k].role);
        CHECK(packets[k].t == doctest::Approx(one[k].t));
        hits += one[k].hit();
        box += one[k].mesh == 1;
    }
    CHECK(one[20].hit());
    CHECK(one[20].t == doctest::Approx(10.0f));
    CHECK(hits > 10);
    CHECK(hits < rays.size());
    CHECK(box > 0);
}
