// io/geotiff.hpp: a grid of heights as a GeoTIFF (TIFF 6.0 with the GeoTIFF 1.1 tags),
// the raster GIS open first: one band of 32-bit floats, one row per strip uncompressed, or
// rows of up to 64 KiB a strip compressed with Deflate and the floating-point predictor,
// its place given by the pixel scale and one tie point at the top-left corner, its CRS by
// GeoTIFF keys (EPSG codes where the CRS has them, found through PROJ), cells without a
// height as GDAL's nodata value. A classic TIFF (32-bit offsets, at most 4 GiB, read by
// every TIFF reader), or a BigTIFF (64-bit offsets, read by libtiff 4 and so GDAL, QGIS
// and Pillow, and by geotiff.js) for a grid that a classic file might not hold. Streamed:
// the caller hands the rows in order, so the memory is one strip whatever the grid's size.
#pragma once
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace io {

/// Which TIFF a grid is written as.
enum class TiffKind {
    automatic,  // classic, unless the file might pass classic TIFF's 4 GiB (with Deflate: zlib's bound)
    classic,    // always classic: a grid whose file might pass 4 GiB is refused
    big,        // always BigTIFF
};

/// What the file says besides its heights.
struct GeoTiffGrid {
    int columns = 0;
    int rows = 0;
    double west = 0.0;     // world x of the grid's left edge (the first column's left side)
    double north = 0.0;    // world y of the grid's top edge (the first row's upper side)
    double cell = 0.0;     // a cell's side, in the CRS's horizontal unit
    bool deflate = false;  // strips of rows compressed with Deflate and the floating-point predictor
    TiffKind kind = TiffKind::automatic;
};

/// The value written for a cell without a height, declared in the GDAL_NODATA tag.
inline constexpr float kGeoTiffNoData = -9999.0f;

/// One GeoTIFF key as written: its id and its value (a SHORT, or text in GeoAsciiParams).
struct GeoKey {
    std::uint16_t id = 0;
    std::uint16_t value = 0;  // for a text key, 0
    std::string text;         // for a text key (a citation), else empty
};

/// The GeoTIFF keys of `wkt` (GeoTIFF 1.1 §7): the model type (projected, geographic), the
/// raster type (pixel is area), the horizontal CRS's EPSG code (ProjectedCSTypeGeoKey or
/// GeographicTypeGeoKey), or 32767 (user-defined) with its name as the citation and its
/// linear unit's code; the vertical CRS's code (VerticalCSTypeGeoKey) or its name and unit
/// where a compound or vertical CRS has one. A code is the WKT's own (AUTHORITY / ID), else
/// the one PROJ identifies with full confidence. Empty for an empty WKT, and for one PROJ
/// cannot read (`problem` says why; empty otherwise). Never throws.
std::vector<GeoKey> geoKeysForWkt(std::string_view wkt, std::string& problem);

/// Whether `grid` with `keys` is written as a BigTIFF (`grid.kind`; automatic: when its
/// classic file's size, as geoTiffBytes gives it, passes 4 GiB - 1).
bool geoTiffIsBig(const GeoTiffGrid& grid, const std::vector<GeoKey>& keys);

/// The file's size in bytes for `grid` with `keys` (its header, tags and heights, in the
/// kind geoTiffIsBig says); with `grid.deflate`, the most it can take (zlib's bound on
/// each strip).
std::uint64_t geoTiffBytes(const GeoTiffGrid& grid, const std::vector<GeoKey>& keys);

/// Writes `grid` to `out` with `keys` (geoKeysForWkt's; none: no GeoTIFF keys, the grid
/// placed without a CRS): `row(r, values)` fills row r (0 the northernmost) with `columns`
/// heights, NaN for a cell without one (written as kGeoTiffNoData). Throws
/// core::Error("output: <what>: ...") when the sizes are not > 0, the corner or the cell
/// not finite (the cell > 0), when a classic TIFF is asked for (TiffKind::classic) and the
/// file might pass its 4 GiB, or when a write fails.
void writeGeoTiff(std::FILE* out, const GeoTiffGrid& grid, const std::vector<GeoKey>& keys,
                  const std::function<void(int, float*)>& row, const std::string& what);

}  // namespace io
