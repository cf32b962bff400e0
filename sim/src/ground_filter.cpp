// sim/src/ground_filter.cpp: the ground filter seams: method names, the factories, the
// checks shared by every filter, and the terrain raster's interpolation.
#include "ground_internal.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace sim {

void failGroundOption(const char* parameter, double value, const char* allowed) {
    std::ostringstream s;
    s << "ground: " << parameter << " = " << value << ": allowed " << allowed;
    throw core::Error(s.str());
}

const char* groundMethodName(GroundMethod m) {
    switch (m) {
        case GroundMethod::Ransac: return "ransac";
        case GroundMethod::Smrf: return "smrf";
        case GroundMethod::Csf: return "csf";
    }
    return "ransac";
}

GroundMethod parseGroundMethod(std::string_view text, std::string_view context) {
    if (text == "ransac") return GroundMethod::Ransac;
    if (text == "smrf") return GroundMethod::Smrf;
    if (text == "csf") return GroundMethod::Csf;
    throw core::Error(std::string(context) + " '" + std::string(text) + "': allowed ransac, smrf, csf");
}

void validate(const GroundChoice& o) {
    validate(o.ransac);
    validate(o.smrf);
    validate(o.csf);
}

bool isPerView(GroundMethod m) { return m == GroundMethod::Ransac; }

std::unique_ptr<const ViewGroundFilter> makeViewFilter(const GroundChoice& o) {
    if (o.method == GroundMethod::Ransac) return makeRansacFilter(o.ransac);
    return nullptr;
}

std::unique_ptr<const CloudGroundFilter> makeCloudFilter(const GroundChoice& o) {
    switch (o.method) {
        case GroundMethod::Ransac: return nullptr;
        case GroundMethod::Smrf: return makeSmrfFilter(o.smrf);
        case GroundMethod::Csf: return makeCsfFilter(o.csf);
    }
    return nullptr;
}

double TerrainGrid::heightAt(double x, double y) const {
    if (empty()) return 0.0;
    const double fx = std::clamp((x - x0_m) / cell_m, 0.0, double(nx - 1));
    const double fy = std::clamp((y - y0_m) / cell_m, 0.0, double(ny - 1));
    const int i0 = std::min(int(fx), std::max(nx - 2, 0)), j0 = std::min(int(fy), std::max(ny - 2, 0));
    const int i1 = std::min(i0 + 1, nx - 1), j1 = std::min(j0 + 1, ny - 1);
    const double tx = fx - i0, ty = fy - j0;
    const double low = (1 - tx) * at(i0, j0) + tx * at(i1, j0);
    const double high = (1 - tx) * at(i0, j1) + tx * at(i1, j1);
    return (1 - ty) * low + ty * high;
}

double TerrainGrid::slopeAt(double x, double y) const {
    if (empty()) return 0.0;
    const int i = int(std::lround(std::clamp((x - x0_m) / cell_m, 0.0, double(nx - 1))));
    const int j = int(std::lround(std::clamp((y - y0_m) / cell_m, 0.0, double(ny - 1))));
    const int il = std::max(i - 1, 0), ir = std::min(i + 1, nx - 1);
    const int jl = std::max(j - 1, 0), jr = std::min(j + 1, ny - 1);
    const double dx = ir > il ? (at(ir, j) - at(il, j)) / ((ir - il) * cell_m) : 0.0;
    const double dy = jr > jl ? (at(i, jr) - at(i, jl)) / ((jr - jl) * cell_m) : 0.0;
    return std::hypot(dx, dy);
}

}  // namespace sim
