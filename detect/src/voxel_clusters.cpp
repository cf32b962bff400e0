// detect/src/voxel_clusters.cpp: the clustering on voxels of detect/src/voxel_clusters.hpp,
// a step each: the points' voxel keys, the voxels (count, first point, centroid), the
// pairs of voxels within reach, the union-find over the dense voxels, the sparse voxels
// attached to their nearest dense one, and the points grouped by their voxels' segments.
#include "voxel_clusters.hpp"

#include "parts.hpp"

#include <core/error.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>

namespace detect::detail {

// A least-significant-digit radix sort over the bytes in which the keys differ. Each pass
// counts and moves the pairs in `parts` runs on threads of their own; run p's pairs of a
// digit go after those of runs before p, so the result does not depend on `parts`.
void sortByKey(KeyedPoints& keyed, std::size_t parts) {
    const std::size_t n = keyed.size();
    if (n < 2) return;
    parts = partsFor(n, parts);
    std::uint64_t differ = 0;
    for (const auto& e : keyed) differ |= e.first ^ keyed[0].first;
    KeyedPoints other(n);
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

namespace {

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

// Joins the groups of a and b in `parent`; each root stays its group's smallest voxel.
void join(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
    a = findRoot(parent, a);
    b = findRoot(parent, b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

// Each point's voxel key and its place in idx, sorted by key, then by place: the points
// come in runs of one voxel each, its points in their original order.
KeyedPoints voxelKeys(const core::PointCloud& cloud, std::span<const std::uint32_t> idx, const glm::dvec3& lo,
                      const SegmentOptions& o, std::size_t parts) {
    const std::size_t n = idx.size();
    KeyedPoints keyed(n);
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
    return keyed;
}

// The occupied voxels in key order (s): key, point count, first point (the smallest place
// in idx, which breaks ties between equally near voxels) and centroid; and each point's
// voxel, by its place in idx.
struct Voxels {
    std::vector<std::uint64_t> key;
    std::vector<std::uint32_t> count, first;
    std::vector<glm::dvec3> centroid;
    std::vector<std::uint32_t> voxel_of_point;
    std::size_t size() const { return key.size(); }
};

// The voxels of the sorted `keyed`, the centroid summed over the voxel's run in the
// sorted pairs, that is in the points' order. The segments (and their order, that of
// their first points) do not depend on how neighbours are found. Each part takes the
// runs that start in its share of the pairs.
Voxels voxelsOf(const core::PointCloud& cloud, std::span<const std::uint32_t> idx, const glm::dvec3& lo,
                const KeyedPoints& keyed, std::size_t parts) {
    const std::size_t n = keyed.size();
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
    Voxels v;
    v.key.resize(voxels);
    v.count.resize(voxels);
    v.first.resize(voxels);
    v.voxel_of_point.resize(n);
    v.centroid.resize(voxels);
    runParts(parts, [&](std::size_t part) {
        std::size_t s = runs_before[part];
        for (std::size_t i = run_start[part]; i < run_start[part + 1]; ++s) {
            std::size_t j = i;
            glm::dvec3 sum(0.0);
            for (; j < run_start[part + 1] && keyed[j].first == keyed[i].first; ++j) {
                // The points are read in key order, scattered over the cloud: ask for the
                // point 16 places ahead (and, before that, its place in idx) while this sums.
                if (j + 32 < n) __builtin_prefetch(&idx[keyed[j + 32].second]);
                if (j + 16 < n) __builtin_prefetch(&cloud.points[idx[keyed[j + 16].second]]);
                sum += glm::dvec3(cloud.points[idx[keyed[j].second]].position) - lo;
                v.voxel_of_point[keyed[j].second] = std::uint32_t(s);
            }
            v.key[s] = keyed[i].first;
            v.count[s] = std::uint32_t(j - i);
            v.first[s] = keyed[i].second;
            v.centroid[s] = sum / double(j - i);
            i = j;
        }
    });
    return v;
}

// Voxel indices in key order, with their keys.
struct VoxelList {
    std::vector<std::uint32_t> ids;
    std::vector<std::uint64_t> keys;
};

// The pairs of voxels within reach: cells at most r apart on each axis, centroids within
// the tolerance.
class VoxelPairs {
  public:
    VoxelPairs(const Voxels& voxels, const SegmentOptions& o)
        : voxels_(voxels),
          r_(std::int64_t(std::ceil(o.cluster_tolerance_m / o.voxel_m))),
          tol2_(o.cluster_tolerance_m * o.cluster_tolerance_m) {}

    const Voxels& voxels() const { return voxels_; }
    double tolerance2() const { return tol2_; }

    // `visit(s, t, squared distance, t's place in to)` for every voxel s of
    // from.ids[begin, end) and every voxel t of `to` within reach of s, s != t; with
    // forward_only each unordered pair once (t's cell the larger). Both lists are in key
    // order, so in each column (dx, dy) of the (2r + 1)^2 around s, the cells dz in
    // [-r, r] are one range of `to` that only moves forward from one s to the next: one
    // cursor per column, placed by a binary search at its first use, finds it without a
    // lookup.
    template <class Visit>
    void sweep(const VoxelList& from, std::size_t begin, std::size_t end, const VoxelList& to, bool forward_only,
               Visit&& visit) const {
        const std::int64_t r = r_, side = 2 * r + 1;
        const std::size_t tn = to.ids.size();
        std::vector<std::size_t> cursor(std::size_t(side * side), SIZE_MAX);
        const std::int64_t mask = (std::int64_t(1) << 21) - 1;
        for (std::size_t f = begin; f < end; ++f) {
            const std::uint32_t s = from.ids[f];
            const std::uint64_t key = voxels_.key[s];
            const std::int64_t x = std::int64_t(key >> 42) - kKeyOffset,
                               y = std::int64_t((key >> 21) & std::uint64_t(mask)) - kKeyOffset,
                               z = std::int64_t(key & std::uint64_t(mask)) - kKeyOffset;
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
                        c = std::size_t(std::lower_bound(to.keys.begin(), to.keys.end(), k0) - to.keys.begin());
                    while (c < tn && to.keys[c] < k0) ++c;
                    for (std::size_t u = c; u < tn && to.keys[u] <= k1; ++u) {
                        const std::uint32_t t = to.ids[u];
                        if (t == s) continue;
                        const glm::dvec3 d = voxels_.centroid[s] - voxels_.centroid[t];
                        const double d2 = glm::dot(d, d);
                        if (d2 <= tol2_) visit(s, t, d2, u);
                    }
                }
        }
    }

  private:
    const Voxels& voxels_;
    std::int64_t r_;
    double tol2_;
};

// Union-find over the pairs of dense voxels within reach: the parent of each voxel (a
// sparse one its own root). Each part joins the pairs of its dense voxels in a union-find
// of its own (part 0 in the result's); the others are merged into it. The groups a
// union-find ends with do not depend on the order of the unions, and each root is its
// group's smallest voxel.
std::vector<std::uint32_t> joinDenseVoxels(const VoxelPairs& pairs, const VoxelList& dense, std::size_t parts) {
    const std::size_t dn = dense.ids.size();
    std::vector<std::vector<std::uint32_t>> parents(parts);
    runParts(parts, [&](std::size_t part) {
        std::vector<std::uint32_t>& parent = parents[part];
        parent.resize(pairs.voxels().size());
        std::iota(parent.begin(), parent.end(), 0u);
        pairs.sweep(dense, partStart(dn, parts, part), partStart(dn, parts, part + 1), dense, true,
                    [&](std::uint32_t s, std::uint32_t t, double, std::size_t) { join(parent, s, t); });
    });
    std::vector<std::uint32_t> parent = std::move(parents[0]);
    for (std::size_t part = 1; part < parts; ++part) {
        std::vector<std::uint32_t>& other = parents[part];
        for (const std::uint32_t s : dense.ids) {
            const std::uint32_t b0 = findRoot(other, s);
            if (b0 != s) join(parent, s, b0);
        }
        other = {};
    }
    return parent;
}

// Each sparse voxel takes the segment of the nearest dense voxel (ties: the one whose
// first point comes first); it stays alone when none is within reach. The nearest is the
// minimum over all pairs (by distance, then id), so neither the order of the pairs nor
// the parts that saw them matter.
void attachSparseVoxels(const VoxelPairs& pairs, const VoxelList& dense, const VoxelList& sparse, std::size_t parts,
                        std::vector<std::uint32_t>& parent) {
    struct Nearest {
        std::vector<std::uint32_t> attached;  // per sparse voxel (its place in sparse.ids)
        std::vector<double> d2;
    };
    const std::size_t dn = dense.ids.size(), sn = sparse.ids.size();
    const std::vector<std::uint32_t>& first = pairs.voxels().first;
    std::vector<Nearest> nearest(parts);
    const auto closer = [&](double d2, std::uint32_t t, double best_d2, std::uint32_t best) {
        return d2 < best_d2 || (d2 == best_d2 && best != UINT32_MAX && first[t] < first[best]);
    };
    runParts(parts, [&](std::size_t part) {
        Nearest& m = nearest[part];
        m.attached.assign(sn, UINT32_MAX);
        m.d2.assign(sn, pairs.tolerance2() + 1.0);
        pairs.sweep(dense, partStart(dn, parts, part), partStart(dn, parts, part + 1), sparse, false,
                    [&](std::uint32_t d, std::uint32_t, double d2, std::size_t u) {
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
        if (nearest[0].attached[u] != UINT32_MAX) parent[sparse.ids[u]] = findRoot(parent, nearest[0].attached[u]);
}

// The points of idx grouped by their voxels' roots, groups in the order of their first
// point, each ascending.
std::vector<std::vector<std::uint32_t>> groupPoints(std::span<const std::uint32_t> idx, const Voxels& v,
                                                    std::vector<std::uint32_t>& parent) {
    const std::size_t n = idx.size(), voxels = v.size();
    std::vector<std::uint32_t> segment_of_root(voxels, UINT32_MAX), segment_of_voxel(voxels, UINT32_MAX), sizes;
    for (std::size_t k = 0; k < n; ++k) {
        std::uint32_t& segment = segment_of_voxel[v.voxel_of_point[k]];
        if (segment == UINT32_MAX) {
            std::uint32_t& of_root = segment_of_root[findRoot(parent, v.voxel_of_point[k])];
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
    for (std::size_t k = 0; k < n; ++k) segments[segment_of_voxel[v.voxel_of_point[k]]].push_back(idx[k]);
    return segments;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> clusterPoints(const core::PointCloud& cloud, std::span<const std::uint32_t> idx,
                                                      const glm::dvec3& lo, const SegmentOptions& o, int core_points,
                                                      std::size_t parts, std::size_t* voxels_out) {
    parts = partsFor(idx.size(), parts);
    Voxels voxels;
    {
        const KeyedPoints keyed = voxelKeys(cloud, idx, lo, o, parts);
        voxels = voxelsOf(cloud, idx, lo, keyed, parts);
    }
    if (voxels_out) *voxels_out = voxels.size();

    // A voxel with fewer than core_points points does not join two segments: it is
    // attached to its nearest dense voxel within reach afterwards, so a sparse trail of
    // noise or mixed returns between a crown and a vehicle does not chain them.
    VoxelList dense, sparse;
    for (std::size_t s = 0; s < voxels.size(); ++s) {
        VoxelList& list = voxels.count[s] >= std::uint32_t(core_points) ? dense : sparse;
        list.ids.push_back(std::uint32_t(s));
        list.keys.push_back(voxels.key[s]);
    }
    const VoxelPairs pairs(voxels, o);
    std::vector<std::uint32_t> parent = joinDenseVoxels(pairs, dense, parts);
    attachSparseVoxels(pairs, dense, sparse, parts, parent);
    return groupPoints(idx, voxels, parent);
}

}  // namespace detect::detail
