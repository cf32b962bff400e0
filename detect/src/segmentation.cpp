// detect/src/segmentation.cpp: the segments of detect/segmentation.hpp.
#include <detect/segmentation.hpp>

#include <core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <span>
#include <sstream>
#include <unordered_map>

namespace detect {
namespace {

[[noreturn]] void fail(const char* option, double value, const char* allowed) {
    std::ostringstream s;
    s << "detect: " << option << " = " << value << ": allowed " << allowed;
    throw core::Error(s.str());
}

// Voxel keys packed into 64 bits: 21 bits per axis, offset so that negative indices fit.
constexpr std::int64_t kKeyOffset = std::int64_t(1) << 20;
constexpr std::int64_t kKeyMax = (std::int64_t(1) << 21) - 1;

std::uint64_t packKey(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (std::uint64_t(x + kKeyOffset) << 42) | (std::uint64_t(y + kKeyOffset) << 21) |
           std::uint64_t(z + kKeyOffset);
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

// Clusters the points `idx` (ascending indices into the cloud) on voxels of o.voxel_m
// whose cells are counted from `lo`: union-find over pairs of dense voxels (core_points
// points or more) whose centroids lie within o.cluster_tolerance_m; a sparse voxel joins
// the segment of its nearest dense voxel within reach. Groups in order of their first
// point, each ascending; small ones are not dropped here.
std::vector<std::vector<std::uint32_t>> clusterPoints(const core::PointCloud& cloud, std::span<const std::uint32_t> idx,
                                                      const glm::dvec3& lo, const SegmentOptions& o, int core_points) {
    // Each point's voxel key; sorted by key, then by position in idx, the points come in
    // runs of one voxel each, its points in their original order.
    const std::size_t n = idx.size();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
    for (std::size_t k = 0; k < n; ++k) {
        const glm::dvec3 p = glm::dvec3(cloud.points[idx[k]].position) - lo;
        const std::int64_t cx = std::int64_t(std::floor(p.x / o.voxel_m)),
                           cy = std::int64_t(std::floor(p.y / o.voxel_m)),
                           cz = std::int64_t(std::floor(p.z / o.voxel_m));
        if (cx > kKeyMax - kKeyOffset || cy > kKeyMax - kKeyOffset || cz > kKeyMax - kKeyOffset)
            throw core::Error("detect: the cloud is too wide for --segment-voxel-m " + std::to_string(o.voxel_m) +
                              " (at most 2^20 voxels across); allowed a larger voxel");
        keyed[k] = {packKey(cx, cy, cz), std::uint32_t(k)};
    }
    std::sort(keyed.begin(), keyed.end());

    // Voxels in key order (s): key, point count, centroid (summed in the points' order),
    // and id, the rank of its first point, which breaks ties between equally near
    // voxels. The segments (and their order, that of their first points) do not depend
    // on how neighbours are found.
    std::vector<std::uint64_t> key;
    std::vector<std::uint32_t> count, first;
    std::vector<glm::dvec3> centroid;
    for (std::size_t i = 0; i < n;) {
        std::size_t j = i;
        glm::dvec3 sum(0.0);
        for (; j < n && keyed[j].first == keyed[i].first; ++j)
            sum += glm::dvec3(cloud.points[idx[keyed[j].second]].position) - lo;
        key.push_back(keyed[i].first);
        count.push_back(std::uint32_t(j - i));
        first.push_back(keyed[i].second);
        centroid.push_back(sum / double(j - i));
        i = j;
    }
    const std::size_t voxels = key.size();
    std::vector<std::uint32_t> id_of(voxels), voxel_of_point(n);
    {
        std::vector<std::uint32_t> run_of_first(n, UINT32_MAX);
        for (std::size_t s = 0; s < voxels; ++s) run_of_first[first[s]] = std::uint32_t(s);
        std::uint32_t next = 0;
        for (std::size_t k = 0; k < n; ++k)
            if (run_of_first[k] != UINT32_MAX) id_of[run_of_first[k]] = next++;
        std::uint32_t s = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (i > 0 && keyed[i].first != keyed[i - 1].first) ++s;
            voxel_of_point[keyed[i].second] = s;
        }
    }
    keyed = {};

    // Union-find over pairs of dense voxels within reach (cells up to r apart on each
    // axis, centroids within the tolerance). A voxel with fewer than core_points points
    // does not join two segments: it is attached to its nearest dense voxel within reach
    // afterwards, so a sparse trail of noise or mixed returns between a crown and a
    // vehicle does not chain them.
    const auto dense = [&](std::size_t s) { return count[s] >= std::uint32_t(core_points); };
    std::vector<std::uint32_t> parent(voxels);
    std::iota(parent.begin(), parent.end(), 0u);
    const std::int64_t r = std::int64_t(std::ceil(o.cluster_tolerance_m / o.voxel_m));
    const double tol2 = o.cluster_tolerance_m * o.cluster_tolerance_m;
    // The neighbours of the voxels, visited in key order: in each column (dx, dy) of the
    // (2r + 1)^2 around a voxel, the cells dz in [-r, r] are one range of keys, and that
    // range only moves forward from one voxel to the next, so one cursor per column finds
    // it without a lookup. `visit(s, t, squared distance)` for every neighbour t of s
    // within reach; with forward_only each unordered pair once (the neighbour's cell the
    // larger).
    const auto sweep = [&](bool forward_only, auto&& wanted, auto&& visit) {
        const std::int64_t side = 2 * r + 1;
        std::vector<std::size_t> cursor(std::size_t(side * side), 0);
        const std::int64_t mask = (std::int64_t(1) << 21) - 1;
        for (std::size_t s = 0; s < voxels; ++s) {
            if (!wanted(s)) continue;
            const std::int64_t x = std::int64_t(key[s] >> 42) - kKeyOffset,
                               y = std::int64_t((key[s] >> 21) & std::uint64_t(mask)) - kKeyOffset,
                               z = std::int64_t(key[s] & std::uint64_t(mask)) - kKeyOffset;
            for (std::int64_t dx = -r; dx <= r; ++dx)
                for (std::int64_t dy = -r; dy <= r; ++dy) {
                    if (forward_only && (dx < 0 || (dx == 0 && dy < 0))) continue;
                    const std::int64_t cx = x + dx, cy = y + dy;
                    if (cx < -kKeyOffset || cy < -kKeyOffset || cx > kKeyMax - kKeyOffset || cy > kKeyMax - kKeyOffset)
                        continue;
                    const std::int64_t z0 = std::max(forward_only && dx == 0 && dy == 0 ? z + 1 : z - r, -kKeyOffset),
                                       z1 = std::min(z + r, kKeyMax - kKeyOffset);
                    const std::uint64_t k0 = packKey(cx, cy, z0), k1 = packKey(cx, cy, z1);
                    std::size_t& c = cursor[std::size_t((dx + r) * side + (dy + r))];
                    while (c < voxels && key[c] < k0) ++c;
                    for (std::size_t t = c; t < voxels && key[t] <= k1; ++t) {
                        if (t == s) continue;
                        const glm::dvec3 d = centroid[s] - centroid[t];
                        const double d2 = glm::dot(d, d);
                        if (d2 <= tol2) visit(s, t, d2);
                    }
                }
        }
    };
    sweep(true, dense, [&](std::size_t s, std::size_t t, double) {
        if (!dense(t)) return;
        const std::uint32_t a = findRoot(parent, std::uint32_t(s)), b = findRoot(parent, std::uint32_t(t));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    });
    // Sparse voxels: the segment of the nearest dense voxel (ties: the smaller id); alone
    // when none is within reach. Read only from dense voxels, so the order does not matter.
    std::vector<std::uint32_t> attached(voxels);
    std::vector<double> best(voxels, tol2 + 1.0);
    std::iota(attached.begin(), attached.end(), 0u);
    sweep(
        false, [&](std::size_t s) { return !dense(s); },
        [&](std::size_t s, std::size_t t, double d2) {
            if (!dense(t)) return;
            if (d2 < best[s] || (d2 == best[s] && id_of[t] < id_of[attached[s]]))
                best[s] = d2, attached[s] = std::uint32_t(t);
        });
    best = {};
    for (std::size_t s = 0; s < voxels; ++s)
        if (!dense(s) && attached[s] != s) parent[s] = findRoot(parent, attached[s]);

    // Groups in the order of their first point, each ascending.
    std::vector<std::uint32_t> segment_of_root(voxels, UINT32_MAX);
    std::vector<std::vector<std::uint32_t>> segments;
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t root = findRoot(parent, voxel_of_point[k]);
        if (segment_of_root[root] == UINT32_MAX) {
            segment_of_root[root] = std::uint32_t(segments.size());
            segments.emplace_back();
        }
        segments[segment_of_root[root]].push_back(idx[k]);
    }
    return segments;
}

// A part carved out of a tall segment holds at least this many times min_points.
constexpr std::size_t kSplitMinFactor = 10;

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
    if (!(std::isfinite(o.split_height_m) &&
          (o.split_height_m == 0.0 || (o.split_height_m >= 1.0 && o.split_height_m <= 100.0))))
        fail("--split-height-m", o.split_height_m, "0 (no split) or [1, 100] m");
}

Segmentation segmentCloud(const core::PointCloud& cloud, const SegmentOptions& o) {
    validate(o);
    if (cloud.points.size() >= std::size_t(UINT32_MAX))
        throw core::Error("detect: the cloud has too many points (at most 4294967294)");
    Segmentation out;
    const std::size_t n = cloud.points.size();
    if (n == 0) return out;

    // Step 1: the whole-cloud SMRF run sees the points with their views, so on a real
    // sensor's thick ground it measures the thickness, takes each view's height error off
    // and levels each cell at its ground's centre (docs/ground.md); on the ideal sensor's
    // thin ground it is the published minimum-surface SMRF.
    std::vector<std::uint8_t> ground(n);
    out.height_m.resize(n);
    {
        const std::unique_ptr<sim::TerrainFit> fit = sim::startSmrf(o.terrain);
        constexpr std::size_t kChunk = 1 << 16;
        std::vector<core::CloudPoint> chunk;
        for (std::size_t i = 0; i < n; i += kChunk) {
            const std::span<const core::CloudPoint> part(cloud.points.data() + i, std::min(kChunk, n - i));
            if (cloud.fields.view) {
                fit->add(part);
                continue;
            }
            chunk.assign(part.begin(), part.end());  // no views recorded: one view
            for (core::CloudPoint& p : chunk) p.view = 0;
            fit->add(chunk);
        }
        fit->fit();
        const sim::TerrainGrid& t = fit->surface();
        out.ground_sigma_m = t.ground_sigma_m;
        const double observed_m2 = double(t.observed_cells) * t.cell_m * t.cell_m;
        if (observed_m2 > 0) out.points_per_voxel_face = double(n) / observed_m2 * o.voxel_m * o.voxel_m;
        for (std::size_t i = 0; i < n; ++i) {
            core::CloudPoint p = cloud.points[i];
            if (!cloud.fields.view) p.view = 0;
            ground[i] = fit->classify(p, out.height_m[i]);
        }
    }
    // A thick ground reaches higher: the threshold grows with its measured thickness.
    out.min_height_m = std::max(o.min_height_m, o.ground_sigmas * out.ground_sigma_m);

    // Step 2: voxels of the points above the terrain, clustered.
    std::vector<std::uint32_t> above;
    for (std::size_t i = 0; i < n; ++i)
        if (!ground[i] && out.height_m[i] > out.min_height_m) above.push_back(std::uint32_t(i));
    out.above_points = above.size();
    // The bar follows the cloud's sampling: at most half the points a voxel's face of
    // level ground holds on average (the cloud's points over the terrain's observed
    // area), so a sparsely sampled cloud (few views, a far orbit), whose surfaces hold one
    // or two points a voxel, still joins them.
    out.core_points = int(std::clamp(std::floor(out.points_per_voxel_face / 2.0), 1.0, double(o.core_points)));
    const glm::dvec3 lo = cloud.bounds().lo;
    std::vector<std::vector<std::uint32_t>> segments = clusterPoints(cloud, above, lo, o, out.core_points);

    // Step 3: small segments are noise.
    for (auto& s : segments)
        if (s.size() >= std::size_t(o.min_points)) out.segments.push_back(std::move(s));

    // Step 4: a segment that reaches above split_height_m is split into what stands free
    // below that height and the rest. A column (a voxel_m square of the segment's
    // footprint) rises when its occupied layers (voxel_m of height above the terrain) run
    // without a gap beyond the clustering's reach from its lowest point to above
    // split_height_m: a wall, a trunk, a conifer's branches down to the ground. The
    // points below split_height_m in columns that do not rise are clustered alone (as in
    // step 2); each such cluster of kSplitMinFactor x min_points or more becomes a
    // segment (a smaller one, a shrub or a low branch, stays where it was), and the rest
    // stays one segment (not clustered again: a canopy does not fall into fragments). A
    // vehicle parked against a wall or under crowns that touch each other then stands
    // apart from them; a segment with nothing free is kept whole.
    if (o.split_height_m > 0) {
        const auto big = [&](const std::vector<std::uint32_t>& p) { return p.size() >= std::size_t(o.min_points); };
        const auto layerOf = [&](std::uint32_t i) {
            return std::int64_t(std::floor(std::max(0.0f, out.height_m[i]) / o.voxel_m));
        };
        const auto columnOf = [&](std::uint32_t i) {
            const glm::dvec3 p = glm::dvec3(cloud.points[i].position) - lo;
            return packKey(std::int64_t(std::floor(p.x / o.voxel_m)), std::int64_t(std::floor(p.y / o.voxel_m)), 0);
        };
        const std::int64_t top_layer = std::int64_t(std::floor(o.split_height_m / o.voxel_m));
        // Layers this far apart are within the clustering's reach (as step 2's voxels).
        const std::int64_t reach = std::int64_t(std::ceil(o.cluster_tolerance_m / o.voxel_m));
        std::vector<std::vector<std::uint32_t>> kept;
        for (auto& s : out.segments) {
            const bool tall =
                std::any_of(s.begin(), s.end(), [&](std::uint32_t i) { return out.height_m[i] > o.split_height_m; });
            if (!tall) {
                kept.push_back(std::move(s));
                continue;
            }
            std::vector<std::uint64_t> column(s.size());
            std::unordered_map<std::uint64_t, std::vector<std::int64_t>> layers;
            for (std::size_t k = 0; k < s.size(); ++k) {
                column[k] = columnOf(s[k]);
                layers[column[k]].push_back(layerOf(s[k]));
            }
            std::unordered_map<std::uint64_t, bool> rises;
            for (auto& [key, l] : layers) {
                std::sort(l.begin(), l.end());
                bool up = false;
                for (std::size_t k = 0; k < l.size(); ++k) {
                    if (l[k] >= top_layer) {
                        up = true;
                        break;
                    }
                    if (k + 1 < l.size() && l[k + 1] - l[k] > reach) break;
                }
                rises.emplace(key, up);
            }
            std::vector<std::uint32_t> free_points, rest;
            for (std::size_t k = 0; k < s.size(); ++k)
                (out.height_m[s[k]] <= o.split_height_m && !rises.at(column[k]) ? free_points : rest).push_back(s[k]);
            std::vector<std::vector<std::uint32_t>> parts,
                free_parts = clusterPoints(cloud, free_points, lo, o, out.core_points);
            for (auto& p : free_parts) {
                if (p.size() >= kSplitMinFactor * std::size_t(o.min_points))
                    parts.push_back(std::move(p));
                else
                    rest.insert(rest.end(), p.begin(), p.end());
            }
            if (parts.empty()) {
                kept.push_back(std::move(s));
                continue;
            }
            std::sort(rest.begin(), rest.end());
            parts.push_back(std::move(rest));
            ++out.split_segments;
            for (auto& p : parts)
                if (big(p)) kept.push_back(std::move(p));
        }
        // Segments in order of their first point again.
        std::stable_sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
        out.segments = std::move(kept);
    }
    return out;
}

}  // namespace detect
