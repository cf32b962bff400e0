// tests/viewer/tools/candidates_tool_test.cpp: the pointer's ray against candidate boxes, and
// the verdicts the operator gives.
#include "tools/candidates_tool.hpp"

#include <doctest/doctest.h>

using namespace viewer;

TEST_CASE("a ray enters an oriented box where the box's yaw puts its faces") {
    // A 10 x 2 x 2 m box at (100, 0, 0), long side along x.
    const glm::dvec3 centre(100.0, 0.0, 0.0), size(10.0, 2.0, 2.0);
    const LocalRay along_x{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}};
    CHECK(*rayBoxDistance(along_x, centre, size, 0.0) == doctest::Approx(95.0));
    // Turned 90 deg, the long side lies along y: the ray enters at 99 m.
    CHECK(*rayBoxDistance(along_x, centre, size, 90.0) == doctest::Approx(99.0));
    // A ray 3 m to the side misses the unturned box and hits the turned one.
    const LocalRay beside{{0.0, 3.0, 0.0}, {1.0, 0.0, 0.0}};
    CHECK_FALSE(rayBoxDistance(beside, centre, size, 0.0));
    CHECK(rayBoxDistance(beside, centre, size, 90.0));
    // Pointing away: none; starting inside: 0.
    CHECK_FALSE(rayBoxDistance({{0.0, 0.0, 0.0}, {-1.0, 0.0, 0.0}}, centre, size, 0.0));
    CHECK(*rayBoxDistance({centre, {0.0, 0.0, 1.0}}, centre, size, 30.0) == 0.0);
}

TEST_CASE("the candidate pointed at gets the verdict, and the nearest box along the ray is the one pointed at") {
    std::vector<core::Candidate> list(2);
    list[0].id = "far";
    list[0].centre_world = {1000100.0, 0.0, 0.0};
    list[0].size_m = {4.0, 4.0, 4.0};
    list[1].id = "near";
    list[1].centre_world = {1000050.0, 0.0, 0.0};
    list[1].size_m = {4.0, 4.0, 4.0};
    CandidatesTool tool;
    tool.set(list, {1000000.0, 0.0, 0.0});  // the cloud's local frame is 10^6 m east
    tool.update(LocalRay{{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}});
    REQUIRE(tool.pointed());
    CHECK(tool.candidate(*tool.pointed()).id == "near");
    CHECK(tool.decide(Verdict::Rejected) == std::optional<std::size_t>(1));
    CHECK(tool.verdict(1) == Verdict::Rejected);
    CHECK(tool.verdict(0) == Verdict::Unreviewed);
    tool.update(std::nullopt);
    CHECK_FALSE(tool.decide(Verdict::Confirmed));  // nothing pointed at: no verdict
    OverlayList overlay;
    tool.draw(overlay, false);
    CHECK(overlay.lines.size() == 2 * 12 * 2);  // 12 edges per box, 2 vertices per edge
    CHECK(tool.log()[1]["verdict"] == "rejected");
    CHECK(tool.log()[0]["verdict"] == "unreviewed");
}
