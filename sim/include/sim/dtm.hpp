// sim/dtm.hpp: the fitted terrain (a TerrainGrid) as a digital terrain model raster.
#pragma once
#include <sim/ground.hpp>

#include <io/geotiff.hpp>
#include <platform/scratch_file.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

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

/// Writes `grid` in world coordinates (local + origin) to `out` as a GeoTIFF
/// (io::writeGeoTiff, with `keys`): the northernmost row first, as dtmAscii. Throws
/// core::Error("output: <what>: ...") on failure, or when the grid is empty.
void dtmGeoTiff(std::FILE* out, const TerrainGrid& grid, const glm::dvec3& origin, const std::vector<io::GeoKey>& keys,
                const std::string& what);

/// A DTM put together from pieces of terrains fitted on one cell lattice (`ladarvr ground
/// --dtm`: one fit's whole raster, or each tile's own square). Cell (i, j) of the lattice
/// has its centre at frame + ((i + 0.5) cell, (j + 0.5) cell); a TerrainGrid fitted in
/// that frame lies on it. The pieces' heights go to one scratch file as they come, so the
/// memory is one row of the output whatever the survey's size.
class DtmMosaic {
  public:
    /// `scratch_dir`: where the scratch file goes (the DTM's folder); `what`: the output
    /// named in messages. Throws as platform::ScratchFile.
    DtmMosaic(const std::filesystem::path& scratch_dir, std::string what, double cell, const glm::dvec3& frame);

    /// Keeps the heights of `grid`'s cells whose centres lie in [lo, hi) (frame
    /// coordinates; an empty box or grid keeps none). `grid.cell_m` must be the lattice's
    /// cell (else core::Error). Pieces must not overlap. Several threads may add at once.
    void add(const TerrainGrid& grid, const glm::dvec2& lo, const glm::dvec2& hi);

    /// Cells of the box around every piece (0 x 0 before any).
    int columns() const { return pieces_.empty() ? 0 : i1_ - i0_ + 1; }
    int rows() const { return pieces_.empty() ? 0 : j1_ - j0_ + 1; }

    /// Writes the box around every piece as an ESRI ASCII grid (dtmAscii's layout, in the
    /// frame's units), NODATA_value -9999 in its cells no piece holds. Throws
    /// core::Error("output: <what>: ...") when there is no piece or a write fails, and
    /// core::Error("output: <folder>: ...") when the scratch folder's filesystem has less
    /// free than the grid takes at least (6 bytes a cell).
    void write(std::FILE* out);
    /// The same box as a GeoTIFF (io::writeGeoTiff with `keys`, a classic TIFF or a BigTIFF
    /// as `kind` says), its cells no piece holds as the file's nodata value; the same
    /// errors (4 bytes a cell). Returns whether it wrote a BigTIFF.
    bool writeGeoTiff(std::FILE* out, const std::vector<io::GeoKey>& keys, io::TiffKind kind = io::TiffKind::automatic);

    /// What the run does with the grid once every piece is in, before the cloud's output
    /// is renamed into place (so that a grid that cannot be written stops the run while
    /// the cloud can still be discarded): set by the caller, called by complete().
    std::function<void(DtmMosaic&)> on_complete;
    /// Called by the classifier when the last piece is in, before the cloud lands.
    void complete() {
        if (on_complete) on_complete(*this);
    }

  private:
    // Row j of the lattice (frame heights, NaN where no piece holds a cell) into `row`.
    void readRow(int j, float* row);

    struct Piece {
        int i0, i1, j0, j1;  // the lattice cells held, inclusive
        std::uint64_t offset;
    };
    std::string what_;
    double cell_;
    glm::dvec3 frame_;
    std::filesystem::path scratch_dir_;  // the grid's folder
    std::mutex mutex_;
    platform::ScratchFile heights_;
    std::vector<Piece> pieces_;
    int i0_ = 0, i1_ = -1, j0_ = 0, j1_ = -1;
};

}  // namespace sim
