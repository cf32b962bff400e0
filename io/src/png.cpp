// png: PNG encoding through stb_image_write, the one PNG writer of the project.
// Its implementation is not compiled here: Debian's libstb (the same package as the
// header) exports stbi_write_png_to_func, so io links that library.
#include <io/png.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>

#include <stb_image_write.h>

#include <algorithm>
#include <limits>
#include <vector>

namespace io {

using core::Error;
using platform::writeFileAtomic;

std::string encodePng(std::span<const std::uint8_t> pixels, int width, int height, int channels, PngRows rows) {
    const bool sizes_ok = width > 0 && height > 0 && (channels == 1 || channels == 3) &&
                          std::size_t(width) * std::size_t(channels) <= std::size_t(std::numeric_limits<int>::max()) &&
                          pixels.size() == std::size_t(width) * std::size_t(height) * std::size_t(channels);
    if (!sizes_ok)
        throw Error("png: image " + std::to_string(width) + "x" + std::to_string(height) + " with " +
                    std::to_string(channels) + " channels does not match " + std::to_string(pixels.size()) +
                    " bytes (allowed: width, height > 0; channels 1 or 3)");
    const int stride = width * channels;
    std::vector<std::uint8_t> flipped;
    const std::uint8_t* top_down = pixels.data();
    if (rows == PngRows::BottomUp) {
        // A copy instead of stb's global flip flag, which other threads would see.
        flipped.resize(pixels.size());
        for (int y = 0; y < height; ++y)
            std::copy_n(pixels.data() + std::size_t(height - 1 - y) * std::size_t(stride), stride,
                        flipped.data() + std::size_t(y) * std::size_t(stride));
        top_down = flipped.data();
    }
    std::string png;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
    };
    if (stbi_write_png_to_func(append, &png, width, height, channels, top_down, stride) == 0)
        throw Error("png: stb_image_write could not encode the " + std::to_string(width) + "x" +
                    std::to_string(height) + " image (out of memory?)");
    return png;
}

void writePng(const std::filesystem::path& path, std::span<const std::uint8_t> pixels, int width, int height,
              int channels, PngRows rows) {
    writeFileAtomic(path, encodePng(pixels, width, height, channels, rows));
}

}  // namespace io
