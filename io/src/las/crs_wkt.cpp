// io/src/las/crs_wkt.cpp: EPSG codes to OGC WKT through PROJ (crs_wkt.hpp). Each call
// has a PROJ context of its own (PROJ's contexts are not shared between threads), with
// its logging off: a code PROJ does not know is reported through `problem` alone.
#include "crs_wkt.hpp"

#include <proj.h>

#include <memory>

namespace io::detail {

namespace {

struct ContextDeleter {
    void operator()(PJ_CONTEXT* c) const { proj_context_destroy(c); }
};
struct PjDeleter {
    void operator()(PJ* p) const { proj_destroy(p); }
};
using Context = std::unique_ptr<PJ_CONTEXT, ContextDeleter>;
using Pj = std::unique_ptr<PJ, PjDeleter>;

Pj fromEpsg(PJ_CONTEXT* ctx, int code) {
    const std::string text = std::to_string(code);
    return Pj(proj_create_from_database(ctx, "EPSG", text.c_str(), PJ_CATEGORY_CRS, 0, nullptr));
}

}  // namespace

std::string wktForEpsg(int epsg, int vertical_epsg, std::string& problem) {
    problem.clear();
    if (epsg <= 0 || epsg >= 32767) {
        problem = "the GeoTIFF keys give no EPSG code for the CRS";
        return {};
    }
    const Context ctx(proj_context_create());
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
    if (vertical_epsg > 0 && vertical_epsg < 32767) {
        if (Pj vertical = fromEpsg(ctx.get(), vertical_epsg)) {
            const char* name = proj_get_name(crs.get());
            const std::string compound_name = std::string(name ? name : "") + " + " +
                                              (proj_get_name(vertical.get()) ? proj_get_name(vertical.get()) : "");
            if (Pj compound = Pj(proj_create_compound_crs(ctx.get(), compound_name.c_str(), crs.get(), vertical.get())))
                crs = std::move(compound);
        }
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
