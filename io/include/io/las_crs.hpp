// io/las_crs.hpp: the coordinate reference system a LAS file declares, read from its
// VLRs (LAS 1.4 R15 §2.5): the OGC WKT record (user LASF_Projection, record 2112) or the
// GeoTIFF keys (records 34735 directory, 34736 doubles, 34737 ASCII). What is found is
// the CRS's name and EPSG code and the units of its coordinates, horizontal and vertical
// (a cloud in US survey feet needs its metre-based defaults scaled by 3.28). The parsers
// take the payload bytes and never throw: a record that holds no CRS, or one that cannot
// be read, says why in `problem`. No EPSG database: a CRS the file names only by code
// keeps an empty name, and its units are those the file states.
#pragma once
#include <string>
#include <string_view>

namespace io {

/// A unit of the coordinates: of length (metres > 0) or of angle (geographic CRSs).
struct CrsUnit {
    std::string name;     // "metre", "US survey foot", "foot", "degree", ...; empty: not stated
    int epsg = 0;         // its EPSG code (9001 metre, 9002 foot, 9003 US survey foot, ...); 0 unknown
    double metres = 0.0;  // its length in metres; 0 for an angle or when unknown
    bool angular = false;
    bool stated() const { return !name.empty(); }
};

/// What a LAS file's CRS records say.
struct LasCrs {
    std::string source;  // "wkt", "geotiff", or empty: no CRS was read
    std::string kind;    // "projected", "geographic", "geocentric", "compound", "vertical" or empty
    std::string name;    // as the file names it; empty when it gives only a code
    /// The CRS's EPSG code (AUTHORITY / ID, ProjectedCSTypeGeoKey, GeographicTypeGeoKey);
    /// for a compound CRS without one, its horizontal part's. 0 unknown.
    int epsg = 0;
    CrsUnit horizontal_unit;
    std::string vertical_name;
    int vertical_epsg = 0;
    CrsUnit vertical_unit;
    std::string problem;  // why no CRS was read from the record; empty when one was
};

/// The CRS of an OGC WKT string (WKT 1 as LAS 1.4 and PDAL write it, or WKT 2), ended
/// by its first NUL if it has one.
LasCrs crsFromWkt(std::string_view wkt);

/// The CRS of GeoTIFF keys: the GeoKeyDirectoryTag record's payload (`directory`) and
/// the GeoDoubleParamsTag and GeoAsciiParamsTag payloads (empty when the file has none).
LasCrs crsFromGeoKeys(std::string_view directory, std::string_view doubles, std::string_view ascii);

/// The unit an EPSG unit code names (9001 metre, 9002 foot, 9003 US survey foot, 9036
/// kilometre, 9102 degree, ...): its name and length; a code not in the table keeps its
/// code, "EPSG unit N" as its name and no length.
CrsUnit epsgUnit(int code);

}  // namespace io
