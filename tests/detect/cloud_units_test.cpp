// tests/detect/cloud_units_test.cpp: a survey in feet detected in metres
// (detect/cloud_units.hpp): its points scaled about its origin, the centres put back, the
// sizes of a candidates file turned into the cloud's units, and a file of other units
// refused in one line.
#include <core/error.hpp>
#include <detect/cloud_units.hpp>

#include <doctest/doctest.h>

namespace {

constexpr double kFoot_m = 1200.0 / 3937.0;

sim::CoordinateUnits usFeet() {
    sim::CoordinateUnits u;
    u.horizontal_m = u.vertical_m = kFoot_m;
    u.horizontal_name = u.vertical_name = "US survey foot";
    return u;
}

core::Candidate candidate(glm::dvec3 centre, glm::dvec3 size_m) {
    core::Candidate c;
    c.id = "c1";
    c.centre_world = centre;
    c.size_m = size_m;
    c.yaw_deg = 30.0;
    c.score = 0.5;
    return c;
}

}  // namespace

TEST_CASE("cloud_units: the local coordinates scaled, the origin kept, metres untouched") {
    core::PointCloud c;
    c.origin = {1639600.0, 1454500.0, 7000.0};
    core::CloudPoint p;
    p.position = {10.0f, -20.0f, 5.0f};
    c.points.push_back(p);
    core::PointCloud m = c;
    detect::scaleToMetres(m, sim::CoordinateUnits{});
    CHECK(m.points[0].position == c.points[0].position);
    sim::CoordinateUnits mixed;
    mixed.vertical_m = kFoot_m;  // metres across, feet up
    detect::scaleToMetres(m, mixed);
    CHECK(m.origin == c.origin);
    CHECK(m.points[0].position.x == 10.0f);
    CHECK(m.points[0].position.z == doctest::Approx(5.0 * kFoot_m));
    detect::scaleToMetres(c, usFeet());
    CHECK(c.points[0].position.x == doctest::Approx(10.0 * kFoot_m));
    CHECK(c.points[0].position.y == doctest::Approx(-20.0 * kFoot_m));
    CHECK(c.points[0].position.z == doctest::Approx(5.0 * kFoot_m));
}

TEST_CASE("cloud_units: centres back in the survey's coordinates with sizes, yaw and score kept") {
    const glm::dvec3 origin{1639600.0, 1454500.0, 7000.0};
    const std::vector<core::Candidate> found{candidate(origin + glm::dvec3(3.048006096, 0.0, 1.0), {7, 3.5, 2.5})};
    const std::vector<core::Candidate> back = detect::centresInUnits(found, origin, usFeet());
    CHECK(back[0].centre_world.x == doctest::Approx(origin.x + 10.0));
    CHECK(back[0].centre_world.y == origin.y);
    CHECK(back[0].centre_world.z == doctest::Approx(origin.z + 1.0 / kFoot_m));
    CHECK(back[0].size_m == glm::dvec3(7, 3.5, 2.5));
    CHECK(back[0].yaw_deg == 30.0);
    CHECK(detect::centresInUnits(found, origin, sim::CoordinateUnits{})[0].centre_world == found[0].centre_world);
    const io::CandidateUnits u = detect::candidateUnits(usFeet());
    CHECK(u.horizontal_m == kFoot_m);
    CHECK(!u.metres());
}

TEST_CASE("cloud_units: a file's sizes drawn in its cloud's units, other units refused in one line") {
    const std::vector<core::Candidate> read{candidate({1639610.0, 1454500.0, 7001.0}, {7, 3.5, 2.5})};
    const io::CandidateUnits feet_file = detect::candidateUnits(usFeet());
    const std::vector<core::Candidate> drawn = detect::sizesInCloudUnits(read, feet_file, usFeet(), "view: c.json");
    CHECK(drawn[0].centre_world == read[0].centre_world);
    CHECK(drawn[0].size_m.x == doctest::Approx(7.0 / kFoot_m));
    CHECK(drawn[0].size_m.z == doctest::Approx(2.5 / kFoot_m));
    CHECK(detect::sizesInCloudUnits(read, io::CandidateUnits{}, sim::CoordinateUnits{}, "view: c.json")[0].size_m ==
          read[0].size_m);
    CHECK_THROWS_WITH_AS(detect::sizesInCloudUnits(read, io::CandidateUnits{}, usFeet(), "view: --candidates c.json"),
                         "view: --candidates c.json: centres in metres; the cloud is in US survey feet (0.3048006 m): "
                         "allowed candidates found in this cloud (`ladarvr detect` on it)",
                         core::Error);
    CHECK_THROWS_WITH_AS(
        detect::sizesInCloudUnits(read, feet_file, sim::CoordinateUnits{}, "view: --candidates c.json"),
        "view: --candidates c.json: centres in units of 0.3048006096 m; the cloud is in metres: "
        "allowed candidates found in this cloud (`ladarvr detect` on it)",
        core::Error);
}
