// sim/src/ground_reconstruct.hpp: morphological (geodesic) reconstruction on SMRF's
// rasters, for SmrfOptions::reconstruct: grayscale reconstruction by dilation (Vincent
// 1993, "Morphological grayscale reconstruction in image analysis: applications and
// efficient algorithms", IEEE Trans. Image Processing 2(2):176-201, the hybrid
// algorithm), the h-dome transform built on it, and the three uses SMRF measures:
// the opening by reconstruction, the dome test and the terrain given back up steps.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sim {

/// Grayscale reconstruction by dilation of `marker` under `mask` (both w x h, row-major,
/// finite), 8-connected: each cell ends at the highest level it can reach from a marker
/// cell along a path whose mask never drops below that level. A marker above its mask is
/// first clipped to it. One raster and one anti-raster sweep, then a FIFO of the cells
/// that can still raise a neighbour (each cell queued at most once at a time: at most
/// w x h entries). Deterministic; single-threaded.
void reconstructByDilation(std::vector<float>& marker, const std::vector<float>& mask, int w, int h);

/// `steps` elementary geodesic dilations of `marker` under `mask` (each cell takes the
/// highest of its 3 x 3 cells, then no more than its mask): what reconstructByDilation
/// reaches within `steps` cells. 0 steps: the whole reconstruction. Deterministic.
void geodesicDilation(std::vector<float>& marker, const std::vector<float>& mask, int w, int h, int steps);

/// The h-dome transform of `surface` (w x h): surface - reconstruction of (surface - h_m)
/// under surface. Each cell gets how far it rises, up to h_m, above the highest level
/// from which it can be reached without going down: 0 on a slope that climbs on by h_m,
/// the object's height above its surroundings on an isolated roof or crown (at most h_m).
std::vector<float> hDomes(const std::vector<float>& surface, int w, int h, float h_m);

/// Cells that SMRF's openings called objects (`ground` 0 where `observed`) whose h-dome
/// (hDomes with h_m) is at most `tolerance_m` become ground again: from them the surface
/// climbs on by h_m without a drop of more than tolerance_m (a terrace's upper edge
/// joined to higher terrain), where a roof or a crown stands above its surroundings.
void domeGroundBack(const std::vector<float>& surface, const std::vector<std::uint8_t>& observed,
                    std::vector<std::uint8_t>& ground, int w, int h, float h_m, float tolerance_m);

/// The top-hat by reconstruction: `eroded` (the surface eroded by a small disk) is
/// reconstructed under `surface`; a cell more than `h_m` above it (a part too narrow for
/// the disk that stands above everything it joins: a bush, a car) is no longer ground.
void topHatObjects(const std::vector<float>& surface, std::vector<float>& eroded, std::vector<std::uint8_t>& ground,
                   int w, int h, float h_m);

/// The terrain given back up steps: the reconstruction of min(terrain + tolerance_m,
/// surface) under `surface` reaches, from the cells within tolerance_m of `terrain`,
/// every cell that a path at or above its own level joins to them (the upper edge of a
/// terrace whose top is ground), but not a roof that stands above the ground around it.
/// Observed cells so reached within `steps` cells (0: however far), at most `max_rise_m`
/// above `terrain`, become ground. Returns how many did.
/// With `from_ground`, the seeds are the ground cells' own levels (`surface` where
/// `ground` and `observed`) instead of min(terrain + tolerance_m, surface) everywhere.
std::size_t stepGroundBack(const std::vector<float>& surface, const std::vector<float>& terrain,
                           const std::vector<std::uint8_t>& observed, std::vector<std::uint8_t>& ground, int w, int h,
                           float tolerance_m, float max_rise_m, int steps, bool from_ground);

}  // namespace sim
