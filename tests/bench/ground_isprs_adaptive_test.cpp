// tests/bench/ground_isprs_adaptive_test.cpp: the rule that chooses SMRF's options per
// survey from its traits, fitted on known error tables: it finds the trait and the
// threshold that separate the surveys another set suits, and keeps the base set where
// nothing is gained or one survey alone would choose the other.
#include "ground_isprs_adaptive.hpp"

#include <doctest/doctest.h>

#include <vector>

namespace {

// Six surveys, two traits; errors of three option sets. Set 0 is the base.
struct Table {
    std::vector<std::vector<double>> errors, traits;
    std::vector<std::size_t> all{0, 1, 2, 3, 4, 5};
};

Table steepSurveysPreferSet2() {
    Table t;
    // Trait 0 (noise), trait 1 (terrain slope): the three steep surveys do best with set 2.
    t.traits = {{3, 0.05}, {1, 0.08}, {2, 0.1}, {3, 0.3}, {1, 0.4}, {2, 0.5}};
    t.errors = {{2, 3, 6}, {2, 3, 6}, {2, 3, 6}, {6, 5, 1}, {6, 5, 1}, {6, 5, 1}};
    return t;
}

}  // namespace

TEST_CASE("selection rule: the trait and threshold that separate the surveys another set suits") {
    const Table t = steepSurveysPreferSet2();
    const bench::SelectionRule r = bench::fitSelectionRule(t.errors, t.traits, t.all, 0);
    CHECK(r.trait == 1);
    CHECK(r.alternative == 2);
    CHECK(r.above);
    CHECK(r.threshold == doctest::Approx(0.2));
    CHECK(r.choose({0, 0.05}) == 0);
    CHECK(r.choose({0, 0.6}) == 2);
}

TEST_CASE("selection rule: the base set is kept when nothing beats it") {
    Table t = steepSurveysPreferSet2();
    for (auto& e : t.errors) e = {1, 2, 3};
    const bench::SelectionRule r = bench::fitSelectionRule(t.errors, t.traits, t.all, 0);
    CHECK(r.trait == -1);
    CHECK(r.choose({0, 0.6}) == 0);
}

TEST_CASE("selection rule: one survey alone does not make a rule") {
    Table t = steepSurveysPreferSet2();
    // The last survey gains 5 points with set 2; any other survey loses 7 with it.
    t.errors = {{2, 3, 9}, {2, 3, 9}, {2, 3, 9}, {2, 3, 9}, {2, 3, 9}, {6, 5, 1}};
    const bench::SelectionRule r = bench::fitSelectionRule(t.errors, t.traits, t.all, 0);
    CHECK(r.trait == -1);
}

TEST_CASE("selection rule: fitted on the training surveys only") {
    const Table t = steepSurveysPreferSet2();
    // Without the steep surveys there is nothing to learn about them.
    const bench::SelectionRule r = bench::fitSelectionRule(t.errors, t.traits, {0, 1, 2}, 0);
    CHECK(r.trait == -1);
    CHECK(r.choose({0, 0.5}) == 0);
}
