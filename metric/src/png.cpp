// metric/src/png.cpp: a minimal PNG encoder (greyscale 8-bit, zlib "stored" blocks).
// Enough for binary masks; every PNG reader accepts uncompressed deflate.
#include <metric/report.hpp>

#include <engine/error.hpp>

#include <array>
#include <cstdint>
#include <string>

namespace metric {
namespace {

const std::array<std::uint32_t, 256>& crcTable() {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t n = 0; n < 256; ++n) {
            std::uint32_t c = n;
            for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[n] = c;
        }
        return t;
    }();
    return table;
}

std::uint32_t crc32(const std::string& data, std::size_t begin) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (std::size_t i = begin; i < data.size(); ++i)
        c = crcTable()[(c ^ static_cast<std::uint8_t>(data[i])) & 0xFFu] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

void put32(std::string& out, std::uint32_t v) {
    out += static_cast<char>((v >> 24) & 0xFF);
    out += static_cast<char>((v >> 16) & 0xFF);
    out += static_cast<char>((v >> 8) & 0xFF);
    out += static_cast<char>(v & 0xFF);
}

void chunk(std::string& png, const char* type, const std::string& data) {
    put32(png, static_cast<std::uint32_t>(data.size()));
    const std::size_t start = png.size();
    png += type;
    png += data;
    put32(png, crc32(png, start));
}

}  // namespace

std::string encodePngGray(int width, int height, const std::vector<std::uint8_t>& rows_bottom_up) {
    if (width <= 0 || height <= 0 || rows_bottom_up.size() != static_cast<std::size_t>(width) * height)
        throw engine::Error("png: image size " + std::to_string(width) + "x" + std::to_string(height) +
                            " does not match " + std::to_string(rows_bottom_up.size()) + " bytes");
    // Raw scanlines: filter byte 0, then the row; PNG stores the top row first.
    std::string raw;
    raw.reserve(static_cast<std::size_t>(width + 1) * height);
    for (int y = height - 1; y >= 0; --y) {
        raw += '\0';
        raw.append(reinterpret_cast<const char*>(rows_bottom_up.data()) + static_cast<std::size_t>(y) * width,
                   static_cast<std::size_t>(width));
    }
    // zlib: header 0x78 0x01, stored blocks of <= 65535 bytes, Adler-32.
    std::string z;
    z += static_cast<char>(0x78);
    z += static_cast<char>(0x01);
    std::size_t pos = 0;
    do {
        const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
        const bool last = pos + n == raw.size();
        z += static_cast<char>(last ? 1 : 0);
        z += static_cast<char>(n & 0xFF);
        z += static_cast<char>((n >> 8) & 0xFF);
        z += static_cast<char>(~n & 0xFF);
        z += static_cast<char>((~n >> 8) & 0xFF);
        z.append(raw, pos, n);
        pos += n;
    } while (pos < raw.size());
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : raw) {
        a = (a + c) % 65521u;
        b = (b + a) % 65521u;
    }
    put32(z, (b << 16) | a);

    std::string png("\x89PNG\r\n\x1a\n", 8);
    std::string header;
    put32(header, static_cast<std::uint32_t>(width));
    put32(header, static_cast<std::uint32_t>(height));
    header += static_cast<char>(8);  // bit depth
    header += static_cast<char>(0);  // greyscale
    header += std::string(3, '\0');  // deflate, adaptive filtering, no interlace
    chunk(png, "IHDR", header);
    chunk(png, "IDAT", z);
    chunk(png, "IEND", "");
    return png;
}

}  // namespace metric
