// sim/src/dtm.cpp: the terrain raster as an ESRI ASCII grid, a plain text format
// that GDAL, QGIS, ArcGIS and numpy.loadtxt(skiprows=6) read.
#include <sim/dtm.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>

#include <cstdio>

namespace sim {

std::string dtmAscii(const TerrainGrid& grid, const glm::dvec3& origin) {
    std::string s;
    s.reserve(std::size_t(grid.nx) * std::size_t(grid.ny) * 10 + 256);
    char line[256];
    std::snprintf(line, sizeof line,
                  "ncols %d\nnrows %d\nxllcorner %.6f\nyllcorner %.6f\ncellsize %.6f\nNODATA_value -9999\n", grid.nx,
                  grid.ny, origin.x + grid.x0_m - 0.5 * grid.cell_m, origin.y + grid.y0_m - 0.5 * grid.cell_m,
                  grid.cell_m);
    s += line;
    for (int j = grid.ny - 1; j >= 0; --j) {
        for (int i = 0; i < grid.nx; ++i) {
            std::snprintf(line, sizeof line, i == 0 ? "%.3f" : " %.3f", origin.z + double(grid.at(i, j)));
            s += line;
        }
        s += '\n';
    }
    return s;
}

void writeDtm(const std::filesystem::path& path, const TerrainGrid& grid, const glm::dvec3& origin) {
    if (grid.empty()) throw core::Error("output: " + path.string() + ": no terrain was fitted (the cloud is empty)");
    platform::writeFileAtomic(path, dtmAscii(grid, origin));
}

}  // namespace sim
