// tests/bench/ground_isprs_map_test.cpp: the error picture of `bench ground-isprs --map`:
// each point where it lies (x to the right, y up, the aspect kept), in the colour of what the
// filter made of it, errors over right points, the sample's number in the corner, and the
// panels laid out in rows with a frame around each.
#include "ground_isprs_map.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

namespace {

core::CloudPoint at(float x, float y) {
    core::CloudPoint p{};
    p.position = {x, y, 0.0f};
    return p;
}

bool is(const bench::MapImage& image, int x, int y, const std::uint8_t* colour) {
    return std::equal(colour, colour + 3, image.at(x, y));
}

}  // namespace

TEST_CASE("error map: each point in its place and in the colour of what the filter made of it") {
    // A 100 m x 50 m sample: corners and the middle of the bottom edge.
    const std::vector<core::CloudPoint> points = {at(0, 0), at(100, 0), at(0, 50), at(100, 50), at(50, 0)};
    const std::vector<std::uint8_t> truth = {1, 0, 1, 0, 1};
    const std::vector<std::uint8_t> found = {1, 0, 0, 1, 1};  // right ground, right object, type I, type II
    const int side = 103;                                     // 100 px for 100 m, and the 3 px of a dot
    const bench::MapImage image = bench::renderErrorPanel(points, truth, found, side, "");
    REQUIRE(image.width == side);
    REQUIRE(image.height == side);
    REQUIRE(image.rgb.size() == std::size_t(side * side * 3));
    // 1 px a metre, the 50 m of height centred: y = 0 m at row 75, y = 50 m at row 25.
    CHECK(is(image, 0, 75, bench::kMapGroundRight));
    CHECK(is(image, 1, 76, bench::kMapGroundRight));  // a right point is 2 x 2
    CHECK(is(image, 2, 77, bench::kMapBackground));
    CHECK(is(image, 100, 75, bench::kMapObjectRight));
    CHECK(is(image, 0, 25, bench::kMapTypeI));
    CHECK(is(image, 2, 27, bench::kMapTypeI));  // an error is 3 x 3
    CHECK(is(image, 100, 25, bench::kMapTypeII));
    CHECK(is(image, 50, 75, bench::kMapGroundRight));
    CHECK(is(image, 50, 50, bench::kMapBackground));
}

TEST_CASE("error map: an error is drawn over a right point at the same place") {
    const std::vector<core::CloudPoint> points = {at(0, 0), at(0, 0), at(10, 10)};
    for (const bool error_first : {true, false}) {
        const std::vector<std::uint8_t> truth = {1, 1, 1};
        const std::vector<std::uint8_t> found =
            error_first ? std::vector<std::uint8_t>{0, 1, 1} : std::vector<std::uint8_t>{1, 0, 1};
        const bench::MapImage image = bench::renderErrorPanel(points, truth, found, 64, "");
        CHECK(is(image, 0, 61, bench::kMapTypeI));  // (0, 0) m: 6.1 px a metre, 10 m up
    }
}

TEST_CASE("error map: the sample's number in the top-left corner, on a clear box") {
    const std::vector<core::CloudPoint> points = {at(0, 1), at(1, 0)};
    const std::vector<std::uint8_t> labels = {1, 1};
    const bench::MapImage plain = bench::renderErrorPanel(points, labels, labels, 64, "");
    const bench::MapImage one = bench::renderErrorPanel(points, labels, labels, 64, "samp1");
    const auto dark = [](const bench::MapImage& image) {
        int n = 0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) n += is(image, x, y, bench::kMapLabel);
        return n;
    };
    CHECK(dark(plain) == 0);
    // "1" in the 3 x 5 font: 8 of its 15 pixels set, each 3 x 3 image pixels.
    CHECK(dark(one) == 8 * 9);
    // The point at (0, 1 m), under the label's box, is covered by it.
    CHECK(is(plain, 0, 0, bench::kMapGroundRight));
    CHECK(is(one, 0, 0, bench::kMapBackground));
}

TEST_CASE("error map: the panels in rows, framed, and bad sizes refused") {
    const std::vector<core::CloudPoint> points = {at(0, 0), at(1, 1)};
    const std::vector<std::uint8_t> labels = {1, 1};
    const bench::MapImage panel = bench::renderErrorPanel(points, labels, labels, 20, "");
    const bench::MapImage m = bench::mosaic({panel, panel, panel}, 2, 4);
    CHECK(m.width == 2 * 20 + 3 * 4);
    CHECK(m.height == 2 * 20 + 3 * 4);
    CHECK(is(m, 3, 3, bench::kMapFrame));  // the frame around the first panel
    CHECK(is(m, 4 + 19, 4 + 19, panel.at(19, 19)));
    CHECK(is(m, 4 + 20 + 4 + 2, 4 + 20 + 4 + 2, bench::kMapBackground));  // no fourth panel
    CHECK(is(m, 4 + 20 + 4, 4, panel.at(0, 0)));                          // the second, right of it
    CHECK(is(m, 4, 4 + 20 + 4, panel.at(0, 0)));                          // the third, below
    CHECK_THROWS_AS(bench::mosaic({}, 2, 4), core::Error);
    CHECK_THROWS_AS(bench::mosaic({panel, bench::renderErrorPanel(points, labels, labels, 21, "")}, 2, 4), core::Error);
    CHECK_THROWS_AS(bench::renderErrorPanel(points, {1}, labels, 20, ""), core::Error);
    CHECK_THROWS_AS(bench::renderErrorPanel(points, labels, labels, 8, ""), core::Error);
}
