// tests/sim/colour_test.cpp: the paper's jet map with 64 values, red low, blue high.
#include <sim/colour.hpp>

#include <core/error.hpp>
#include <core/jet.hpp>
#include <core/point_cloud.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace {

// Hue in degrees of a packed colour (0 red, 60 yellow, 120 green, 180 cyan, 240 blue).
double hueDeg(std::uint32_t rgb) {
    const double r = (rgb >> 16 & 255) / 255.0, g = (rgb >> 8 & 255) / 255.0, b = (rgb & 255) / 255.0;
    const double mx = std::max({r, g, b}), mn = std::min({r, g, b});
    if (mx == mn) return 0.0;
    double h;
    if (mx == r)
        h = 60.0 * std::fmod((g - b) / (mx - mn), 6.0);
    else if (mx == g)
        h = 60.0 * ((b - r) / (mx - mn) + 2.0);
    else
        h = 60.0 * ((r - g) / (mx - mn) + 4.0);
    return h < 0 ? h + 360.0 : h;
}

}  // namespace

TEST_CASE("jet(64) matches MATLAB's table at known rows") {
    const auto jet = core::jetTable(64);
    REQUIRE(jet.size() == 64);
    CHECK(jet[0] == core::packRgb(0, 0, 143));                            // [0 0 0.5625]
    CHECK(jet[7] == core::packRgb(0, 0, 255));                            // [0 0 1]
    CHECK(jet[8] == core::packRgb(0, 16, 255));                           // [0 0.0625 1]
    CHECK(jet[23] == core::packRgb(0, 255, 255));                         // [0 1 1]
    CHECK(jet[39] == core::packRgb(255, 255, 0));                         // [1 1 0]
    CHECK(jet[63] == core::packRgb(128, 0, 0));                           // [0.5 0 0]
    CHECK(std::set<std::uint32_t>(jet.begin(), jet.end()).size() == 64);  // every colour once
}

TEST_CASE("height colours: red at the minimum, blue at the maximum, hue rising with height") {
    const auto jet = core::jetTable(64);
    CHECK(sim::heightColour(10.0f, 10.0f, 20.0f, jet) == core::packRgb(128, 0, 0));
    CHECK(sim::heightColour(20.0f, 10.0f, 20.0f, jet) == core::packRgb(0, 0, 143));
    double last_hue = -1.0;
    std::set<std::uint32_t> seen;
    for (int k = 0; k <= 640; ++k) {
        const float z = 10.0f + 10.0f * float(k) / 640.0f;
        const std::uint32_t c = sim::heightColour(z, 10.0f, 20.0f, jet);
        seen.insert(c);
        const double h = hueDeg(c);
        CHECK(h >= last_hue - 1e-9);  // red (0) -> yellow -> green -> cyan -> blue (240)
        last_hue = h;
    }
    CHECK(last_hue == doctest::Approx(240.0));
    CHECK(seen.size() == 64);  // quantised to the 64 entries
    // Out-of-range heights clamp; equal heights give the lowest colour, never NaN-driven.
    CHECK(sim::heightColour(-5.0f, 10.0f, 20.0f, jet) == core::packRgb(128, 0, 0));
    CHECK(sim::heightColour(99.0f, 10.0f, 20.0f, jet) == core::packRgb(0, 0, 143));
    CHECK(sim::heightColour(3.0f, 3.0f, 3.0f, jet) == core::packRgb(128, 0, 0));
}

TEST_CASE("the generator colours with core's jet table, the one the viewer shows") {
    for (int m : {2, 5, 16, 64, 256}) {
        const auto jet = core::jetTable(m);
        for (int k = -2; k <= 42; ++k) {
            const float z = -1.0f + 0.5f * float(k);
            CHECK(sim::heightColour(z, 0.0f, 20.0f, jet) == jet[core::jetIndex(z, 0.0, 20.0, m)]);
        }
    }
}

TEST_CASE("colour options are validated") {
    sim::ColourOptions o;
    o.entries = 1;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("entries"), core::Error);
    o.entries = 64;
    CHECK_NOTHROW(sim::validate(o));
}
