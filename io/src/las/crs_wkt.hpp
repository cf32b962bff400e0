// io/src/las/crs_wkt.hpp (internal): a CRS known by its EPSG code, as the OGC WKT record
// LAS 1.4 point formats 6-10 need, from PROJ's EPSG database. The LAS reader gives it to
// the writers for a foreign file that declares its CRS only by GeoTIFF keys.
#pragma once
#include <io/las_crs.hpp>

#include <string>

namespace io::detail {

/// WKT 1 (GDAL's flavour, as PDAL writes it) of `crs`'s EPSG code, compounded with its
/// vertical CRS code when it has one. Where the keys state a linear unit other than the
/// EPSG CRS's own (a State Plane CRS in metres whose file is in US survey feet), the
/// axes get the stated unit, as GDAL reads such keys. Empty, with `problem` saying why,
/// when there is no code or PROJ does not know it. Never throws.
std::string wktForCrs(const LasCrs& crs, std::string& problem);

}  // namespace io::detail
