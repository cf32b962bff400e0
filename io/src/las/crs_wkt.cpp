// io/src/las/crs_wkt.cpp: EPSG codes to OGC WKT through PROJ (crs_wkt.hpp). Each call
// has a PROJ context of its own (PROJ's contexts are not shared between threads), with
// its logging off: a code PROJ does not know is reported through `problem` alone.
#include "crs_wkt.hpp"

#include "../proj_ptr.hpp"

#include <cmath>
#include <memory>

namespace io::detail {

namespace {

Pj fromEpsg(PJ_CONTEXT* ctx, int code) {
    const std::string text = std::to_string(code);
    return Pj(proj_create_from_database(ctx, "EPSG", text.c_str(), PJ_CATEGORY_CRS, 0, nullptr));
}

// `pj` with its axes in `unit` where the unit is stated, of length, and not the one
// its axes have: the keys' ProjLinearUnits or VerticalUnits win over the EPSG CRS's.
Pj withUnit(PJ_CONTEXT* ctx, Pj pj, const CrsUnit& unit) {
    if (!unit.stated() || unit.angular || !(unit.metres > 0.0)) return pj;
    const Pj cs(proj_crs_get_coordinate_system(ctx, pj.get()));
    double factor = 0.0;
    if (!cs || !proj_cs_get_axis_info(ctx, cs.get(), 0, nullptr, nullptr, nullptr, &factor, nullptr, nullptr, nullptr))
        return pj;
    if (std::fabs(factor - unit.metres) <= 1e-12 * unit.metres) return pj;
    const std::string code = unit.epsg > 0 ? std::to_string(unit.epsg) : std::string();
    Pj altered(proj_crs_alter_cs_linear_unit(ctx, pj.get(), unit.name.c_str(), unit.metres,
                                             code.empty() ? nullptr : "EPSG", code.empty() ? nullptr : code.c_str()));
    return altered ? std::move(altered) : std::move(pj);
}

// A name from the file (the keys' vertical citation) as the WKT may hold it: printable
// ASCII without the quote that ends a WKT string, at most 80 characters; "unknown" when
// nothing is left. Control bytes or a newline would make a record of several lines.
std::string wktName(const std::string& text) {
    std::string name;
    for (const char c : text)
        if (c >= 0x20 && c < 0x7f && c != '"' && name.size() < 80) name.push_back(c);
    return name.empty() ? "unknown" : name;
}

}  // namespace

std::string wktForCrs(const LasCrs& las, std::string& problem) {
    problem.clear();
    const int epsg = las.epsg;
    if (epsg <= 0 || epsg >= 32767) {
        problem = "the GeoTIFF keys give no EPSG code for the CRS";
        return {};
    }
    const ProjContext ctx(proj_context_create());
    if (!ctx) {
        problem = "PROJ could not be started";
        return {};
    }
    proj_log_level(ctx.get(), PJ_LOG_NONE);
    Pj crs = fromEpsg(ctx.get(), epsg);
    if (!crs) {
        problem = "EPSG:" + std::to_string(epsg) + " is not in PROJ's database";
        return {};
    }
    crs = withUnit(ctx.get(), std::move(crs), las.horizontal_unit);
    // The vertical CRS: its code's, in the stated unit; else, where the keys state only a
    // vertical unit, an unknown datum in that unit (as GDAL reads such keys), so that the
    // heights' unit is not lost.
    Pj vertical;
    if (las.vertical_epsg > 0 && las.vertical_epsg < 32767) vertical = fromEpsg(ctx.get(), las.vertical_epsg);
    if (vertical) {
        vertical = withUnit(ctx.get(), std::move(vertical), las.vertical_unit);
    } else if (las.vertical_unit.stated() && !las.vertical_unit.angular && las.vertical_unit.metres > 0.0) {
        const std::string name = wktName(las.vertical_name);
        vertical = Pj(proj_create_vertical_crs(ctx.get(), name.c_str(), "unknown", las.vertical_unit.name.c_str(),
                                               las.vertical_unit.metres));
    }
    if (vertical) {
        const char* h_name = proj_get_name(crs.get());
        const char* v_name = proj_get_name(vertical.get());
        const std::string name = std::string(h_name ? h_name : "") + " + " + (v_name ? v_name : "");
        if (Pj compound = Pj(proj_create_compound_crs(ctx.get(), name.c_str(), crs.get(), vertical.get())))
            crs = std::move(compound);
    }
    const char* const options[] = {"MULTILINE=NO", nullptr};
    const char* wkt = proj_as_wkt(ctx.get(), crs.get(), PJ_WKT1_GDAL, options);
    if (!wkt) {
        problem = "PROJ cannot write EPSG:" + std::to_string(epsg) + " as WKT 1";
        return {};
    }
    return wkt;
}

}  // namespace io::detail
