// Tests of study/instruments.hpp: the SSQ's clusters and weights against the published
// maxima, the raw TLX, and the one-line refusals of out-of-range ratings.
#include <study/instruments.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <set>
#include <string>
#include <vector>

TEST_CASE("the SSQ has 16 symptoms, seven per cluster, with distinct ids") {
    const auto items = study::ssqItems();
    REQUIRE(items.size() == 16);
    int n = 0, o = 0, d = 0;
    std::set<std::string_view> ids;
    for (const auto& it : items) {
        n += (it.clusters & study::kSsqNausea) ? 1 : 0;
        o += (it.clusters & study::kSsqOculomotor) ? 1 : 0;
        d += (it.clusters & study::kSsqDisorientation) ? 1 : 0;
        ids.insert(it.item.id);
    }
    CHECK(n == 7);
    CHECK(o == 7);
    CHECK(d == 7);
    CHECK(ids.size() == 16);
}

TEST_CASE("SSQ scores: none is zero, all severe gives Kennedy's maxima") {
    std::vector<int> none(16, 0), severe(16, 3);
    const auto z = study::scoreSsq(none);
    CHECK(z.total == 0.0);
    const auto m = study::scoreSsq(severe);
    CHECK(m.nausea == doctest::Approx(200.34));
    CHECK(m.oculomotor == doctest::Approx(159.18));
    CHECK(m.disorientation == doctest::Approx(292.32));
    CHECK(m.total == doctest::Approx(235.62));
}

TEST_CASE("SSQ: one slight nausea counts in nausea and disorientation") {
    std::vector<int> r(16, 0);
    r[std::size_t(*study::ssqItemIndex("nausea"))] = 1;
    const auto s = study::scoreSsq(r);
    CHECK(s.nausea == doctest::Approx(9.54));
    CHECK(s.oculomotor == 0.0);
    CHECK(s.disorientation == doctest::Approx(13.92));
    CHECK(s.total == doctest::Approx(7.48));
}

TEST_CASE("SSQ and TLX refuse what is not a rating, naming the item") {
    std::vector<int> r(16, 0);
    r[3] = 4;
    CHECK_THROWS_WITH_AS(study::scoreSsq(r), doctest::Contains("eyestrain rated 4"), core::Error);
    CHECK_THROWS_AS(study::scoreSsq(std::vector<int>(15, 0)), core::Error);
    CHECK_THROWS_WITH_AS(study::scoreTlxRaw(std::vector<int>{50, 50, 52, 50, 50, 50}),
                         doctest::Contains("temporal rated 52"), core::Error);
    CHECK_THROWS_AS(study::scoreTlxRaw(std::vector<int>{50, 50, 50, 50, 50, 105}), core::Error);
}

TEST_CASE("raw TLX is the mean of the six subscales") {
    CHECK(study::scoreTlxRaw(std::vector<int>{0, 0, 0, 0, 0, 0}) == 0.0);
    CHECK(study::scoreTlxRaw(std::vector<int>{10, 20, 30, 40, 50, 60}) == doctest::Approx(35.0));
    CHECK(study::tlxItemIndex("effort") == 4);
    CHECK(!study::tlxItemIndex("fatigue"));
    CHECK(study::ssqItemIndex("fatigue") == 1);
}
