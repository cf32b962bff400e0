// sim/src/scene_from_cloud_vehicle.cpp: the vehicle of `scene from-cloud` put on the
// survey's ground: a spot (given, or drawn) where the plane fitted to the terrain under
// its footprint is flat and smooth enough and no box stands within the clearance; the
// vehicle then yawed, tilted to that plane (pitch along its length, roll across) and
// lowered until its bottom centre lies on it, so its height follows the terrain.
#include "scene_from_cloud_internal.hpp"

#include <core/error.hpp>
#include <core/random.hpp>
#include <core/scene.hpp>
#include <io/scene_file.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sim::detail {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Plane {
    double z = 0, gx = 0, gy = 0;  // height at the centre, rise per metre along x and y
    double roughness_m = 0;
    double top_m = 0;  // the highest terrain under the footprint
};

// The least-squares plane through the terrain's heights sampled over the rotated
// footprint (half sizes hl along the vehicle's x, hw across), centred at c.
Plane fitPlane(const TerrainMesh& t, const glm::dvec2& c, double yaw_rad, double hl, double hw) {
    const double cs = std::cos(yaw_rad), sn = std::sin(yaw_rad);
    const double step = std::min(0.5, t.cell_m / 2);
    const int nu = std::max(2, int(std::ceil(2 * hl / step)) + 1), nv = std::max(2, int(std::ceil(2 * hw / step)) + 1);
    std::vector<glm::dvec3> samples;
    samples.reserve(std::size_t(nu) * std::size_t(nv));
    double sxx = 0, sxy = 0, syy = 0, sx = 0, sy = 0, sz = 0, sxz = 0, syz = 0;
    for (int a = 0; a < nu; ++a)
        for (int b = 0; b < nv; ++b) {
            const double u = -hl + 2 * hl * a / (nu - 1), v = -hw + 2 * hw * b / (nv - 1);
            const double dx = u * cs - v * sn, dy = u * sn + v * cs;
            const double z = t.heightAt(c.x + dx, c.y + dy);
            samples.push_back({dx, dy, z});
            sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sx += dx, sy += dy, sz += z, sxz += dx * z, syz += dy * z;
        }
    const double n = double(samples.size());
    // Normal equations of z = z0 + gx dx + gy dy with centred sums.
    const double cxx = sxx - sx * sx / n, cxy = sxy - sx * sy / n, cyy = syy - sy * sy / n;
    const double cxz = sxz - sx * sz / n, cyz = syz - sy * sz / n;
    const double det = cxx * cyy - cxy * cxy;
    Plane p;
    if (std::abs(det) > 1e-12) {
        p.gx = (cxz * cyy - cyz * cxy) / det;
        p.gy = (cyz * cxx - cxz * cxy) / det;
    }
    p.z = (sz - p.gx * sx - p.gy * sy) / n;
    p.top_m = samples.front().z;
    for (const glm::dvec3& s : samples) {
        p.roughness_m = std::max(p.roughness_m, std::abs(s.z - (p.z + p.gx * s.x + p.gy * s.y)));
        p.top_m = std::max(p.top_m, s.z);
    }
    return p;
}

// Whether a box of `boxes` (sorted by i, j, k) stands over the axis-aligned square
// around c of half sizes ex, ey, above `floor_m` and below `ceiling_m`.
bool boxNear(const std::vector<std::array<std::int32_t, 3>>& boxes, double voxel_m, const glm::dvec2& c, double ex,
             double ey, double floor_m, double ceiling_m) {
    const auto i0 = std::int32_t(std::floor((c.x - ex) / voxel_m)), i1 = std::int32_t(std::floor((c.x + ex) / voxel_m));
    const auto j0 = std::int32_t(std::floor((c.y - ey) / voxel_m)), j1 = std::int32_t(std::floor((c.y + ey) / voxel_m));
    for (std::int32_t i = i0; i <= i1; ++i) {
        auto it = std::lower_bound(boxes.begin(), boxes.end(), std::array<std::int32_t, 3>{i, j0, INT32_MIN});
        for (; it != boxes.end() && (*it)[0] == i && (*it)[1] <= j1; ++it) {
            const double bottom = (*it)[2] * voxel_m, top = bottom + voxel_m;
            if (top > floor_m && bottom < ceiling_m) return true;
        }
    }
    return false;
}

std::string number(double v) { return core::shownNumber(v); }

}  // namespace

PlacedVehicle placeVehicle(const TerrainMesh& t, const std::vector<std::array<std::int32_t, 3>>& boxes, double voxel_m,
                           const glm::dvec3& offset_m, const VehiclePlacement& o) {
    const std::string where = "scene from-cloud: --vehicle '" + core::printable(o.mesh.string(), 400) + "'";
    const io::MeshTriangles mesh = io::loadMeshTriangles(o.mesh, o.up_y, 1.0, where);
    core::Bounds b;
    for (const glm::dvec3& v : mesh.vertices) b.extend(v);
    PlacedVehicle pv;
    pv.file = vehicleFileName(o);
    if (vehicleAsObj(o)) pv.obj_text = vehicleObj(mesh, o.mesh, where);
    pv.size_m = b.size();
    const glm::dvec3 bottom((b.lo.x + b.hi.x) / 2, (b.lo.y + b.hi.y) / 2, b.lo.z);
    const double hl = pv.size_m.x / 2, hw = pv.size_m.y / 2, radius = std::hypot(hl, hw) + o.clearance_m;

    // Drawn spots keep the orbit's covered disc (about 125 m across) inside the survey
    // where the survey is large enough.
    const double x1 = t.x0_m + (t.nx - 1) * t.cell_m, y1 = t.y0_m + (t.ny - 1) * t.cell_m;
    const double half = std::min(x1 - t.x0_m, y1 - t.y0_m) / 2;
    const double inset = radius + std::clamp((half - radius) / 2, 0.0, 62.5);
    core::SplitMix64 rng(o.seed);
    std::string last_reason = "the survey is smaller than the vehicle";
    const int draws = o.at_world ? 1 : kSpotDraws;
    for (int attempt = 0; attempt < draws; ++attempt) {
        glm::dvec2 c;
        if (o.at_world) {
            c = *o.at_world - glm::dvec2(offset_m);
        } else {
            if (t.x0_m + inset > x1 - inset || t.y0_m + inset > y1 - inset) break;
            c = {rng.uniform(t.x0_m + inset, x1 - inset), rng.uniform(t.y0_m + inset, y1 - inset)};
        }
        const double yaw_deg = o.yaw_deg ? *o.yaw_deg : std::floor(rng.uniform(0.0, 360.0));
        const Plane p = fitPlane(t, c, yaw_deg * kDeg, hl, hw);
        const double slope = std::hypot(p.gx, p.gy);
        if (slope > o.max_slope) {
            last_reason = "the ground slopes " + number(slope) + " (--max-slope " + number(o.max_slope) + ")";
            continue;
        }
        if (p.roughness_m > o.max_roughness_m) {
            last_reason = "the ground is " + number(p.roughness_m) + " m off its plane (--max-roughness-m " +
                          number(o.max_roughness_m) + ")";
            continue;
        }
        const double cs = std::cos(yaw_deg * kDeg), sn = std::sin(yaw_deg * kDeg);
        const double ex = std::abs(hl * cs) + std::abs(hw * sn) + o.clearance_m;
        const double ey = std::abs(hl * sn) + std::abs(hw * cs) + o.clearance_m;
        if (boxNear(boxes, voxel_m, c, ex, ey, p.z - p.roughness_m - 0.5 * voxel_m,
                    p.top_m + pv.size_m.z + o.clearance_m)) {
            last_reason = "a box of the survey's points stands within --clearance-m " + number(o.clearance_m);
            continue;
        }
        // The plane's rise along the vehicle's length and across it: pitch (nose down when
        // positive, core::tilt) and roll (its left side up when positive).
        const double along = p.gx * cs + p.gy * sn, across = -p.gx * sn + p.gy * cs;
        pv.yaw_deg = yaw_deg;
        pv.pitch_deg = -std::atan(along) / kDeg;
        pv.roll_deg = std::asin(across / std::sqrt(along * along + across * across + 1)) / kDeg;
        const glm::dvec3 tilted = core::tilt(bottom, pv.pitch_deg, pv.roll_deg);
        const glm::dvec3 turned(tilted.x * cs - tilted.y * sn, tilted.x * sn + tilted.y * cs, tilted.z);
        pv.footprint_centre = glm::dvec3(c, p.z);
        pv.position = pv.footprint_centre - turned;
        pv.slope = slope;
        pv.roughness_m = p.roughness_m;
        pv.attempts = attempt + 1;
        return pv;
    }
    if (o.at_world)
        throw core::Error(where + ": no room at --vehicle-at " + number(o.at_world->x) + "," + number(o.at_world->y) +
                          ": " + last_reason + "; allowed a flat, free spot: move it or raise that option");
    throw core::Error(
        where + ": no flat, free spot in " + std::to_string(kSpotDraws) + " drawn (the last: " + last_reason +
        "); allowed: raise --max-slope, --max-roughness-m, lower --clearance-m, or " + "give --vehicle-at");
}

}  // namespace sim::detail
