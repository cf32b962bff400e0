// sim/colour.hpp: height colouring of the fused cloud (paper §III-C, first principle).
#pragma once
#include <cstdint>
#include <vector>

namespace sim {

/// The jet map of the paper: `entries` colours (the paper's 64), red at the minimum height,
/// blue at the maximum; a height falls in one of `entries` equal bins (no blending).
struct ColourOptions {
    int entries = 64;
};

/// Throws core::Error("colour: entries = N: allowed [2, 256]").
void validate(const ColourOptions& o);

/// Colour of height z in [z_min, z_max] for a table from core::jetTable() (MATLAB's
/// jet(m), the table the viewer shows too): bin
/// floor((z - z_min) / (z_max - z_min) * m) clamped to [0, m-1], reversed so the lowest
/// bin is red (core::jetIndex). z_max <= z_min (all heights equal) gives the lowest
/// bin's colour.
std::uint32_t heightColour(float z, float z_min, float z_max, const std::vector<std::uint32_t>& jet);

}  // namespace sim
