// detect/src/oversized_segments.cpp: the segmentation's step 5 of
// detect/src/oversized_segments.hpp, a step each: the plan extents along the principal
// axes, the segment's lower envelope, the clusters above each cut, and the points inside
// each vehicle-sized cluster's widened hull taken as a segment.
#include "oversized_segments.hpp"

#include "voxel_clusters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace detect::detail {
namespace {

// A child holds at least this many times min_points (as step 4's parts).
constexpr std::size_t kChildMinFactor = 10;

// The unit vector of the larger principal axis of the points' (x, y) covariance.
glm::dvec2 majorAxis(const core::PointCloud& cloud, std::span<const std::uint32_t> idx) {
    glm::dvec2 mean(0.0);
    for (const std::uint32_t i : idx) mean += glm::dvec2(cloud.points[i].position);
    mean /= double(idx.size());
    double sxx = 0, sxy = 0, syy = 0;
    for (const std::uint32_t i : idx) {
        const glm::dvec2 d = glm::dvec2(cloud.points[i].position) - mean;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    // The angle of the major axis of a 2 x 2 symmetric matrix.
    const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
    return {std::cos(angle), std::sin(angle)};
}

// The lower envelope of a segment: per point of s, the lowest height above the terrain
// of the segment's points within the envelope window (square cells of `cell_m`).
std::vector<float> lowerEnvelope(const core::PointCloud& cloud, const std::vector<std::uint32_t>& s,
                                 const std::vector<float>& height_m, double cell_m) {
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const std::uint32_t i : s) {
        lo = glm::min(lo, glm::dvec2(cloud.points[i].position));
        hi = glm::max(hi, glm::dvec2(cloud.points[i].position));
    }
    // Larger cells where the segment spans more than kMaxEnvelopeCells of them.
    const double area_cells = (hi.x - lo.x) / cell_m * ((hi.y - lo.y) / cell_m);
    if (area_cells > kMaxEnvelopeCells) cell_m *= std::sqrt(area_cells / kMaxEnvelopeCells) * 1.01;
    const std::int64_t nx = std::int64_t(std::floor((hi.x - lo.x) / cell_m)) + 1,
                       ny = std::int64_t(std::floor((hi.y - lo.y) / cell_m)) + 1;
    const auto cellOf = [&](std::uint32_t i) {
        const glm::dvec2 p = glm::dvec2(cloud.points[i].position) - lo;
        const std::int64_t cx = std::clamp<std::int64_t>(std::int64_t(std::floor(p.x / cell_m)), 0, nx - 1),
                           cy = std::clamp<std::int64_t>(std::int64_t(std::floor(p.y / cell_m)), 0, ny - 1);
        return std::size_t(cy * nx + cx);
    };
    constexpr float kEmpty = std::numeric_limits<float>::max();
    std::vector<float> low(std::size_t(nx * ny), kEmpty), row(low.size(), kEmpty);
    for (const std::uint32_t i : s) {
        float& l = low[cellOf(i)];
        l = std::min(l, height_m[i]);
    }
    // The window's minimum, separable: along x, then along y.
    const std::int64_t r = std::max<std::int64_t>(1, std::int64_t(std::ceil(kEnvelopeReach_m / cell_m)));
    for (std::int64_t y = 0; y < ny; ++y)
        for (std::int64_t x = 0; x < nx; ++x) {
            float m = kEmpty;
            for (std::int64_t d = std::max<std::int64_t>(0, x - r); d <= std::min(nx - 1, x + r); ++d)
                m = std::min(m, low[std::size_t(y * nx + d)]);
            row[std::size_t(y * nx + x)] = m;
        }
    for (std::int64_t y = 0; y < ny; ++y)
        for (std::int64_t x = 0; x < nx; ++x) {
            float m = kEmpty;
            for (std::int64_t d = std::max<std::int64_t>(0, y - r); d <= std::min(ny - 1, y + r); ++d)
                m = std::min(m, row[std::size_t(d * nx + x)]);
            low[std::size_t(y * nx + x)] = m;
        }
    std::vector<float> envelope(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) envelope[k] = low[cellOf(s[k])];
    return envelope;
}

// The convex hull in plan of the points `idx` (Andrew's monotone chain), counter-clockwise,
// without repeated points.
std::vector<glm::dvec2> planHull(const core::PointCloud& cloud, std::span<const std::uint32_t> idx) {
    std::vector<glm::dvec2> p;
    p.reserve(idx.size());
    for (const std::uint32_t i : idx) p.emplace_back(cloud.points[i].position);
    std::sort(p.begin(), p.end(),
              [](const glm::dvec2& a, const glm::dvec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() < 3) return p;
    const auto cross = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    std::vector<glm::dvec2> h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
        while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
        h[k++] = p[i - 1];
    }
    h.resize(k - 1);
    return h;
}

// Whether `q` lies within `margin_m` outside the convex polygon `hull` (counter-clockwise;
// its edges' lines moved out by the margin, so corners are mitred).
bool inWidenedHull(const std::vector<glm::dvec2>& hull, const glm::dvec2& q, double margin_m) {
    if (hull.size() < 3) return false;
    for (std::size_t e = 0; e < hull.size(); ++e) {
        const glm::dvec2 a = hull[e], b = hull[(e + 1) % hull.size()];
        const glm::dvec2 d = b - a;
        const double len = glm::length(d);
        if (len <= 0) continue;
        // Outward distance from the edge's line (the interior is on the left).
        const double out = ((q.x - a.x) * d.y - (q.y - a.y) * d.x) / len;
        if (out > margin_m) return false;
    }
    return true;
}

// The points of `s` not yet `taken` inside the hull in plan of the cluster `c` widened
// by `margin_m`, at most `top_m` above the terrain, taken as a new child (when any).
void takeHull(const core::PointCloud& cloud, const std::vector<std::uint32_t>& s, const std::vector<std::uint32_t>& c,
              double margin_m, const std::vector<float>& height_m, double top_m, std::vector<std::uint8_t>& taken,
              std::vector<std::vector<std::uint32_t>>& children) {
    const std::vector<glm::dvec2> hull = planHull(cloud, c);
    glm::dvec2 box_lo(std::numeric_limits<double>::max()), box_hi(std::numeric_limits<double>::lowest());
    for (const glm::dvec2& h : hull) box_lo = glm::min(box_lo, h - margin_m), box_hi = glm::max(box_hi, h + margin_m);
    std::vector<std::uint32_t> child;
    for (std::size_t k = 0; k < s.size(); ++k) {
        if (taken[k] || double(height_m[s[k]]) > top_m) continue;
        const glm::dvec2 q(cloud.points[s[k]].position);
        if (q.x < box_lo.x || q.y < box_lo.y || q.x > box_hi.x || q.y > box_hi.y) continue;
        if (inWidenedHull(hull, q, margin_m)) {
            taken[k] = 1;
            child.push_back(s[k]);
        }
    }
    if (!child.empty()) children.push_back(std::move(child));
}

// Step 5 on one oversized segment `s`: its children, each ascending, then the rest
// (ascending); empty when no cluster of vehicle size stands out at any cut.
std::vector<std::vector<std::uint32_t>> splitOversized(const core::PointCloud& cloud,
                                                       const std::vector<std::uint32_t>& s, const glm::dvec3& lo,
                                                       const SegmentOptions& o, const Segmentation& out,
                                                       std::size_t work_parts) {
    const std::vector<float> envelope = lowerEnvelope(cloud, s, out.height_m, kEnvelopeCellVoxels * o.voxel_m);
    std::vector<std::uint8_t> taken(s.size(), 0);
    std::vector<std::vector<std::uint32_t>> children;
    std::vector<std::uint32_t> above;
    const std::size_t min_child = kChildMinFactor * std::size_t(o.min_points);
    // Each point's height above the envelope.
    std::vector<float> above_m(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) above_m[k] = out.height_m[s[k]] - envelope[k];
    for (const OversizeBand& band : kOversizeBands) {
        above.clear();
        for (std::size_t k = 0; k < s.size(); ++k)
            if (!taken[k] && above_m[k] > band.cut_m && above_m[k] <= band.cap_m) above.push_back(s[k]);
        if (above.size() < min_child) continue;
        for (const auto& c : clusterPoints(cloud, above, lo, o, out.core_points, work_parts)) {
            if (c.size() < min_child) continue;
            const PlanExtent e = planExtent(cloud, c);
            if (e.length_m > o.max_vehicle_length_m || e.width_m > o.max_vehicle_width_m) continue;
            // An uncapped band's cluster takes its hull at every height; a capped one's up
            // to its own top, not the crown above it.
            double top_m = kNoCap;
            if (band.cap_m < kNoCap) {
                top_m = 0;
                for (const std::uint32_t i : c) top_m = std::max(top_m, double(out.height_m[i]));
                top_m += o.voxel_m;
            }
            takeHull(cloud, s, c, kHullMargin * o.voxel_m, out.height_m, top_m, taken, children);
        }
    }
    if (children.empty()) return children;
    std::vector<std::uint32_t> rest;
    for (std::size_t k = 0; k < s.size(); ++k)
        if (!taken[k]) rest.push_back(s[k]);
    children.push_back(std::move(rest));
    return children;
}

}  // namespace

PlanExtent planExtent(const core::PointCloud& cloud, std::span<const std::uint32_t> idx) {
    if (idx.empty()) return {};
    const glm::dvec2 major = majorAxis(cloud, idx), minor(-major.y, major.x);
    double lo_a = std::numeric_limits<double>::max(), hi_a = std::numeric_limits<double>::lowest();
    double lo_b = lo_a, hi_b = hi_a;
    for (const std::uint32_t i : idx) {
        const glm::dvec2 p(cloud.points[i].position);
        const double a = glm::dot(p, major), b = glm::dot(p, minor);
        lo_a = std::min(lo_a, a), hi_a = std::max(hi_a, a);
        lo_b = std::min(lo_b, b), hi_b = std::max(hi_b, b);
    }
    const double u = hi_a - lo_a, v = hi_b - lo_b;
    return {std::max(u, v), std::min(u, v)};
}

void splitOversizedSegments(const core::PointCloud& cloud, const glm::dvec3& lo, const SegmentOptions& o,
                            std::size_t work_parts, Segmentation& out) {
    if (o.max_vehicle_length_m <= 0) return;
    std::vector<std::vector<std::uint32_t>> kept;
    bool split = false;
    for (auto& s : out.segments) {
        const bool tall = o.split_height_m > 0 && std::any_of(s.begin(), s.end(), [&](std::uint32_t i) {
                              return out.height_m[i] > o.split_height_m;
                          });
        const PlanExtent e = tall ? PlanExtent{} : planExtent(cloud, s);
        if (tall || (e.length_m <= o.max_vehicle_length_m && e.width_m <= o.max_vehicle_width_m)) {
            kept.push_back(std::move(s));
            continue;
        }
        std::vector<std::vector<std::uint32_t>> parts = splitOversized(cloud, s, lo, o, out, work_parts);
        if (parts.empty()) {
            kept.push_back(std::move(s));
            continue;
        }
        ++out.oversized_segments;
        split = true;
        for (auto& p : parts)
            if (p.size() >= std::size_t(o.min_points)) kept.push_back(std::move(p));
    }
    // Segments in order of their first point again.
    if (split)
        std::stable_sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
    out.segments = std::move(kept);
}

}  // namespace detect::detail
