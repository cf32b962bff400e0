// sim/ground_units.hpp: the units of a file's coordinates, from the CRS it declares
// (io::readCloudCrs: its OGC WKT record or GeoTIFF keys), and the ground filter's options,
// given in metres, turned into those units. A survey in US survey feet keeps its
// coordinates; its 0.5 m threshold becomes 1.64 ft rather than 0.5 ft. A file without a
// CRS, or without a stated unit, is taken to be in metres.
#pragma once
#include <io/las_crs.hpp>
#include <sim/ground_file.hpp>

#include <filesystem>
#include <string>

namespace sim {

/// The length of a file's coordinate units: x and y (horizontal) and z (vertical).
struct CoordinateUnits {
    double horizontal_m = 1.0;    // metres per horizontal unit
    double vertical_m = 1.0;      // metres per vertical unit
    std::string horizontal_name;  // the unit as the CRS names it ("US survey foot"); empty: metres assumed
    std::string vertical_name;    // likewise; the horizontal unit when the CRS states no vertical one
    bool metres() const { return horizontal_m == 1.0 && vertical_m == 1.0; }
};

/// The units of `crs`'s coordinates: its horizontal unit, and its vertical unit where it
/// states one, else the horizontal one for z too (as LAS producers write z). Throws
/// core::Error("<context>: <file>: ...") naming the CRS when its horizontal unit is an
/// angle (a geographic CRS: distances in degrees cannot take options in metres) or a
/// length the file does not give; allowed a CRS in metres, feet or another known length.
CoordinateUnits coordinateUnits(const io::LasCrs& crs, const std::filesystem::path& file, const char* context);

/// coordinateUnits of the CRS `file` declares (io::readCloudCrs: its header and VLRs
/// only); metres for a file without one. Throws core::Error as both.
CoordinateUnits readCoordinateUnits(const std::filesystem::path& file, const char* context);

/// "US survey feet (0.3048006 m)", or "metres horizontally, US survey feet (0.3048006 m)
/// vertically" when the two differ.
std::string describe(const CoordinateUnits& u);

/// The units of `crs`'s coordinates for a display, never throwing: "US survey feet
/// (0.3048006 m)", "degrees (geographic 'WGS 84')"; empty when it has no CRS or states no unit.
std::string describeUnits(const io::LasCrs& crs);

/// Short labels of `crs`'s horizontal and vertical units for a number shown to a user:
/// "m", "ft", "US ft", "deg", or the unit's own name when it has no usual symbol; "m" for
/// a unit not stated (no CRS: metres, as the generator writes). The vertical one is the
/// horizontal one where the CRS states no vertical length, as describeUnits reads it.
struct UnitSymbols {
    std::string horizontal = "m";
    std::string vertical = "m";
};
UnitSymbols unitSymbols(const io::LasCrs& crs);

/// `o` (every length in metres) in units `u`: the horizontal lengths (SMRF's cell and
/// window, CSF's cloth) divided by horizontal_m, the vertical ones (thresholds, the
/// low-outlier gap) by vertical_m, SMRF's slope (a rise over a run) and its scalar (a
/// height per unit of slope) so that they mean what they meant in metres; z_unit_m (the
/// raster's own fixed heights, the ground thickness's windows) times vertical_m.
GroundFileOptions inUnits(const GroundFileOptions& o, const CoordinateUnits& u);

}  // namespace sim
