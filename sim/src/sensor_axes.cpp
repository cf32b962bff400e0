// sim/src/sensor_axes.cpp: which beams of a row run lie on one plane. A beam's footprint
// lies within its pixel's cell, which the axes of its 3x3 neighbour pixels enclose; when
// all nine hit one mesh within 1 mm + 1e-5 x range of the plane of the centre's triangle,
// the footprint sees that plane alone and the beam needs no sub-rays (a feature narrower
// than the pixel spacing between the axes can be missed: footprint_exact traces every
// sub-ray).
//
// Each row's axes serve three rows of beams (its own, the one above, the one below), and
// the generator hands a thread consecutive rows of one view. So the axes are kept per
// thread for the last three rows of the (sensor, view) last traced: a row of n beams
// traces about n axes rather than 3 (n + 2). Embree's hit of a ray can differ in its last
// bits with the other rays of its packet, so an axis is always traced in the same packet:
// the 16 columns of its row from a multiple of 16 (or alone without packets), whichever
// call first needs it. Its hit is then the same whatever the order of the calls and the
// thread that makes them. (For the same reason a beam that is not planar traces its axis
// again with its sub-rays, one beam after the other, as --footprint-exact lays them out.)
#include "sensor_axes.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <vector>

namespace sim::sensor_model {
namespace {

constexpr std::int64_t kGroup = 16;  // axes traced together: columns [16 g, 16 g + 16) of a row

// The axes of one image row, traced group by group as calls need them.
struct AxisRow {
    std::int64_t row = -1;             // -1: none
    std::vector<std::uint8_t> traced;  // per group of kGroup columns
    std::vector<glm::vec3> direction;  // per column: the axis ray's direction (local frame)
    std::vector<Hit> hit;
    std::vector<glm::dvec3> point;  // origin + t * direction, where hit
};

struct AxisCache {
    std::uint64_t sensor_id = 0;  // 0: empty
    const RayCaster* caster = nullptr;
    int view = -1;
    bool packets = false;
    core::Pose actual;
    AxisRow rows[3];  // row y in rows[y % 3]: any three consecutive rows at once
    Ray rays[kGroup];
    Hit hits[kGroup];
};
thread_local AxisCache t_axes;

std::atomic<std::uint64_t> g_next_sensor_id{1};

bool samePose(const core::Pose& a, const core::Pose& b) {
    // Bit for bit: -0.0 and 0.0 may give different rays.
    return std::memcmp(&a.rotation, &b.rotation, sizeof a.rotation) == 0 &&
           std::memcmp(&a.translation, &b.translation, sizeof a.translation) == 0;
}

// Row y's axes, those of columns [lo, hi) traced.
const AxisRow& axisRow(AxisCache& cache, const AxisSource& src, const RayCaster& caster, const SensorView& v,
                       std::int64_t y, std::int64_t lo, std::int64_t hi) {
    const std::int64_t xres = src.orbit->xres;
    AxisRow& r = cache.rows[y % 3];
    if (r.row != y) {
        r.row = y;
        r.traced.assign(std::size_t((xres + kGroup - 1) / kGroup), 0);
        r.direction.resize(std::size_t(xres));
        r.hit.resize(std::size_t(xres));
        r.point.resize(std::size_t(xres));
    }
    const glm::vec3 origin(v.actual.translation);
    const glm::dvec3 o(origin);
    for (std::int64_t g = lo / kGroup; g <= (hi - 1) / kGroup; ++g) {
        if (r.traced[std::size_t(g)]) continue;
        const std::int64_t c0 = g * kGroup;
        const std::size_t m = std::size_t(std::min(kGroup, xres - c0));
        for (std::size_t k = 0; k < m; ++k) {
            const glm::dvec3 d = src.directions.empty()
                                     ? pixelDirection(*src.orbit, double(c0 + std::int64_t(k)), double(y))
                                     : src.directions[std::size_t(y) * std::size_t(xres) + std::size_t(c0) + k];
            cache.rays[k] = Ray{origin, glm::vec3(v.actual.rotation * d), src.t_far};
        }
        const std::span<const Ray> rays(cache.rays, m);
        const std::span<Hit> hits(cache.hits, m);
        if (cache.packets)
            caster.intersect16(rays, hits);
        else
            caster.intersect(rays, hits);
        for (std::size_t k = 0; k < m; ++k) {
            const std::size_t c = std::size_t(c0) + k;
            r.direction[c] = rays[k].direction;
            r.hit[c] = hits[k];
            if (hits[k].hit()) r.point[c] = o + double(hits[k].t) * glm::dvec3(rays[k].direction);
        }
        r.traced[std::size_t(g)] = 1;
    }
    return r;
}

}  // namespace

std::uint64_t newSensorId() { return g_next_sensor_id.fetch_add(1, std::memory_order_relaxed); }

std::size_t axisCacheBytes(int xres) {
    const std::size_t per_column = sizeof(glm::vec3) + sizeof(Hit) + sizeof(glm::dvec3) + 1;
    return sizeof(AxisCache) + 3 * std::size_t(std::max(xres, 0)) * per_column;
}

void markPlanar(const AxisSource& src, const RayCaster& caster, const SensorView& v, std::int64_t y, std::int64_t x0,
                std::size_t n, bool packets, std::span<std::uint8_t> planar, std::span<Ray> axis_rays,
                std::span<Hit> axis_hits) {
    if (n == 0) return;
    AxisCache& cache = t_axes;
    if (cache.sensor_id != src.sensor_id || cache.caster != &caster || cache.view != v.view ||
        cache.packets != packets || !samePose(cache.actual, v.actual)) {
        cache.sensor_id = src.sensor_id;
        cache.caster = &caster;
        cache.view = v.view;
        cache.packets = packets;
        cache.actual = v.actual;
        for (AxisRow& r : cache.rows) r.row = -1;
    }
    const std::int64_t xres = src.orbit->xres, yres = src.orbit->yres;
    const std::int64_t lo = std::max<std::int64_t>(0, x0 - 1);
    const std::int64_t hi = std::min<std::int64_t>(xres, x0 + std::int64_t(n) + 1);
    const AxisRow* rows[3] = {nullptr, nullptr, nullptr};
    for (std::int64_t r = 0; r < 3; ++r) {
        const std::int64_t row = y - 1 + r;
        if (row >= 0 && row < yres) rows[r] = &axisRow(cache, src, caster, v, row, lo, hi);
    }
    if (!rows[0] || !rows[2]) return;  // the top or bottom row: neighbours outside the image
    const AxisRow& centre = *rows[1];
    const glm::vec3 origin(v.actual.translation);
    for (std::size_t i = 0; i < n; ++i) {
        const std::int64_t x = x0 + std::int64_t(i);
        if (x < 1 || x + 1 >= xres) continue;  // the first or last column: likewise
        const Hit& hc = centre.hit[std::size_t(x)];
        if (!hc.hit() || !(glm::dot(hc.normal, hc.normal) > 0.0f)) continue;  // length > 0, no sqrt
        const glm::dvec3 normal = glm::normalize(glm::dvec3(hc.normal));
        const glm::dvec3& pc = centre.point[std::size_t(x)];
        const double tolerance_m = 1e-3 + 1e-5 * double(hc.t);
        bool on_plane = true;
        for (int r = 0; r < 3 && on_plane; ++r)
            for (std::size_t c = std::size_t(x - 1); c <= std::size_t(x + 1) && on_plane; ++c) {
                const Hit& h = rows[r]->hit[c];
                on_plane =
                    h.hit() && h.mesh == hc.mesh && std::abs(glm::dot(normal, rows[r]->point[c] - pc)) <= tolerance_m;
            }
        if (!on_plane) continue;
        planar[i] = 1;
        axis_rays[i] = Ray{origin, centre.direction[std::size_t(x)], src.t_far};
        axis_hits[i] = hc;
    }
}

}  // namespace sim::sensor_model
