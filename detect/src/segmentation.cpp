// detect/src/segmentation.cpp: the segments of detect/segmentation.hpp.
#include <detect/segmentation.hpp>

#include <core/error.hpp>

#include "parts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <span>
#include <sstream>

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

// The clustering cuts its work into parts of at least this many points, and at most
// kMaxParts of them: each part beyond the first holds tables of its own over the voxels.
constexpr std::size_t kMinPointsPerPart = std::size_t(1) << 16;
constexpr std::size_t kMaxParts = 4;

// How many parts `n` items make: `parts`, fewer when each would hold under
// kMinPointsPerPart, at least one.
std::size_t partsFor(std::size_t n, std::size_t parts) {
    return std::clamp<std::size_t>(n / kMinPointsPerPart, 1, std::max<std::size_t>(parts, 1));
}

// Sorts (key, index) pairs by key, keeping their order among equal keys: a
// least-significant-digit radix sort over the bytes in which the keys differ, so the
// result equals std::stable_sort's by key. Each pass counts and moves the pairs in
// `parts` runs on threads of their own; run p's pairs of a digit go after those of runs
// before p, so the result does not depend on `parts`.
void sortByKey(std::vector<std::pair<std::uint64_t, std::uint32_t>>& keyed, std::size_t parts) {
    const std::size_t n = keyed.size();
    if (n < 2) return;
    parts = partsFor(n, parts);
    std::uint64_t differ = 0;
    for (const auto& e : keyed) differ |= e.first ^ keyed[0].first;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> other(n);
    std::vector<std::array<std::size_t, 256>> start(parts);
    for (int shift = 0; shift < 64; shift += 8) {
        if (((differ >> shift) & 0xffu) == 0) continue;
        runParts(parts, [&](std::size_t part) {
            start[part].fill(0);
            for (std::size_t i = partStart(n, parts, part); i < partStart(n, parts, part + 1); ++i)
                ++start[part][(keyed[i].first >> shift) & 0xffu];
        });
        std::size_t at = 0;
        for (std::size_t digit = 0; digit < 256; ++digit)
            for (std::size_t part = 0; part < parts; ++part) {
                const std::size_t c = start[part][digit];
                start[part][digit] = at;
                at += c;
            }
        runParts(parts, [&](std::size_t part) {
            std::array<std::size_t, 256>& next = start[part];
            for (std::size_t i = partStart(n, parts, part); i < partStart(n, parts, part + 1); ++i)
                other[next[(keyed[i].first >> shift) & 0xffu]++] = keyed[i];
        });
        keyed.swap(other);
    }
}

// Clusters the points `idx` (ascending indices into the cloud) on voxels of o.voxel_m
// whose cells are counted from `lo`: union-find over pairs of dense voxels (core_points
// points or more) whose centroids lie within o.cluster_tolerance_m; a sparse voxel joins
// the segment of its nearest dense voxel within reach. Groups in order of their first
// point, each ascending; small ones are not dropped here. The keys and the two sweeps
// over the voxels run in `parts` parts on threads of their own; the segments do not
// depend on it.
std::vector<std::vector<std::uint32_t>> clusterPoints(const core::PointCloud& cloud, std::span<const std::uint32_t> idx,
                                                      const glm::dvec3& lo, const SegmentOptions& o, int core_points,
                                                      std::size_t parts, std::size_t* voxels_out = nullptr) {
    const std::size_t n = idx.size();
    parts = partsFor(n, parts);
    // Each point's voxel key; sorted by key, then by position in idx, the points come in
    // runs of one voxel each, its points in their original order.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
    runParts(parts, [&](std::size_t part) {
        for (std::size_t k = partStart(n, parts, part); k < partStart(n, parts, part + 1); ++k) {
            const glm::dvec3 p = glm::dvec3(cloud.points[idx[k]].position) - lo;
            const std::int64_t cx = std::int64_t(std::floor(p.x / o.voxel_m)),
                               cy = std::int64_t(std::floor(p.y / o.voxel_m)),
                               cz = std::int64_t(std::floor(p.z / o.voxel_m));
            if (cx > kKeyMax - kKeyOffset || cy > kKeyMax - kKeyOffset || cz > kKeyMax - kKeyOffset)
                throw core::Error("detect: the cloud is too wide for --segment-voxel-m " + std::to_string(o.voxel_m) +
                                  " (at most 2^20 voxels across); allowed a larger voxel");
            keyed[k] = {packKey(cx, cy, cz), std::uint32_t(k)};
        }
    });
    sortByKey(keyed, parts);

    // Voxels in key order (s): key, point count, first point (the smallest position in
    // idx, which breaks ties between equally near voxels) and centroid, summed over the
    // voxel's run in the sorted pairs, that is in the points' order. The segments (and
    // their order, that of their first points) do not depend on how neighbours are found.
    // Each part takes the runs that start in its share of the pairs.
    std::vector<std::size_t> run_start(parts + 1, n), runs_before(parts + 1, 0);
    runParts(parts, [&](std::size_t part) {
        std::size_t i = partStart(n, parts, part);
        while (i > 0 && i < n && keyed[i].first == keyed[i - 1].first) ++i;
        run_start[part] = i;
    });
    for (std::size_t part = 0; part < parts; ++part) {
        std::size_t runs = 0;
        for (std::size_t i = run_start[part]; i < run_start[part + 1]; ++i)
            runs += i == run_start[part] || keyed[i].first != keyed[i - 1].first;
        runs_before[part + 1] = runs_before[part] + runs;
    }
    const std::size_t voxels = runs_before[parts];
    if (voxels_out) *voxels_out = voxels;
    std::vector<std::uint64_t> key(voxels);
    std::vector<std::uint32_t> count(voxels), first(voxels), voxel_of_point(n);
    std::vector<glm::dvec3> centroid(voxels);
    runParts(parts, [&](std::size_t part) {
        std::size_t v = runs_before[part];
        for (std::size_t i = run_start[part]; i < run_start[part + 1]; ++v) {
            std::size_t j = i;
            glm::dvec3 sum(0.0);
            for (; j < run_start[part + 1] && keyed[j].first == keyed[i].first; ++j) {
                // The points are read in key order, scattered over the cloud: ask for the
                // point 16 places ahead (and, before that, its place in idx) while this sums.
                if (j + 32 < n) __builtin_prefetch(&idx[keyed[j + 32].second]);
                if (j + 16 < n) __builtin_prefetch(&cloud.points[idx[keyed[j + 16].second]]);
                sum += glm::dvec3(cloud.points[idx[keyed[j].second]].position) - lo;
                voxel_of_point[keyed[j].second] = std::uint32_t(v);
            }
            key[v] = keyed[i].first;
            count[v] = std::uint32_t(j - i);
            first[v] = keyed[i].second;
            centroid[v] = sum / double(j - i);
            i = j;
        }
    });
    keyed = {};

    // Union-find over pairs of dense voxels within reach (cells up to r apart on each
    // axis, centroids within the tolerance). A voxel with fewer than core_points points
    // does not join two segments: it is attached to its nearest dense voxel within reach
    // afterwards, so a sparse trail of noise or mixed returns between a crown and a
    // vehicle does not chain them.
    const auto dense = [&](std::size_t s) { return count[s] >= std::uint32_t(core_points); };
    const std::int64_t r = std::int64_t(std::ceil(o.cluster_tolerance_m / o.voxel_m));
    const double tol2 = o.cluster_tolerance_m * o.cluster_tolerance_m;
    // Voxel indices in key order: the dense ones, which join segments, and the sparse ones,
    // which each take the segment of their nearest dense voxel.
    std::vector<std::uint32_t> dense_voxels, sparse_voxels;
    for (std::size_t s = 0; s < voxels; ++s) (dense(s) ? dense_voxels : sparse_voxels).push_back(std::uint32_t(s));
    const auto keysOf = [&](const std::vector<std::uint32_t>& list) {
        std::vector<std::uint64_t> k(list.size());
        for (std::size_t u = 0; u < list.size(); ++u) k[u] = key[list[u]];
        return k;
    };
    const std::vector<std::uint64_t> dense_keys = keysOf(dense_voxels), sparse_keys = keysOf(sparse_voxels);
    // `visit(s, t, squared distance, t's place in to)` for every voxel s of from[begin,
    // end) and every voxel t of `to` within reach of s (cells at most r apart on each axis, centroids
    // within the tolerance), s != t; with forward_only each unordered pair once (t's cell
    // the larger). Both lists are in key order, so in each column (dx, dy) of the
    // (2r + 1)^2 around s, the cells dz in [-r, r] are one range of `to` that only moves
    // forward from one s to the next: one cursor per column, placed by a binary search
    // at its first use, finds it without a lookup.
    const auto sweep = [&](const std::vector<std::uint32_t>& from, std::size_t begin, std::size_t end,
                           const std::vector<std::uint32_t>& to, const std::vector<std::uint64_t>& to_key,
                           bool forward_only, auto&& visit) {
        const std::int64_t side = 2 * r + 1;
        const std::size_t tn = to.size();
        std::vector<std::size_t> cursor(std::size_t(side * side), SIZE_MAX);
        const std::int64_t mask = (std::int64_t(1) << 21) - 1;
        for (std::size_t f = begin; f < end; ++f) {
            const std::uint32_t s = from[f];
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
                    if (c == SIZE_MAX)
                        c = std::size_t(std::lower_bound(to_key.begin(), to_key.end(), k0) - to_key.begin());
                    while (c < tn && to_key[c] < k0) ++c;
                    for (std::size_t u = c; u < tn && to_key[u] <= k1; ++u) {
                        const std::uint32_t t = to[u];
                        if (t == s) continue;
                        const glm::dvec3 d = centroid[s] - centroid[t];
                        const double d2 = glm::dot(d, d);
                        if (d2 <= tol2) visit(s, t, d2, u);
                    }
                }
        }
    };
    const std::size_t dn = dense_voxels.size();
    // Each part joins the pairs of its dense voxels in a union-find of its own (part 0 in
    // the result's); the others are merged into it. The groups a union-find ends with do
    // not depend on the order of the unions, and each root is its group's smallest voxel.
    std::vector<std::vector<std::uint32_t>> parents(parts);
    runParts(parts, [&](std::size_t part) {
        std::vector<std::uint32_t>& parent = parents[part];
        parent.resize(voxels);
        std::iota(parent.begin(), parent.end(), 0u);
        sweep(dense_voxels, partStart(dn, parts, part), partStart(dn, parts, part + 1), dense_voxels, dense_keys, true,
              [&](std::uint32_t s, std::uint32_t t, double, std::size_t) {
                  const std::uint32_t a = findRoot(parent, s), b = findRoot(parent, t);
                  if (a != b) parent[std::max(a, b)] = std::min(a, b);
              });
    });
    std::vector<std::uint32_t>& parent = parents[0];
    for (std::size_t part = 1; part < parts; ++part) {
        std::vector<std::uint32_t>& other = parents[part];
        for (const std::uint32_t s : dense_voxels) {
            const std::uint32_t b0 = findRoot(other, s);
            if (b0 == s) continue;
            const std::uint32_t a = findRoot(parent, s), b = findRoot(parent, b0);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
        other = {};
    }
    // Sparse voxels: the segment of the nearest dense voxel (ties: the one whose first point
    // comes first); alone
    // when none is within reach. The nearest is the minimum over all pairs (by distance,
    // then id), so neither the order of the pairs nor the parts that saw them matter.
    struct Nearest {
        std::vector<std::uint32_t> attached;  // per sparse voxel (its place in sparse_voxels)
        std::vector<double> d2;
    };
    const std::size_t sn = sparse_voxels.size();
    std::vector<Nearest> nearest(parts);
    const auto closer = [&](double d2, std::uint32_t t, double best_d2, std::uint32_t best) {
        return d2 < best_d2 || (d2 == best_d2 && best != UINT32_MAX && first[t] < first[best]);
    };
    runParts(parts, [&](std::size_t part) {
        Nearest& m = nearest[part];
        m.attached.assign(sn, UINT32_MAX);
        m.d2.assign(sn, tol2 + 1.0);
        sweep(dense_voxels, partStart(dn, parts, part), partStart(dn, parts, part + 1), sparse_voxels, sparse_keys,
              false, [&](std::uint32_t d, std::uint32_t, double d2, std::size_t u) {
                  if (closer(d2, d, m.d2[u], m.attached[u])) m.d2[u] = d2, m.attached[u] = d;
              });
    });
    for (std::size_t part = 1; part < parts; ++part) {
        for (std::size_t u = 0; u < sn; ++u)
            if (nearest[part].attached[u] != UINT32_MAX &&
                closer(nearest[part].d2[u], nearest[part].attached[u], nearest[0].d2[u], nearest[0].attached[u]))
                nearest[0].d2[u] = nearest[part].d2[u], nearest[0].attached[u] = nearest[part].attached[u];
        nearest[part] = {};
    }
    for (std::size_t u = 0; u < sn; ++u)
        if (nearest[0].attached[u] != UINT32_MAX) parent[sparse_voxels[u]] = findRoot(parent, nearest[0].attached[u]);
    nearest = {};

    // Groups in the order of their first point, each ascending.
    std::vector<std::uint32_t> segment_of_root(voxels, UINT32_MAX), segment_of_voxel(voxels, UINT32_MAX), sizes;
    for (std::size_t k = 0; k < n; ++k) {
        std::uint32_t& segment = segment_of_voxel[voxel_of_point[k]];
        if (segment == UINT32_MAX) {
            std::uint32_t& of_root = segment_of_root[findRoot(parent, voxel_of_point[k])];
            if (of_root == UINT32_MAX) {
                of_root = std::uint32_t(sizes.size());
                sizes.push_back(0);
            }
            segment = of_root;
        }
        ++sizes[segment];
    }
    std::vector<std::vector<std::uint32_t>> segments(sizes.size());
    for (std::size_t g = 0; g < sizes.size(); ++g) segments[g].reserve(sizes[g]);
    for (std::size_t k = 0; k < n; ++k) segments[segment_of_voxel[voxel_of_point[k]]].push_back(idx[k]);
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

Segmentation segmentCloud(const core::PointCloud& cloud, const SegmentOptions& o, int threads) {
    validate(o);
    if (threads < 1) throw core::Error("detect: threads = " + std::to_string(threads) + ": allowed >= 1");
    const std::size_t work_parts = std::min(std::size_t(threads), kMaxParts);
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
    std::vector<std::vector<std::uint32_t>> segments =
        clusterPoints(cloud, above, lo, o, out.core_points, work_parts, &out.voxels);

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
        std::vector<std::vector<std::uint32_t>> kept;
        std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
        std::vector<std::uint8_t> rises;
        for (auto& s : out.segments) {
            const bool tall =
                std::any_of(s.begin(), s.end(), [&](std::uint32_t i) { return out.height_m[i] > o.split_height_m; });
            if (!tall) {
                kept.push_back(std::move(s));
                continue;
            }
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
            if (parts.empty()) {
                kept.push_back(std::move(s));
                continue;
            }
            // rest: ascending, then the small parts' points, which are merged in.
            std::sort(rest.begin() + std::ptrdiff_t(rest_sorted), rest.end());
            std::inplace_merge(rest.begin(), rest.begin() + std::ptrdiff_t(rest_sorted), rest.end());
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
