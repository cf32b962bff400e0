// tests/bench/common_test.cpp: the spread reported beside every benchmark median, and
// when a ratio of two medians counts as within that spread.
#include <common.hpp>

#include <doctest/doctest.h>

#include <cmath>

TEST_CASE("spread: min, median and max of the samples, NaN for none") {
    const bench::Spread s = bench::spread({5.0, 1.0, 4.0, 2.0, 3.0});
    CHECK(s.n == 5);
    CHECK(s.min == 1.0);
    CHECK(s.median == 3.0);
    CHECK(s.max == 5.0);
    CHECK(bench::spread({2.0, 4.0}).median == 3.0);
    const bench::Spread none = bench::spread({});
    CHECK(none.n == 0);
    CHECK(std::isnan(none.median));
}

TEST_CASE("fmtSpread shows the range only when there are two samples or more") {
    CHECK(bench::fmtSpread("%.2f", bench::spread({1.0, 3.0, 2.0})) == "2.00 [1.00..3.00]");
    CHECK(bench::fmtSpread("%.1f", bench::spread({7.0})) == "7.0");
}

TEST_CASE("a ratio is within spread when the two ranges overlap, never for single runs") {
    const bench::Spread a = bench::spread({10.0, 11.0, 12.0});
    const bench::Spread touching = bench::spread({12.0, 13.0, 14.0});
    const bench::Spread apart = bench::spread({12.5, 13.0, 14.0});
    CHECK(bench::withinSpread(a, touching));
    CHECK(bench::withinSpread(touching, a));
    CHECK_FALSE(bench::withinSpread(a, apart));
    CHECK_FALSE(bench::withinSpread(apart, a));
    CHECK(bench::spreadNote(a, touching) == " (within spread)");
    CHECK(bench::spreadNote(a, apart).empty());
    CHECK_FALSE(bench::withinSpread(bench::spread({11.0}), a));
}
