// sim/src/dtm.cpp: the terrain raster as an ESRI ASCII grid, a plain text format
// that GDAL, QGIS, ArcGIS and numpy.loadtxt(skiprows=6) read.
#include <sim/dtm.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>

#include "memory_plan.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>

namespace sim {
namespace {

std::string asciiHeader(int columns, int rows, double x_ll, double y_ll, double cell) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "ncols %d\nnrows %d\nxllcorner %.6f\nyllcorner %.6f\ncellsize %.6f\nNODATA_value -9999\n", columns,
                  rows, x_ll, y_ll, cell);
    return line;
}

// One row of heights (z0 + each), millimetre precision, separated by spaces; a NaN (a
// cell no piece of a mosaic holds) is written as the NODATA value.
void appendRow(std::string& s, const float* z, int n, double z0) {
    char value[64];
    for (int i = 0; i < n; ++i) {
        if (std::isnan(z[i]))
            std::snprintf(value, sizeof value, i == 0 ? "-9999" : " -9999");
        else
            std::snprintf(value, sizeof value, i == 0 ? "%.3f" : " %.3f", z0 + double(z[i]));
        s += value;
    }
    s += '\n';
}

}  // namespace

std::string dtmAscii(const TerrainGrid& grid, const glm::dvec3& origin) {
    std::string s;
    s.reserve(std::size_t(grid.nx) * std::size_t(grid.ny) * 10 + 256);
    s += asciiHeader(grid.nx, grid.ny, origin.x + grid.x0_m - 0.5 * grid.cell_m,
                     origin.y + grid.y0_m - 0.5 * grid.cell_m, grid.cell_m);
    for (int j = grid.ny - 1; j >= 0; --j)
        appendRow(s, grid.z_m.data() + std::size_t(j) * std::size_t(grid.nx), grid.nx, origin.z);
    return s;
}

void writeDtm(const std::filesystem::path& path, const TerrainGrid& grid, const glm::dvec3& origin) {
    if (grid.empty()) throw core::Error("output: " + path.string() + ": no terrain was fitted (the cloud is empty)");
    platform::writeFileAtomic(path, dtmAscii(grid, origin));
}

DtmMosaic::DtmMosaic(const std::filesystem::path& scratch_dir, std::string what, double cell, const glm::dvec3& frame)
    : what_(std::move(what)), cell_(cell), frame_(frame), scratch_dir_(scratch_dir), heights_(scratch_dir, what_) {}

void DtmMosaic::add(const TerrainGrid& grid, const glm::dvec2& lo, const glm::dvec2& hi) {
    if (grid.empty()) return;
    if (grid.cell_m != cell_)
        throw core::Error("output: " + what_ + ": a terrain of " + std::to_string(grid.cell_m) +
                          " cells on a lattice of " + std::to_string(cell_));
    // The lattice index of the grid's first cell, and the cells whose centre lies in [lo, hi).
    const double big = 1e9;
    const auto lattice = [&](double centre) { return int(std::llround(centre / cell_ - 0.5)); };
    const auto first = [&](double v) { return int(std::clamp(std::ceil(v / cell_ - 0.5), -big, big)); };
    const int gi0 = lattice(grid.x0_m), gj0 = lattice(grid.y0_m);
    const int i0 = std::max(gi0, first(lo.x)), i1 = std::min(gi0 + grid.nx - 1, first(hi.x) - 1);
    const int j0 = std::max(gj0, first(lo.y)), j1 = std::min(gj0 + grid.ny - 1, first(hi.y) - 1);
    if (i0 > i1 || j0 > j1) return;
    const std::lock_guard lock(mutex_);
    pieces_.push_back({i0, i1, j0, j1, heights_.size()});
    for (int j = j0; j <= j1; ++j)
        heights_.append(grid.z_m.data() + std::size_t(j - gj0) * std::size_t(grid.nx) + std::size_t(i0 - gi0),
                        std::size_t(i1 - i0 + 1) * sizeof(float));
    if (pieces_.size() == 1) {
        i0_ = i0, i1_ = i1, j0_ = j0, j1_ = j1;
    } else {
        i0_ = std::min(i0_, i0), i1_ = std::max(i1_, i1), j0_ = std::min(j0_, j0), j1_ = std::max(j1_, j1);
    }
}

void DtmMosaic::write(std::FILE* out) {
    if (pieces_.empty()) throw core::Error("output: " + what_ + ": no terrain was fitted (no point was read)");
    heights_.flush();
    const int columns = i1_ - i0_ + 1;
    const std::string header =
        asciiHeader(columns, j1_ - j0_ + 1, frame_.x + double(i0_) * cell_, frame_.y + double(j0_) * cell_, cell_);
    const auto put = [&](const std::string& s) {
        if (std::fwrite(s.data(), 1, s.size(), out) != s.size())
            throw core::Error("output: " + what_ + ": write failed: " + std::strerror(errno));
    };
    // Each value takes at least 6 bytes ("0.000" or "-9999" and a space or the newline).
    const std::uint64_t cells = std::uint64_t(columns) * std::uint64_t(j1_ - j0_ + 1);
    checkFreeSpace(scratch_dir_, header.size() + 6 * cells, "the grid");
    put(header);
    std::vector<float> row(static_cast<std::size_t>(columns));
    std::string text;
    for (int j = j1_; j >= j0_; --j) {
        readRow(j, row.data());
        text.clear();
        appendRow(text, row.data(), columns, frame_.z);
        put(text);
    }
    if (std::fflush(out) != 0) throw core::Error("output: " + what_ + ": write failed: " + std::strerror(errno));
}

void DtmMosaic::readRow(int j, float* row) {
    std::fill(row, row + (i1_ - i0_ + 1), std::numeric_limits<float>::quiet_NaN());
    for (const Piece& p : pieces_) {
        if (j < p.j0 || j > p.j1) continue;
        const std::size_t width = std::size_t(p.i1 - p.i0 + 1);
        heights_.readAt(row + (p.i0 - i0_), width * sizeof(float),
                        p.offset + std::uint64_t(j - p.j0) * width * sizeof(float));
    }
}

bool DtmMosaic::writeGeoTiff(std::FILE* out, const std::vector<io::GeoKey>& keys, io::TiffKind kind) {
    if (pieces_.empty()) throw core::Error("output: " + what_ + ": no terrain was fitted (no point was read)");
    heights_.flush();
    io::GeoTiffGrid g;
    g.columns = i1_ - i0_ + 1;
    g.rows = j1_ - j0_ + 1;
    g.west = frame_.x + double(i0_) * cell_;
    g.north = frame_.y + double(j1_ + 1) * cell_;
    g.cell = cell_;
    g.deflate = true;
    g.kind = kind;
    checkFreeSpace(scratch_dir_, io::geoTiffBytes(g, keys), "the grid");
    std::vector<float> local(static_cast<std::size_t>(g.columns));
    io::writeGeoTiff(
        out, g, keys,
        [&](int r, float* values) {
            readRow(j1_ - r, local.data());
            for (std::size_t i = 0; i < local.size(); ++i) values[i] = float(frame_.z + double(local[i]));
        },
        what_);
    return io::geoTiffIsBig(g, keys);
}

void dtmGeoTiff(std::FILE* out, const TerrainGrid& grid, const glm::dvec3& origin, const std::vector<io::GeoKey>& keys,
                const std::string& what) {
    if (grid.empty()) throw core::Error("output: " + what + ": no terrain was fitted (the cloud is empty)");
    io::GeoTiffGrid g;
    g.columns = grid.nx;
    g.rows = grid.ny;
    g.west = origin.x + grid.x0_m - 0.5 * grid.cell_m;
    g.north = origin.y + grid.y0_m + (double(grid.ny) - 0.5) * grid.cell_m;
    g.cell = grid.cell_m;
    g.deflate = true;
    io::writeGeoTiff(
        out, g, keys,
        [&](int r, float* values) {
            const float* z = grid.z_m.data() + std::size_t(grid.ny - 1 - r) * std::size_t(grid.nx);
            for (int i = 0; i < grid.nx; ++i) values[i] = float(origin.z + double(z[i]));
        },
        what);
}

}  // namespace sim
