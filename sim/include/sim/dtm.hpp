// sim/dtm.hpp: the fitted terrain (a TerrainGrid) as a digital terrain model raster.
#pragma once
#include <sim/ground.hpp>

#include <glm/glm.hpp>

#include <filesystem>
#include <string>

namespace sim {

/// The ESRI ASCII grid (.asc) text of `grid` in world coordinates (local + origin):
/// header ncols, nrows, xllcorner, yllcorner (the lower-left corner of the lower-left
/// cell), cellsize, NODATA_value; then nrows lines of ncols heights in metres, the
/// northernmost (largest y) row first, millimetre precision. Every cell has a height
/// (the unobserved ones interpolated), so NODATA_value never appears.
std::string dtmAscii(const TerrainGrid& grid, const glm::dvec3& origin);

/// Writes dtmAscii() atomically to `path` (platform::writeFileAtomic). Throws core::Error
/// ("output: <path>: ...") on failure, or when the grid is empty.
void writeDtm(const std::filesystem::path& path, const TerrainGrid& grid, const glm::dvec3& origin);

}  // namespace sim
