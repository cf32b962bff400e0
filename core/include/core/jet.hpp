// core/jet.hpp: the jet colour map of the height colouring (paper §III-C): one table for
// everything that colours by height, the generator's files (sim/colour.hpp) and the
// viewer's "height" colours (uploaded to the GPU as a 1D texture), so both show the same.
#pragma once
#include <cstdint>
#include <vector>

namespace core {

/// MATLAB's jet(m) as 0x00RRGGBB (packRgb), index 0 = dark blue ... m-1 = dark red,
/// channels rounded from [0, 1] to [0, 255]. Needs m >= 1 (callers validate; the paper
/// uses 64).
std::vector<std::uint32_t> jetTable(int entries);

/// Index into an m-entry jetTable() of height z in [z_min, z_max]: the height falls in bin
/// floor((z - z_min) / (z_max - z_min) * m) clamped to [0, m-1], reversed (m-1-bin) so the
/// lowest bin is red and the highest blue. z_max <= z_min (all heights equal) gives m-1.
/// Computed in double.
int jetIndex(double z, double z_min, double z_max, int entries);

}  // namespace core
