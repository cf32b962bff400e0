// io/png.hpp: PNG images (8-bit grey or RGB) for every picture the project writes:
// the metric's I1..I4 and the viewer's screenshots. Encoded by stb_image_write (zlib
// deflate, so far smaller than raw pixels), written atomically.
#pragma once
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace io {

/// Row order of the pixels handed in: top row first (files, screens) or bottom row first
/// (OpenGL's glReadPixels). The PNG always shows the image upright.
enum class PngRows { TopDown, BottomUp };

/// The PNG file image of `pixels`: width * height * channels bytes, channels 1 (grey) or
/// 3 (RGB). Throws core::Error("png: ...") when the sizes do not match or are not > 0.
std::string encodePng(std::span<const std::uint8_t> pixels, int width, int height, int channels,
                      PngRows rows = PngRows::TopDown);

/// encodePng, then platform::writeFileAtomic(path, ...): throws core::Error("png: ...")
/// or ("output: <path>: ...").
void writePng(const std::filesystem::path& path, std::span<const std::uint8_t> pixels, int width, int height,
              int channels, PngRows rows = PngRows::TopDown);

}  // namespace io
