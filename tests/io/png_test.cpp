// tests/io/png_test.cpp: io/png.hpp, checked by decoding with a real decoder.
#include <png_decode.hpp>
#include <test_files.hpp>

#include <core/error.hpp>
#include <io/png.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

using test_support::decodePng;

TEST_CASE("png: a known 3x2 RGB image decodes to the same pixels, rows in either order") {
    // Top row red, green, blue; bottom row white, black, grey.
    const std::vector<std::uint8_t> top_down = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 0, 0, 0, 128, 128, 128};
    const auto d = decodePng(io::encodePng(top_down, 3, 2, 3));
    CHECK(d.width == 3);
    CHECK(d.height == 2);
    CHECK(d.channels == 3);
    CHECK(d.pixels == top_down);
    std::vector<std::uint8_t> bottom_up(top_down.begin() + 9, top_down.end());
    bottom_up.insert(bottom_up.end(), top_down.begin(), top_down.begin() + 9);
    CHECK(decodePng(io::encodePng(bottom_up, 3, 2, 3, io::PngRows::BottomUp)).pixels == top_down);
}

TEST_CASE("png: greyscale masks round-trip and compress far below the raw size") {
    // A 512 x 512 binary mask like the metric's: a filled disc on black.
    const int w = 512, h = 512;
    std::vector<std::uint8_t> mask(std::size_t(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if ((x - 200) * (x - 200) + (y - 300) * (y - 300) < 120 * 120) mask[std::size_t(y) * w + x] = 255;
    const std::string png = io::encodePng(mask, w, h, 1, io::PngRows::BottomUp);
    const auto d = decodePng(png);
    REQUIRE(d.channels == 1);
    REQUIRE(d.pixels.size() == mask.size());
    for (int y = 0; y < h; ++y)  // bottom-up in, top-down out
        CHECK(std::equal(d.pixels.begin() + std::ptrdiff_t(y) * w, d.pixels.begin() + std::ptrdiff_t(y + 1) * w,
                         mask.begin() + std::ptrdiff_t(h - 1 - y) * w));
    CHECK(png.size() < mask.size() / 20);  // deflate, not stored blocks
    // Noise does not compress, but still decodes exactly.
    std::vector<std::uint8_t> noise(std::size_t(301) * 77);
    std::uint32_t x = 12345;
    for (auto& v : noise) v = std::uint8_t((x = x * 1664525u + 1013904223u) >> 24);
    CHECK(decodePng(io::encodePng(noise, 301, 77, 1)).pixels == noise);
}

TEST_CASE("png: wrong sizes and channel counts are one clear error") {
    const std::vector<std::uint8_t> six(6, 0);
    CHECK_THROWS_WITH_AS(io::encodePng(six, 3, 3, 1), doctest::Contains("png: image 3x3 with 1 channels"), core::Error);
    CHECK_THROWS_AS(io::encodePng(six, 2, 2, 3), core::Error);  // RGB needs 12 bytes
    CHECK_NOTHROW(io::encodePng(six, 1, 2, 3));
    CHECK_THROWS_AS(io::encodePng(six, 2, 3, 2), core::Error);  // 2 channels not offered
    CHECK_THROWS_AS(io::encodePng(six, 0, 6, 1), core::Error);
}

TEST_CASE("png: writePng writes atomically and leaves nothing else behind") {
    test_support::TempDir dir("png");
    const std::vector<std::uint8_t> grey = {0, 64, 128, 255};
    io::writePng(dir.path / "a.png", grey, 2, 2, 1);
    const auto d = decodePng(test_support::slurp(dir.path / "a.png"));
    CHECK(d.pixels == grey);
    CHECK(dir.entries() == 1);
    CHECK_THROWS_WITH_AS(io::writePng(dir.path / "missing" / "b.png", grey, 2, 2, 1), doctest::Contains("output: "),
                         core::Error);
    CHECK(dir.entries() == 1);
}
