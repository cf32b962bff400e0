// tests/viewer/points/file_colours_test.cpp: a file's 16-bit colour fields shown at the depth
// their values show: 8-bit values (none over 255) as they are, 16-bit ones by their high byte.
#include "points/file_colours.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <vector>

using namespace viewer;

namespace {
// Side records of `stride` bytes, a ForeignPoint with colour (r, g, b) first in each.
std::vector<unsigned char> records(const std::vector<std::array<std::uint16_t, 3>>& rgb, std::size_t stride) {
    std::vector<unsigned char> out(rgb.size() * stride, 0);
    for (std::size_t i = 0; i < rgb.size(); ++i) {
        core::ForeignPoint f;
        f.rgb[0] = rgb[i][0];
        f.rgb[1] = rgb[i][1];
        f.rgb[2] = rgb[i][2];
        std::memcpy(out.data() + i * stride, &f, sizeof f);
    }
    return out;
}
}  // namespace

TEST_CASE("8-bit colours in 16-bit fields are shown as they are, 16-bit ones by their high byte") {
    const std::size_t stride = sizeof(core::ForeignPoint) + 3;  // and 3 extra bytes
    std::vector<core::CloudPoint> points(2);
    FileColours eight;
    eight.recolour(points, records({{200, 180, 40}, {255, 0, 10}}, stride), stride);
    CHECK(eight.depth() == io::ColourDepth::EightBit);
    CHECK(points[0].rgb == core::packRgb(200, 180, 40));
    CHECK(points[1].rgb == core::packRgb(255, 0, 10));

    FileColours sixteen;
    sixteen.recolour(points, records({{200 * 257, 180 * 257, 40 * 257}, {65535, 0, 256}}, stride), stride);
    CHECK(sixteen.depth() == io::ColourDepth::SixteenBit);
    CHECK(points[0].rgb == core::packRgb(200, 180, 40));
    CHECK(points[1].rgb == core::packRgb(255, 0, 1));

    // Once a value over 255 was read, later chunks of the file are 16-bit too.
    sixteen.recolour(points, records({{200, 100, 50}, {0, 0, 0}}, stride), stride);
    CHECK(points[0].rgb == core::packRgb(0, 0, 0));
}
