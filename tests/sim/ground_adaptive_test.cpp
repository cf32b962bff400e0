// tests/sim/ground_adaptive_test.cpp: the survey traits the adaptive choice of SMRF's
// options reads, on known surfaces: a flat plane, a tilted plane and a plane with a box
// building give the slope, relief, density and object shares they were made with.
#include "ground_surfaces.hpp"

#include <sim/ground_adaptive.hpp>
#include <sim/ground_file.hpp>

#include <doctest/doctest.h>

#include <vector>

namespace {

using namespace ground_test;

std::vector<core::CloudPoint> cloudOf(const Labelled& l) {
    std::vector<core::CloudPoint> points(l.points.size());
    for (std::size_t i = 0; i < points.size(); ++i) points[i].position = l.points[i];
    return points;
}

}  // namespace

TEST_CASE("survey traits: a flat plane has no slope, relief or objects, 16 points a square metre") {
    const Labelled l = sample([](double, double) { return 2.0; }, 40.0, {});
    const sim::SurveyTraits t = sim::measureSurvey(cloudOf(l), sim::surveySmrfOptions());
    CHECK(t.slope_p50 < 0.01);
    CHECK(t.slope_p90 < 0.01);
    CHECK(t.relief_m < 0.05);
    CHECK(t.object_share < 0.001);
    CHECK(t.high_share == 0.0);
    CHECK(t.points_per_m2 == doctest::Approx(16.0).epsilon(0.05));
    CHECK(t.empty_share < 0.05);
}

TEST_CASE("survey traits: a plane tilted 0.2 reads slope 0.2 and its relief") {
    const Labelled l = sample([](double x, double) { return 0.2 * x; }, 40.0, {});
    const sim::SurveyTraits t = sim::measureSurvey(cloudOf(l), sim::surveySmrfOptions());
    CHECK(t.slope_p50 == doctest::Approx(0.2).epsilon(0.05));
    CHECK(t.slope_p90 == doctest::Approx(0.2).epsilon(0.1));
    CHECK(t.steep_share == 0.0);
    // 80 m across at 0.2: 16 m, 90 % of it between the 5th and 95th percentiles.
    CHECK(t.relief_m == doctest::Approx(0.9 * 16.0).epsilon(0.05));
    CHECK(t.object_share < 0.01);
}

TEST_CASE("survey traits: a box building's points are the objects and stand high") {
    const Labelled l = sample([](double, double) { return 0.0; }, 40.0, {{0.0, 0.0, 8.0, 6.0}});
    std::size_t high = 0;
    for (const std::uint8_t h : l.high_object) high += h;
    const double high_share = double(high) / double(l.points.size());
    const sim::SurveyTraits t = sim::measureSurvey(cloudOf(l), sim::surveySmrfOptions());
    CHECK(t.high_share == doctest::Approx(high_share).epsilon(0.1));
    CHECK(t.object_share >= t.high_share);
    CHECK(t.edge_share > 0.0);
    CHECK(t.slope_p50 < 0.01);
}
