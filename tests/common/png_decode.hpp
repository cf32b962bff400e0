// tests/common/png_decode.hpp: PNG files decoded by a real decoder (stb_image, from
// Debian's libstb), so tests check pixels rather than the encoder's byte layout.
#pragma once
#include <stb_image.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace test_support {

/// Decoded pixels, top row first, with the size and channel count the file declares.
struct DecodedPng {
    int width = 0, height = 0, channels = 0;
    std::vector<std::uint8_t> pixels;  // empty when the file is not a valid PNG
};

inline DecodedPng decodePng(const std::string& file) {
    DecodedPng d;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(
        stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(file.data()), int(file.size()), &d.width, &d.height,
                              &d.channels, 0),
        stbi_image_free);
    if (!data) return DecodedPng{};
    d.pixels.assign(data.get(), data.get() + std::size_t(d.width) * std::size_t(d.height) * std::size_t(d.channels));
    return d;
}

}  // namespace test_support
