// tests/bench/ground_isprs_selector_test.cpp: the selector's pairwise choice and its training
// rows' labels and weights: the set most probably better than the base is taken only past
// even odds, a tile weighs what the choice moves in its sample's total error, and the
// points two sets disagree on join into patches through touching cells.
#include "ground_isprs_selector.hpp"
#include "ground_isprs_selector_segments.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
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

TEST_CASE("selector: the points two sets label differently join into patches through touching 2 m cells") {
    bench::SampleFits f;
    // Points in 1 m cells (row << 32 | column): columns 0, 3 (2 m cells 0 and 1: touching),
    // 10 (2 m cell 5: apart), 1 (agreeing), and row 4 under column 0 (2 m row 2: apart).
    const auto cell = [](std::uint64_t row, std::uint64_t column) { return (row << 32) | column; };
    f.cell = {cell(0, 0), cell(0, 3), cell(0, 10), cell(0, 1), cell(4, 0)};
    f.ground = {{1, 1, 1, 1, 0}, {0, 0, 0, 1, 1}};
    std::vector<std::vector<std::size_t>> patches = bench::disagreementPatches(f, 1);
    for (auto& p : patches) std::sort(p.begin(), p.end());
    std::sort(patches.begin(), patches.end());
    REQUIRE(patches.size() == 3);
    CHECK(patches[0] == std::vector<std::size_t>{0, 1});
    CHECK(patches[1] == std::vector<std::size_t>{2});
    CHECK(patches[2] == std::vector<std::size_t>{4});
    f.ground[1] = f.ground[0];
    CHECK(bench::disagreementPatches(f, 1).empty());
}
