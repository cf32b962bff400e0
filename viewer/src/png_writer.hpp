// viewer/src/png_writer.hpp: a minimal PNG encoder (RGB8, stored deflate blocks) for screenshots.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace viewer {

/// Encodes `rgb` (width*height*3 bytes, top row first) as a PNG file image.
std::string encodePng(const std::vector<std::uint8_t>& rgb, int width, int height);
/// Writes the PNG atomically; throws engine::Error("output: ...") on failure.
void writePng(const std::filesystem::path& path, const std::vector<std::uint8_t>& rgb, int width, int height);

}  // namespace viewer
