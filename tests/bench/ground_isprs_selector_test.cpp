// tests/bench/ground_isprs_selector_test.cpp: the selector's pairwise choice and its training
// rows' labels and weights: the set most probably better than the base is taken only past
// even odds, and a tile weighs what the choice moves in its sample's total error.
#include "ground_isprs_selector.hpp"

#include <doctest/doctest.h>

#include <vector>

TEST_CASE("selector: the base set unless another is more likely than not to do better") {
    CHECK(bench::choosePairwise({}) == 0);
    CHECK(bench::choosePairwise({0.2, 0.5}) == 0);
    CHECK(bench::choosePairwise({0.6, 0.3}) == 1);
    CHECK(bench::choosePairwise({0.6, 0.9}) == 2);
    CHECK(bench::choosePairwise({0.51, 0.49, 0.7}) == 3);
}

TEST_CASE("selector: a tile's row weighs the points the choice moves, as a share of its sample") {
    const bench::PairTarget better = bench::pairTarget(30, 10, 1000);
    CHECK(better.label == 1.0f);
    CHECK(better.weight == doctest::Approx(2.0));  // 20 points of 1,000: 2 % of the sample's total error
    const bench::PairTarget worse = bench::pairTarget(10, 15, 500);
    CHECK(worse.label == 0.0f);
    CHECK(worse.weight == doctest::Approx(1.0));
    CHECK(bench::pairTarget(7, 7, 100).weight == 0.0f);
    CHECK(bench::pairTarget(7, 3, 0).weight == 0.0f);
}

TEST_CASE("selector: the base set comes first, then the sets it is compared with") {
    const auto& sets = bench::selectorSets();
    REQUIRE(sets.size() >= 3);
    CHECK(sets[0].slope == doctest::Approx(0.15));
    CHECK(sets[0].window_m == doctest::Approx(18.0));
    CHECK(sets[0].threshold_m == doctest::Approx(0.5));
    CHECK(sets[0].scalar == doctest::Approx(1.25));
}
