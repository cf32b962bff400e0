// tests/viewer/png_writer_test.cpp: the screenshot encoder's byte layout (known constants).
#include "png_writer.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

using viewer::encodePng;

namespace {
std::uint32_t be32(const std::string& s, std::size_t at) {
    return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}
}  // namespace

TEST_CASE("PNG layout is signature then IHDR then one stored-deflate IDAT then IEND") {
    const std::vector<std::uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255,   // row 0
                                           1, 2, 3, 4, 5, 6, 7, 8, 9};         // row 1
    const std::string png = encodePng(rgb, 3, 2);
    CHECK(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
    CHECK(be32(png, 8) == 13);
    CHECK(png.substr(12, 4) == "IHDR");
    CHECK(be32(png, 16) == 3);
    CHECK(be32(png, 20) == 2);
    CHECK(png[24] == 8);   // bit depth
    CHECK(png[25] == 2);   // RGB
    // IDAT: zlib header (2) + stored block header (5) + (1 + 9) * 2 raw bytes + adler32 (4).
    const std::size_t idat = 8 + 12 + 13;
    CHECK(be32(png, idat) == 2 + 5 + 20 + 4);
    CHECK(png.substr(idat + 4, 4) == "IDAT");
    CHECK(png.substr(idat + 8 + 2 + 5, 4) == std::string("\0\xff\0\0", 4));   // filter 0, first pixel
    // IEND has the fixed CRC every PNG ends with.
    CHECK(png.substr(png.size() - 12) == std::string("\0\0\0\0IEND\xae\x42\x60\x82", 12));
}

TEST_CASE("large images split into 64 KiB stored blocks") {
    const int w = 300, h = 100;   // 90,100 raw bytes: two blocks
    const std::string png = encodePng(std::vector<std::uint8_t>(std::size_t(w) * h * 3, 128), w, h);
    const std::size_t idat = 8 + 12 + 13;
    CHECK(be32(png, idat) == 2 + 5 + 65535 + 5 + (90100 - 65535) + 4);
}
