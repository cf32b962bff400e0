// Scene loading: transforms, roles and the errors of bad scene files.
#include <engine/error.hpp>
#include <engine/scene.hpp>

#include <doctest/doctest.h>

#include <filesystem>

namespace fs = std::filesystem;
using engine::Role;

namespace {
const fs::path kData = fs::path(LADARVR_TEST_DATA_DIR) / "scenes";
}

TEST_CASE("scene: the basic scene loads with its transforms applied") {
    const engine::Scene s = engine::loadScene(kData / "basic" / "scene.json");
    REQUIRE(s.meshes.size() == 3);
    // No origin key: the first mesh's position (0, 0, 0).
    CHECK(s.origin == glm::dvec3(0.0));
    CHECK(s.meshes[0].role == Role::Ground);
    CHECK(s.meshes[0].triangles.size() == 2);   // the degenerate third face is dropped
    CHECK(s.skipped_triangles == 1);
    CHECK(s.meshes[1].triangles.size() == 12);
    // Target: unit cube scaled 2, yawed 90 deg, at (2, 3, 0): x in [0, 2], y in [3, 5].
    const engine::Bounds t = s.bounds(engine::RoleMask::of({Role::Target}));
    CHECK(t.lo.x == doctest::Approx(0.0));
    CHECK(t.hi.x == doctest::Approx(2.0));
    CHECK(t.lo.y == doctest::Approx(3.0));
    CHECK(t.hi.y == doctest::Approx(5.0));
    CHECK(t.hi.z == doctest::Approx(2.0));
    CHECK(s.hasRole(Role::Environment));
    CHECK(s.triangleCount() == 26);
}
