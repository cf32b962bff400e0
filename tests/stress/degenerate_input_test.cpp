// tests/stress/degenerate_input_test.cpp: zero-area and NaN triangles are skipped
// and counted; the colour map when every height is equal; RANSAC on fewer than 3 points,
// on collinear points and on walls only.
#include <scene_builders.hpp>
#include <test_files.hpp>

#include <core/error.hpp>
#include <core/jet.hpp>
#include <io/scene_file.hpp>
#include <sim/colour.hpp>
#include <sim/generator.hpp>
#include <sim/ground.hpp>
#include <sim/raycaster.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

namespace fs = std::filesystem;

TEST_CASE("zero-area and NaN triangles are skipped and counted, the rest of the mesh is cast") {
    const test_support::TempDir scratch("stress_degenerate");
    const fs::path& dir = scratch.path;
    // A 10 m ground quad (2 proper triangles), 3 zero-area triangles (a repeated vertex,
    // three collinear vertices, all corners equal) and 2 triangles that use a NaN vertex.
    {
        std::ofstream obj(dir / "degenerate.obj");
        obj << "v -5 -5 0\nv 5 -5 0\nv 5 5 0\nv -5 5 0\n"  // 1-4: the quad
               "v 0 0 0\nv 1 0 0\nv 2 0 0\n"               // 5-7: collinear
               "v nan 0 1\n"                               // 8: NaN
               "f 1 2 3\nf 1 3 4\n"
               "f 5 5 6\nf 5 6 7\nf 6 6 6\n"
               "f 1 2 8\nf 8 3 4\n";
        std::ofstream box(dir / "box.obj");
        box << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
        std::ofstream json(dir / "scene.json");
        json << R"({"meshes": [{"file": "degenerate.obj", "role": "ground"},
                               {"file": "box.obj", "role": "target", "position": [-0.5, -0.5, 0]}]})";
    }
    // Strict (the generator's default): the NaN vertex is an error naming it.
    CHECK_THROWS_WITH_AS(io::loadScene(dir / "scene.json"), doctest::Contains("is not finite"), core::Error);
    io::SceneLoadOptions lenient;
    lenient.skip_nonfinite = true;
    const core::Scene scene = io::loadScene(dir / "scene.json", lenient);
    CHECK(scene.skipped_nonfinite_triangles == 2);
    CHECK(scene.skipped_triangles == 3);
    REQUIRE(scene.meshes.size() == 2);
    CHECK(scene.meshes[0].triangles.size() == 2);
    for (const auto& v : scene.meshes[0].vertices)
        if (std::isfinite(v.x)) CHECK(std::isfinite(v.y));
    // The generator runs on what is left: every ray of a nadir view hits the quad or the box.
    sim::GenerateOptions g;
    g.orbit.altitude_m = 20.0;
    g.orbit.inclination_deg = 1.0;
    g.orbit.overlap_m = 0.0;
    g.orbit.fov_deg = 10.0;
    g.orbit.xres = g.orbit.yres = 16;
    g.orbit.views = 2;
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(scene, g, &st);
    CHECK(st.misses == 0);
    CHECK(cloud.points.size() == 512);
    // The loader's counts reach the generator's stats (`ladarvr generate` warns with them).
    CHECK(st.skipped_zero_area_triangles == 3);
    CHECK(st.skipped_nonfinite_triangles == 2);
}

TEST_CASE("a scene built in code with NaN and zero-area triangles: Embree skips them, no leak") {
    core::Scene scene;
    scene.source = "nan (in code)";
    core::Mesh m = test_support::quadMesh(10.0f, 0.0f, core::Role::Ground, "ground");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    m.vertices.push_back({nan, 0.0f, 1.0f});   // 4
    m.vertices.push_back({0.0f, 0.0f, 2.0f});  // 5
    m.triangles.push_back({0, 1, 4});          // NaN
    m.triangles.push_back({5, 5, 5});          // a point
    m.triangles.push_back({0, 2, 0});          // a segment
    scene.meshes.push_back(m);
    sim::RayCaster caster(scene);
    std::vector<sim::Ray> rays;
    for (int i = -9; i <= 9; ++i)
        for (int j = -9; j <= 9; ++j) {
            sim::Ray r;
            r.origin = {float(i) * 0.5f, float(j) * 0.5f, 5.0f};
            rays.push_back(r);
        }
    std::vector<sim::Hit> hits(rays.size());
    caster.intersect(rays, hits);
    std::size_t on_ground = 0;
    for (const auto& h : hits) on_ground += h.hit() && h.t == doctest::Approx(5.0f) && h.triangle < 2;
    CHECK(on_ground == rays.size());
    // The bounds ignore the NaN vertex (they are used for the default centre and culling).
    const core::Bounds b = caster.bounds();
    CHECK(std::isfinite(b.lo.x));
    CHECK(std::isfinite(b.hi.x));
    CHECK(b.hi.z == doctest::Approx(2.0));
}

TEST_CASE("colour map with every height equal: one colour (the lowest bin's), nothing undefined") {
    for (const int m : {2, 64, 256}) {
        const auto jet = core::jetTable(m);
        REQUIRE(int(jet.size()) == m);
        for (const float z : {0.0f, -1e30f, 1e30f, 1e-40f, 123.456f}) {
            CHECK(sim::heightColour(z, z, z, jet) == jet[std::size_t(m - 1)]);
            // Degenerate range given the wrong way round: still the lowest bin.
            CHECK(sim::heightColour(z, z, z - 1.0f, jet) == jet[std::size_t(m - 1)]);
        }
        // A range of one float ulp: both ends still map to valid bins.
        const float lo = 100.0f, hi = std::nextafter(lo, 200.0f);
        CHECK(sim::heightColour(lo, lo, hi, jet) == jet[std::size_t(m - 1)]);
        CHECK(sim::heightColour(hi, lo, hi, jet) == jet[0]);
    }
    // The generator on a flat plate at z = 7: the hits' heights differ only by float rounding
    // of t (tens of micrometres), and every point is white (ground) or a jet colour.
    core::Scene flat;
    flat.source = "flat (in code)";
    flat.meshes.push_back(test_support::quadMesh(500.0f, 7.0f, core::Role::Target, "plate"));
    sim::GenerateOptions g;
    g.orbit.xres = g.orbit.yres = 32;
    g.orbit.views = 4;
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(flat, g, &st);
    REQUIRE(cloud.points.size() == 32u * 32u * 4u);
    CHECK(st.z_max - st.z_min < 1e-3f);
    MESSAGE("flat plate: z range " << (st.z_max - st.z_min) * 1e6 << " micrometres");
    const auto jet = core::jetTable(64);
    std::size_t invalid = 0;
    for (const auto& p : cloud.points)
        invalid += p.rgb != core::kWhite && std::find(jet.begin(), jet.end(), p.rgb) == jet.end();
    CHECK(invalid == 0);
}

TEST_CASE("RANSAC: fewer than 3 points, collinear points, walls only: no ground, no crash") {
    const sim::RansacOptions o;
    sim::GroundStats st;
    CHECK(sim::findGround({}, o, 1, &st).empty());
    CHECK(st.ground_points == 0);
    for (std::size_t n = 1; n < 3; ++n) {
        const std::vector<glm::vec3> few(n, glm::vec3(1.0f, 2.0f, 0.0f));
        CHECK(sim::findGround(few, o, 1, &st) == std::vector<std::uint8_t>(n, 0));
        CHECK(st.planes_accepted == 0);
    }
    // 500 points on one line (in the band): infinitely many planes contain it, none is a
    // plane of the points' own; PCL's sample check refuses collinear triples.
    std::vector<glm::vec3> line;
    for (int i = 0; i < 500; ++i) line.push_back({0.1f * float(i), 0.05f * float(i), 0.0f});
    const auto on_line = sim::findGround(line, o, 1, &st);
    REQUIRE(on_line.size() == line.size());
    std::size_t found = 0;
    for (auto f : on_line) found += f;
    MESSAGE("collinear: " << found << " of 500 points called ground, " << st.planes_accepted << " planes");
    CHECK(found == 0);
    // Walls only: four vertical walls 10 m tall, 0.2 m point spacing; the 3 m band holds
    // wall bottoms only, every plane there is vertical and is rejected.
    std::vector<glm::vec3> walls;
    for (int side = 0; side < 4; ++side)
        for (int i = 0; i < 100; ++i)
            for (int k = 0; k < 50; ++k) {
                const float s = -10.0f + 0.2f * float(i), z = 0.2f * float(k);
                walls.push_back(side == 0   ? glm::vec3(s, -10.0f, z)
                                : side == 1 ? glm::vec3(s, 10.0f, z)
                                : side == 2 ? glm::vec3(-10.0f, s, z)
                                            : glm::vec3(10.0f, s, z));
            }
    const auto on_walls = sim::findGround(walls, o, 7, &st);
    found = 0;
    for (auto f : on_walls) found += f;
    CHECK(found == 0);
    CHECK(st.ground_points == 0);
    CHECK(st.planes_accepted == 0);
    CHECK(st.planes_rejected >= 4);
    // z = 0, 0.2, ..., 2.8 (3.0 in float may fall either side of the band edge).
    CHECK(st.band_points >= 4u * 100u * 15u);
    CHECK(st.band_points <= 4u * 100u * 16u);
}
