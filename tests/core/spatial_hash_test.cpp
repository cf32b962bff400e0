// tests/core/spatial_hash_test.cpp: core/spatial_hash.hpp, the one cell binning.
#include <core/error.hpp>
#include <core/spatial_hash.hpp>

#include <doctest/doctest.h>

#include <set>
#include <vector>

namespace {

core::CloudPoint at(float x, float y, float z) {
    core::CloudPoint p;
    p.position = {x, y, z};
    return p;
}

}  // namespace

TEST_CASE("spatial hash: cells are floor(p / size), negative coordinates included") {
    CHECK(core::cellOf({0.5f, 1.5f, 2.5f}, 1.0) == core::CellKey{0, 1, 2});
    CHECK(core::cellOf({-0.5f, -1.0f, -1.5f}, 1.0) == core::CellKey{-1, -1, -2});
    CHECK(core::cellOf({15.9f, 16.0f, -0.1f}, 16.0) == core::CellKey{0, 1, -1});
}

TEST_CASE("spatial hash: cells in order of their first point, points in input order") {
    const std::vector<core::CloudPoint> pts = {at(5, 5, 5),  at(0.5f, 0, 0),       at(6.5f, 5, 5),
                                               at(-3, 0, 0), at(0.1f, 0.9f, 0.2f), at(6, 5.9f, 5)};
    const core::CellBins bins = core::binByCell(pts, 1.0);
    REQUIRE(bins.cells() == 4);
    CHECK(bins.keys[0] == core::CellKey{5, 5, 5});
    CHECK(bins.keys[1] == core::CellKey{0, 0, 0});
    CHECK(bins.keys[2] == core::CellKey{6, 5, 5});
    CHECK(bins.keys[3] == core::CellKey{-3, 0, 0});
    CHECK(std::vector<std::uint32_t>(bins.cell(0).begin(), bins.cell(0).end()) == std::vector<std::uint32_t>{0});
    CHECK(std::vector<std::uint32_t>(bins.cell(1).begin(), bins.cell(1).end()) == std::vector<std::uint32_t>{1, 4});
    CHECK(std::vector<std::uint32_t>(bins.cell(2).begin(), bins.cell(2).end()) == std::vector<std::uint32_t>{2, 5});
    CHECK(std::vector<std::uint32_t>(bins.cell(3).begin(), bins.cell(3).end()) == std::vector<std::uint32_t>{3});
    // Every point exactly once, and in the cell its key says.
    std::set<std::uint32_t> seen(bins.order.begin(), bins.order.end());
    CHECK(seen.size() == pts.size());
    for (std::size_t c = 0; c < bins.cells(); ++c)
        for (std::uint32_t i : bins.cell(c)) CHECK(core::cellOf(pts[i].position, 1.0) == bins.keys[c]);
}

TEST_CASE("spatial hash: empty input, and a cell size that is not > 0 is refused") {
    const core::CellBins none = core::binByCell({}, 2.0);
    CHECK(none.cells() == 0);
    CHECK(none.order.empty());
    const std::vector<core::CloudPoint> one = {at(1, 2, 3)};
    CHECK_THROWS_WITH_AS(core::binByCell(one, 0.0), doctest::Contains("spatial hash: cell size"), core::Error);
    CHECK_THROWS_AS(core::binByCell(one, -1.0), core::Error);
}
