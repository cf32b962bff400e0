// detect/src/segmentation.cpp: the segments of detect/segmentation.hpp, a step each: the
// terrain fit, the clustering of the points above it (detect/src/voxel_clusters.hpp), the
// small segments dropped, the tall segments split, and the oversized low ones split
// (detect/src/oversized_segments.hpp).
#include <detect/segmentation.hpp>

#include <core/error.hpp>

#include "oversized_segments.hpp"
#include "parts.hpp"
#include "point_spacing.hpp"
#include "terrain_level.hpp"
#include "voxel_clusters.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace detect {
namespace {

using detail::clusterPoints;
using detail::KeyedPoints;
using detail::kKeyMax;
using detail::kKeyOffset;
using detail::packKey;
using detail::partsFor;
using detail::sortByKey;

[[noreturn]] void fail(const char* option, double value, const char* allowed) {
    std::ostringstream s;
    s << "detect: " << option << " = " << value << ": allowed " << allowed;
    throw core::Error(s.str());
}

// A part carved out of a tall segment holds at least this many times min_points.
constexpr std::size_t kSplitMinFactor = 10;

// Step 1: the whole-cloud SMRF run sees the points with their views, so on a real
// sensor's thick ground it measures the thickness, takes each view's height error off
// and levels each cell at its ground's centre (docs/ground.md); on the ideal sensor's
// thin ground it is the published minimum-surface SMRF. Fills out.height_m, out.terrain_cell_m,
// out.ground_sigma_m and out.points_per_voxel_face; returns whether each point is ground.
std::vector<std::uint8_t> fitTerrain(const core::PointCloud& cloud, const SegmentOptions& o, int threads,
                                     std::size_t work_parts, Segmentation& out) {
    const std::size_t n = cloud.points.size();
    std::vector<std::uint8_t> ground(n);
    out.height_m.resize(n);
    const sim::SmrfOptions terrain = terrainForDensity(o.terrain, detail::coveredDensity(cloud));
    out.terrain_cell_m = terrain.cell_m;
    const std::unique_ptr<sim::TerrainFit> fit = sim::startSmrf(terrain);
    fit->setFitThreads(threads);
    if (cloud.fields.view) {
        fit->addAll(cloud.points, threads);
    } else {
        constexpr std::size_t kChunk = 1 << 16;
        std::vector<core::CloudPoint> chunk;
        for (std::size_t i = 0; i < n; i += kChunk) {
            chunk.assign(cloud.points.begin() + std::ptrdiff_t(i),
                         cloud.points.begin() + std::ptrdiff_t(std::min(n, i + kChunk)));
            for (core::CloudPoint& p : chunk) p.view = 0;  // no views recorded: one view
            fit->add(chunk);
        }
    }
    fit->fit();
    const sim::TerrainGrid& t = fit->surface();
    out.ground_sigma_m = t.ground_sigma_m;
    const double observed_m2 = double(t.observed_cells) * t.cell_m * t.cell_m;
    if (observed_m2 > 0) out.points_per_voxel_face = double(n) / observed_m2 * o.voxel_m * o.voxel_m;
    const std::size_t parts = partsFor(n, work_parts);
    runParts(parts, [&](std::size_t part) {
        for (std::size_t i = partStart(n, parts, part); i < partStart(n, parts, part + 1); ++i) {
            core::CloudPoint p = cloud.points[i];
            if (!cloud.fields.view) p.view = 0;
            ground[i] = fit->classify(p, out.height_m[i]);
        }
    });
    return ground;
}

// Step 4's test on a tall segment `s`: per point of s, whether its column (a voxel_m
// square of the footprint) rises, that is whether the column's occupied layers (voxel_m
// of height above the terrain) run without a gap beyond the clustering's reach from its
// lowest point to above split_height_m. `keyed` and `rises` are buffers kept between
// segments; `rises` holds the answer.
void risingColumns(const core::PointCloud& cloud, const std::vector<std::uint32_t>& s, const Segmentation& out,
                   const glm::dvec3& lo, const SegmentOptions& o, std::size_t work_parts, KeyedPoints& keyed,
                   std::vector<std::uint8_t>& rises) {
    const std::int64_t top_layer = std::int64_t(std::floor(o.split_height_m / o.voxel_m));
    // Layers this far apart are within the clustering's reach (as step 2's voxels).
    const std::int64_t reach = std::int64_t(std::ceil(o.cluster_tolerance_m / o.voxel_m));
    // A point's column and layer as one key (the layer in the place of the voxel's z;
    // a layer beyond the key's range is capped, which keeps it above top_layer).
    const auto columnLayerOf = [&](std::uint32_t i) {
        const glm::dvec3 p = glm::dvec3(cloud.points[i].position) - lo;
        const std::int64_t layer = std::min<std::int64_t>(
            std::int64_t(std::floor(std::max(0.0f, out.height_m[i]) / o.voxel_m)), kKeyMax - kKeyOffset);
        return packKey(std::int64_t(std::floor(p.x / o.voxel_m)), std::int64_t(std::floor(p.y / o.voxel_m)), layer);
    };
    // The segment's points by column, each column's layers ascending.
    keyed.resize(s.size());
    for (std::size_t k = 0; k < s.size(); ++k) {
        if (k + 16 < s.size()) {  // a segment's points are scattered over the cloud
            __builtin_prefetch(&cloud.points[s[k + 16]]);
            __builtin_prefetch(&out.height_m[s[k + 16]]);
        }
        keyed[k] = {columnLayerOf(s[k]), std::uint32_t(k)};
    }
    sortByKey(keyed, work_parts);
    rises.assign(s.size(), 0);
    constexpr std::uint64_t kLayerMask = (std::uint64_t(1) << 21) - 1;
    for (std::size_t a = 0; a < keyed.size();) {
        std::size_t b = a;
        while (b < keyed.size() && (keyed[b].first >> 21) == (keyed[a].first >> 21)) ++b;
        bool up = false;
        for (std::size_t k = a; k < b; ++k) {
            const std::int64_t layer = std::int64_t(keyed[k].first & kLayerMask) - kKeyOffset;
            if (layer >= top_layer) {
                up = true;
                break;
            }
            if (k + 1 < b && std::int64_t(keyed[k + 1].first & kLayerMask) - kKeyOffset - layer > reach) break;
        }
        for (std::size_t k = a; k < b; ++k) rises[keyed[k].second] = up;
        a = b;
    }
}

// Step 4 on one tall segment `s` whose columns `rises` says rise: the points below
// split_height_m in columns that do not rise, clustered alone (as in step 2); each such
// cluster of kSplitMinFactor x min_points or more becomes a part, and the rest (with the
// smaller clusters) is the last part, ascending. Empty when nothing stands free.
std::vector<std::vector<std::uint32_t>> splitSegment(const core::PointCloud& cloud, const std::vector<std::uint32_t>& s,
                                                     const std::vector<std::uint8_t>& rises, const Segmentation& out,
                                                     const glm::dvec3& lo, const SegmentOptions& o,
                                                     std::size_t work_parts) {
    std::vector<std::uint32_t> free_points, rest;
    for (std::size_t k = 0; k < s.size(); ++k)
        (out.height_m[s[k]] <= o.split_height_m && !rises[k] ? free_points : rest).push_back(s[k]);
    std::vector<std::vector<std::uint32_t>> parts,
        free_parts = clusterPoints(cloud, free_points, lo, o, out.core_points, work_parts);
    const std::size_t rest_sorted = rest.size();
    for (auto& p : free_parts) {
        if (p.size() >= kSplitMinFactor * std::size_t(o.min_points))
            parts.push_back(std::move(p));
        else
            rest.insert(rest.end(), p.begin(), p.end());
    }
    if (parts.empty()) return parts;
    // rest: ascending, then the small parts' points, which are merged in.
    std::sort(rest.begin() + std::ptrdiff_t(rest_sorted), rest.end());
    std::inplace_merge(rest.begin(), rest.begin() + std::ptrdiff_t(rest_sorted), rest.end());
    parts.push_back(std::move(rest));
    return parts;
}

// Step 4: a segment that reaches above split_height_m is split into what stands free
// below that height and the rest. A column rises (risingColumns) in a wall, a trunk, a
// conifer's branches down to the ground. The points below split_height_m in columns that
// do not rise are clustered alone (as in step 2); each such cluster of kSplitMinFactor x
// min_points or more becomes a segment (a smaller one, a shrub or a low branch, stays
// where it was), and the rest stays one segment (not clustered again: a canopy does not
// fall into fragments). A vehicle parked against a wall or under crowns that touch each
// other then stands apart from them; a segment with nothing free is kept whole.
void splitTallSegments(const core::PointCloud& cloud, const glm::dvec3& lo, const SegmentOptions& o,
                       std::size_t work_parts, Segmentation& out) {
    const auto big = [&](const std::vector<std::uint32_t>& p) { return p.size() >= std::size_t(o.min_points); };
    std::vector<std::vector<std::uint32_t>> kept;
    KeyedPoints keyed;
    std::vector<std::uint8_t> rises;
    for (auto& s : out.segments) {
        const bool tall =
            std::any_of(s.begin(), s.end(), [&](std::uint32_t i) { return out.height_m[i] > o.split_height_m; });
        if (!tall) {
            kept.push_back(std::move(s));
            continue;
        }
        risingColumns(cloud, s, out, lo, o, work_parts, keyed, rises);
        std::vector<std::vector<std::uint32_t>> parts = splitSegment(cloud, s, rises, out, lo, o, work_parts);
        if (parts.empty()) {
            kept.push_back(std::move(s));
            continue;
        }
        ++out.split_segments;
        for (auto& p : parts)
            if (big(p)) kept.push_back(std::move(p));
    }
    // Segments in order of their first point again.
    std::stable_sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
    out.segments = std::move(kept);
}

}  // namespace

void validate(const SegmentOptions& o) {
    sim::validate(o.terrain);
    if (!(std::isfinite(o.min_height_m) && o.min_height_m >= 0.0 && o.min_height_m <= 10.0))
        fail("--min-height-m", o.min_height_m, "[0, 10] m");
    if (!(std::isfinite(o.ground_sigmas) && o.ground_sigmas >= 0.0 && o.ground_sigmas <= 20.0))
        fail("--ground-sigmas", o.ground_sigmas, "[0, 20]");
    if (!(std::isfinite(o.voxel_m) && o.voxel_m >= 0.05 && o.voxel_m <= 10.0))
        fail("--segment-voxel-m", o.voxel_m, "[0.05, 10] m");
    if (!(std::isfinite(o.cluster_tolerance_m) && o.cluster_tolerance_m > o.voxel_m / 2.0 &&
          o.cluster_tolerance_m <= 10.0))
        fail("--segment-tolerance-m", o.cluster_tolerance_m, "(voxel / 2, 10] m");
    if (o.core_points < 1 || o.core_points > 1000) fail("--segment-core-points", o.core_points, "[1, 1000]");
    if (o.min_points < 1) fail("--segment-min-points", o.min_points, ">= 1");
    if (!(std::isfinite(o.level_cell_m) &&
          (o.level_cell_m == 0.0 || (o.level_cell_m >= 1.0 && o.level_cell_m <= 100.0))))
        fail("--level-cell-m", o.level_cell_m, "0 (no levelling) or [1, 100] m");
    if (!(std::isfinite(o.split_height_m) &&
          (o.split_height_m == 0.0 || (o.split_height_m >= 1.0 && o.split_height_m <= 100.0))))
        fail("--split-height-m", o.split_height_m, "0 (no split) or [1, 100] m");
    if (!(std::isfinite(o.max_vehicle_length_m) &&
          (o.max_vehicle_length_m == 0.0 || (o.max_vehicle_length_m >= 2.0 && o.max_vehicle_length_m <= 100.0))))
        fail("max_vehicle_length_m", o.max_vehicle_length_m, "0 (no split) or [2, 100] m");
    if (o.max_vehicle_length_m > 0.0 && !(std::isfinite(o.max_vehicle_width_m) && o.max_vehicle_width_m >= 1.0 &&
                                          o.max_vehicle_width_m <= o.max_vehicle_length_m))
        fail("max_vehicle_width_m", o.max_vehicle_width_m, "[1, max_vehicle_length_m] m");
}

sim::SmrfOptions terrainForDensity(const sim::SmrfOptions& o, double density_m2) {
    if (!(std::isfinite(density_m2) && density_m2 > 0.0) || density_m2 * o.cell_m * o.cell_m >= kTerrainPointsPerCell)
        return o;
    sim::SmrfOptions e = o;
    const double cell_m = std::ceil(std::sqrt(kTerrainPointsPerCell / density_m2) * 10.0) / 10.0;
    e.cell_m = std::max(o.cell_m, std::min(cell_m, std::max(o.window_m, o.cell_m)));
    return e;
}

SegmentOptions scaledForSpacing(const SegmentOptions& o, double spacing_m, double* scale_out) {
    // The join distance max(tolerance, 3 spacing - 2 tolerance): as given up to a spacing
    // of the join distance itself (twice the sparsest drone cloud's), then growing three
    // times as fast as the spacing (a sparse cloud's random gaps reach well past its
    // median spacing).
    double scale = 1.0;
    if (o.scale_with_spacing && std::isfinite(spacing_m) && spacing_m > o.cluster_tolerance_m)
        scale = std::min((3.0 * spacing_m - 2.0 * o.cluster_tolerance_m) / o.cluster_tolerance_m, kMaxSpacingScale);
    if (scale_out) *scale_out = scale;
    if (scale == 1.0) return o;
    SegmentOptions e = o;
    e.voxel_m = o.voxel_m * scale;
    e.cluster_tolerance_m = o.cluster_tolerance_m * scale;
    e.min_points = std::max(std::min(o.min_points, kMinScaledPoints), int(std::lround(o.min_points / (scale * scale))));
    return e;
}

Segmentation segmentCloud(const core::PointCloud& cloud, const SegmentOptions& o, int threads) {
    validate(o);
    if (threads < 1) throw core::Error("detect: threads = " + std::to_string(threads) + ": allowed >= 1");
    const std::size_t work_parts = std::min(std::size_t(threads), detail::kMaxParts);
    if (cloud.points.size() >= std::size_t(UINT32_MAX))
        throw core::Error("detect: the cloud has too many points (at most 4294967294)");
    Segmentation out;
    out.used = o;
    const std::size_t n = cloud.points.size();
    if (n == 0) return out;

    const std::vector<std::uint8_t> ground = fitTerrain(cloud, o, threads, work_parts, out);
    if (o.level_cell_m > 0) detail::levelTerrain(cloud, o.level_cell_m, out.height_m);
    // A thick ground reaches higher: the threshold grows with its measured thickness.
    out.min_height_m = std::max(o.min_height_m, o.ground_sigmas * out.ground_sigma_m);

    // Step 2: voxels of the points above the terrain, clustered.
    std::vector<std::uint32_t> above;
    for (std::size_t i = 0; i < n; ++i)
        if (!ground[i] && out.height_m[i] > out.min_height_m) above.push_back(std::uint32_t(i));
    out.above_points = above.size();
    // A sparse cloud's lengths follow its point spacing; a dense one's stay as given.
    if (o.scale_with_spacing) out.spacing_m = detail::medianSpacing(cloud, above);
    out.used = scaledForSpacing(o, out.spacing_m, &out.spacing_scale);
    const SegmentOptions& u = out.used;
    // The terrain's sampling per voxel face, at the voxel step 2 uses.
    out.points_per_voxel_face *= out.spacing_scale * out.spacing_scale;
    // The bar follows the cloud's sampling: at most half the points a voxel's face of
    // level ground holds on average (the cloud's points over the terrain's observed
    // area), so a sparsely sampled cloud (few views, a far orbit), whose surfaces hold one
    // or two points a voxel, still joins them.
    out.core_points = int(std::clamp(std::floor(out.points_per_voxel_face / 2.0), 1.0, double(u.core_points)));
    const glm::dvec3 lo = cloud.bounds().lo;
    std::vector<std::vector<std::uint32_t>> segments =
        clusterPoints(cloud, above, lo, u, out.core_points, work_parts, &out.voxels);

    // Step 3: small segments are noise.
    for (auto& s : segments)
        if (s.size() >= std::size_t(u.min_points)) out.segments.push_back(std::move(s));

    if (u.split_height_m > 0) splitTallSegments(cloud, lo, u, work_parts, out);
    detail::splitOversizedSegments(cloud, lo, u, work_parts, out);
    return out;
}

}  // namespace detect
