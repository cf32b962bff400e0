// viewer/src/points/file_colours.hpp: the colours of a LAS, LAZ or COPC file from another
// producer, as the viewer draws them (0x00RRGGBB), at the depth its data shows: many
// producers store 8-bit values (0..255) in LAS's 16-bit fields, which the high byte alone
// would show black.
#pragma once
#include <core/point_cloud.hpp>

#include <io/cloud_info.hpp>

#include <cstddef>
#include <span>

namespace viewer {

/// Reads a file's colours chunk by chunk, keeping the largest channel value seen.
class FileColours {
  public:
    /// Sets each point's rgb from its side record (`records`, `stride` bytes each, a
    /// core::ForeignPoint first, one per point): while no red, green or blue value read so
    /// far from the file (this chunk included) exceeds 255 the values are taken as 8-bit
    /// colours (io::colourDepthOf, as `info` reports them), else the high byte of each. A
    /// file's first chunk (262,144 points) decides for the points it holds.
    void recolour(std::span<core::CloudPoint> points, std::span<const unsigned char> records, std::size_t stride);
    /// The depth of the colours read so far.
    io::ColourDepth depth() const { return io::colourDepthOf(largest_); }

  private:
    unsigned largest_ = 0;
};

}  // namespace viewer
