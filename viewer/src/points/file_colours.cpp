// viewer/src/points/file_colours.cpp: 8- or 16-bit file colours to the viewer's 8-bit ones.
#include "points/file_colours.hpp"

#include <algorithm>
#include <cstring>

namespace viewer {

void FileColours::recolour(std::span<core::CloudPoint> points, std::span<const unsigned char> records,
                           std::size_t stride) {
    if (stride < sizeof(core::ForeignPoint)) return;
    const std::size_t n = std::min(points.size(), records.size() / stride);
    auto side = [&](std::size_t i) {
        core::ForeignPoint f;
        std::memcpy(&f, records.data() + i * stride, sizeof f);
        return f;
    };
    for (std::size_t i = 0; i < n; ++i) {
        const core::ForeignPoint f = side(i);
        largest_ = std::max({largest_, unsigned(f.rgb[0]), unsigned(f.rgb[1]), unsigned(f.rgb[2])});
    }
    const unsigned shift = depth() == io::ColourDepth::SixteenBit ? 8u : 0u;
    for (std::size_t i = 0; i < n; ++i) {
        const core::ForeignPoint f = side(i);
        points[i].rgb = core::packRgb(std::uint8_t(f.rgb[0] >> shift), std::uint8_t(f.rgb[1] >> shift),
                                      std::uint8_t(f.rgb[2] >> shift));
    }
}

}  // namespace viewer
