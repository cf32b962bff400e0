// io/src/proj_ptr.hpp (internal): PROJ's context and objects owned by unique_ptr, for the
// files that ask PROJ (las/crs_wkt.cpp, geotiff/geotiff_writer.cpp). A context per call:
// PROJ's contexts are not shared between threads.
#pragma once
#include <proj.h>

#include <memory>

namespace io::detail {

struct ProjContextDeleter {
    void operator()(PJ_CONTEXT* c) const { proj_context_destroy(c); }
};
struct ProjDeleter {
    void operator()(PJ* p) const { proj_destroy(p); }
};
using ProjContext = std::unique_ptr<PJ_CONTEXT, ProjContextDeleter>;
using Pj = std::unique_ptr<PJ, ProjDeleter>;

}  // namespace io::detail
