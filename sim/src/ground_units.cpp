// sim/src/ground_units.cpp: see sim/ground_units.hpp.
#include <sim/ground_units.hpp>

#include <core/error.hpp>
#include <io/cloud_info.hpp>

#include <cstdio>
#include <string_view>

namespace sim {
namespace {

// The CRS as a message names it: "'NAD83 / New Mexico Central (ftUS)' (EPSG:2903)".
std::string crsText(const io::LasCrs& crs) {
    std::string s = crs.name.empty() ? std::string("a ") + (crs.kind.empty() ? "" : crs.kind + " ") + "CRS"
                                     : "'" + core::printable(crs.name, 80) + "'";
    if (crs.epsg != 0) s += " (EPSG:" + std::to_string(crs.epsg) + ")";
    return s;
}

// The unit's plural for a message: "US survey feet", "metres", "kilometres".
std::string plural(const std::string& name) {
    const std::string_view n = name;
    if (n.empty()) return "metres";
    if (n.ends_with("foot")) return name.substr(0, name.size() - 4) + "feet";
    if (n.ends_with("metre") || n.ends_with("mile") || n.ends_with("degree") || n.ends_with("radian"))
        return name + "s";
    return "units of " + core::printable(name, 40);
}

std::string withLength(const std::string& name, double metres) {
    if (metres == 1.0) return plural(name);
    char length[32];
    std::snprintf(length, sizeof length, "%.7g", metres);
    return plural(name) + " (" + length + " m)";
}

// The lengths of a CRS's units, its horizontal one a known length or not stated: the
// vertical unit where it is a known length, else the horizontal one for z too.
CoordinateUnits lengthsOf(const io::LasCrs& crs) {
    CoordinateUnits u;
    const io::CrsUnit& h = crs.horizontal_unit;
    const io::CrsUnit& z = crs.vertical_unit;
    const io::CrsUnit& v = z.stated() && !z.angular && z.metres > 0.0 ? z : h;
    if (h.stated()) {
        u.horizontal_m = h.metres;
        u.horizontal_name = h.name;
    }
    if (v.stated()) {
        u.vertical_m = v.metres;
        u.vertical_name = v.name;
    }
    return u;
}

}  // namespace

CoordinateUnits coordinateUnits(const io::LasCrs& crs, const std::filesystem::path& file, const char* context) {
    if (crs.source.empty()) return {};  // no CRS: metres, as the generator writes
    const std::string where = std::string(context) + ": " + core::printable(file.string(), 400) + ": ";
    const io::CrsUnit& h = crs.horizontal_unit;
    if (h.angular)
        throw core::Error(where + "its CRS " + crsText(crs) + " is geographic (x and y in " + plural(h.name) +
                          "), and distances in degrees cannot take options in metres; allowed a projected CRS in "
                          "metres or feet (reproject it, e.g. with PDAL's filters.reprojection)");
    if (h.stated() && h.metres <= 0.0)
        throw core::Error(where + "its CRS " + crsText(crs) + " gives x and y in " + core::printable(h.name, 40) +
                          ", a unit of unknown length; allowed a CRS in metres, feet or another known length");
    return lengthsOf(crs);
}

CoordinateUnits readCoordinateUnits(const std::filesystem::path& file, const char* context) {
    return coordinateUnits(io::readCloudCrs(file, context), file, context);
}

std::string describe(const CoordinateUnits& u) {
    const std::string h = withLength(u.horizontal_name, u.horizontal_m);
    const std::string v = withLength(u.vertical_name, u.vertical_m);
    if (h == v) return h;
    return h + " horizontally, " + v + " vertically";
}

std::string describeUnits(const io::LasCrs& crs) {
    if (crs.source.empty()) return {};
    const io::CrsUnit& h = crs.horizontal_unit;
    if (h.angular) return plural(h.name) + " (geographic" + (crs.name.empty() ? "" : " " + crsText(crs)) + ")";
    if (h.stated() && h.metres <= 0.0) return core::printable(h.name, 40) + " (length unknown)";
    const CoordinateUnits u = lengthsOf(crs);
    return u.horizontal_name.empty() && u.vertical_name.empty() ? std::string() : describe(u);
}

namespace {

std::string symbolOf(const io::CrsUnit& u) {
    switch (u.epsg) {
        case 9001: return "m";
        case 9002: return "ft";
        case 9003: return "US ft";
        case 9102:
        case 9122: return "deg";
        default: break;
    }
    if (u.name.empty() || u.name == "metre" || u.name == "meter") return "m";
    if (u.name == "foot") return "ft";
    if (u.name == "US survey foot") return "US ft";
    if (u.name == "degree") return "deg";
    return core::printable(u.name, 24);
}

}  // namespace

UnitSymbols unitSymbols(const io::LasCrs& crs) {
    UnitSymbols s;
    if (crs.source.empty()) return s;
    const io::CrsUnit& h = crs.horizontal_unit;
    const io::CrsUnit& z = crs.vertical_unit;
    s.horizontal = symbolOf(h);
    s.vertical = symbolOf(z.stated() && !z.angular && z.metres > 0.0 ? z : h);
    return s;
}

GroundFileOptions inUnits(const GroundFileOptions& o, const CoordinateUnits& u) {
    GroundFileOptions r = o;
    const double h = u.horizontal_m, v = u.vertical_m;
    r.smrf.cell_m /= h;
    r.smrf.window_m /= h;
    r.smrf.threshold_m /= v;
    r.smrf.low_outlier_m /= v;
    // A rise over a run: (dz / v) / (dxy / h). The scalar times that slope is a height:
    // (scalar' * slope * h / v) = scalar * slope / v, so scalar' = scalar / h.
    r.smrf.slope *= h / v;
    r.smrf.scalar /= h;
    r.csf.cloth_m /= h;
    r.csf.threshold_m /= v;
    r.csf.low_outlier_m /= v;
    r.csf.slope_join_m /= v;
    // The raster's own fixed heights (the ground thickness's windows) follow the heights' unit.
    r.smrf.z_unit_m *= v;
    r.csf.z_unit_m *= v;
    return r;
}

}  // namespace sim
