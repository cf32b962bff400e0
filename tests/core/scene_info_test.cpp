// tests/core/scene_info_test.cpp: core::summarize, groundHeightAt and targetWarnings on
// scenes of known geometry built in code.
#include <scene_builders.hpp>

#include <core/error.hpp>
#include <core/scene_info.hpp>

#include <doctest/doctest.h>

namespace {

// A ground triangle pair tilted along x: z = 0.1 x over [-50, 50]^2.
core::Mesh tiltedGround() {
    core::Mesh m;
    m.name = "ground";
    m.role = core::Role::Ground;
    m.vertices = {{-50, -50, -5}, {50, -50, 5}, {50, 50, 5}, {-50, 50, -5}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

core::Scene sceneWithTarget(glm::vec3 lo, glm::vec3 hi) {
    core::Scene s;
    s.meshes.push_back(tiltedGround());
    s.meshes.push_back(test_support::boxMesh(lo, hi, core::Role::Target, "box"));
    s.meshes.back().position = {1, 2, 3};
    return s;
}

}  // namespace

TEST_CASE("groundHeightAt: the highest ground triangle on the vertical line, none off the ground") {
    core::Scene s = sceneWithTarget({0, 0, 0}, {1, 1, 1});
    CHECK(*core::groundHeightAt(s, 10.0, 3.0) == doctest::Approx(1.0));
    CHECK(*core::groundHeightAt(s, -20.0, 0.0) == doctest::Approx(-2.0));
    CHECK(*core::groundHeightAt(s, 50.0, 50.0) == doctest::Approx(5.0));  // a shared corner
    CHECK_FALSE(core::groundHeightAt(s, 60.0, 0.0));
    // A second ground layer 2 m higher over part of it: the higher one wins.
    core::Mesh roof = tiltedGround();
    for (auto& v : roof.vertices) v = v * glm::vec3(0.1f, 0.1f, 0.1f) + glm::vec3(0, 0, 2);
    s.meshes.push_back(roof);
    CHECK(*core::groundHeightAt(s, 1.0, 0.0) == doctest::Approx(2.1));
    CHECK(*core::groundHeightAt(s, 10.0, 0.0) == doctest::Approx(1.0));
    // The target's own triangles are never ground.
    CHECK_FALSE(core::groundHeightAt(s, 70.0, 0.0));
}

TEST_CASE("summarize: sizes, triangles, positions and the target's height above the ground") {
    const core::Scene s = sceneWithTarget({9.5f, -1, 2}, {10.5f, 1, 4});
    const core::SceneSummary sum = core::summarize(s);
    REQUIRE(sum.meshes.size() == 2);
    CHECK(sum.triangles == 14);
    CHECK(sum.has_ground);
    CHECK(sum.meshes[0].role == core::Role::Ground);
    CHECK(sum.meshes[0].bounds.size() == glm::dvec3(100, 100, 10));
    CHECK(sum.meshes[1].file == "box");
    CHECK(sum.meshes[1].triangles == 12);
    CHECK(sum.meshes[1].position == glm::dvec3(1, 2, 3));
    REQUIRE(sum.target);
    CHECK(sum.target->bounds.size() == glm::dvec3(1, 2, 2));
    // Ground under the centre (10, 0) at z = 1; the box's bottom at 2: 1 m above.
    CHECK(*sum.target->ground_z == doctest::Approx(1.0));
    CHECK(*sum.target->height_above_ground_m == doctest::Approx(1.0));
    CHECK(core::targetWarnings(sum).empty());  // 1 m is still within the allowed gap
}

TEST_CASE("targetWarnings: too large, floating, sunk, off the ground, none without a target") {
    auto warnings = [](glm::vec3 lo, glm::vec3 hi) {
        return core::targetWarnings(core::summarize(sceneWithTarget(lo, hi)));
    };
    auto only = [](const std::vector<std::string>& w, const std::string& part) {
        CAPTURE(part);
        REQUIRE(w.size() == 1);
        CHECK(w[0].find(part) != std::string::npos);
        CHECK(w[0].find('\n') == std::string::npos);
    };
    only(warnings({-20, -1, 0}, {20, 1, 2}), "the target is 40.00 m x 2.00 m x 2.00 m, larger than 30 m");
    only(warnings({-1, -1, 1.5f}, {1, 1, 2}), "the target floats 1.50 m above the ground");
    only(warnings({-1, -1, -1.5f}, {1, 1, 0}), "the target sinks 1.50 m below the ground");
    only(warnings({99, 0, 0}, {100, 1, 1}), "no ground mesh lies under the target's centre");
    core::Scene no_target;
    no_target.meshes.push_back(tiltedGround());
    const core::SceneSummary sum = core::summarize(no_target);
    CHECK_FALSE(sum.target);
    CHECK(core::targetWarnings(sum).empty());
}

TEST_CASE("shownNumber: compact, and exact for the limits it prints") {
    CHECK(core::shownNumber(1e308) == "1e+308");
    CHECK(core::shownNumber(1048576) == "1048576");
    CHECK(core::shownNumber(0.2) == "0.2");
    CHECK(core::shownNumber(core::kMaxWorldCoordinate_m) == "1000000000");
}
