// io/src/las/crs_wkt.hpp (internal): a CRS known by its EPSG code, as the OGC WKT record
// LAS 1.4 point formats 6-10 need, from PROJ's EPSG database. The LAS reader gives it to
// the writers for a foreign file that declares its CRS only by GeoTIFF keys.
#pragma once
#include <string>

namespace io::detail {

/// WKT 1 (GDAL's flavour, as PDAL writes it) of EPSG `epsg`, compounded with the vertical
/// CRS EPSG `vertical_epsg` when that is not 0. Empty, with `problem` saying why, when
/// PROJ does not know the code. Never throws.
std::string wktForEpsg(int epsg, int vertical_epsg, std::string& problem);

}  // namespace io::detail
