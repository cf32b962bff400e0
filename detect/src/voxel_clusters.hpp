// detect/src/voxel_clusters.hpp (internal): the Euclidean clustering on voxels that the
// trained detector's segmentation runs (detect/segmentation.hpp, steps 2 and 4), with the
// packed voxel keys and the stable radix sort its steps share.
#pragma once
#include <detect/segmentation.hpp>

#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace detect::detail {

// Voxel keys packed into 64 bits: 21 bits per axis, offset so that negative indices fit.
inline constexpr std::int64_t kKeyOffset = std::int64_t(1) << 20;
inline constexpr std::int64_t kKeyMax = (std::int64_t(1) << 21) - 1;

inline std::uint64_t packKey(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (std::uint64_t(x + kKeyOffset) << 42) | (std::uint64_t(y + kKeyOffset) << 21) |
           std::uint64_t(z + kKeyOffset);
}

// The clustering cuts its work into parts of at least this many points, and at most
// kMaxParts of them: each part beyond the first holds tables of its own over the voxels.
inline constexpr std::size_t kMinPointsPerPart = std::size_t(1) << 16;
inline constexpr std::size_t kMaxParts = 4;

// How many parts `n` items make: `parts`, fewer when each would hold under
// kMinPointsPerPart, at least one.
inline std::size_t partsFor(std::size_t n, std::size_t parts) {
    return std::clamp<std::size_t>(n / kMinPointsPerPart, 1, std::max<std::size_t>(parts, 1));
}

/// (key, index) pairs, sorted by key by sortByKey.
using KeyedPoints = std::vector<std::pair<std::uint64_t, std::uint32_t>>;

/// Sorts (key, index) pairs by key, keeping their order among equal keys (the result
/// equals std::stable_sort's by key), in up to `parts` parts on threads of their own; the
/// result does not depend on `parts`.
void sortByKey(KeyedPoints& keyed, std::size_t parts);

/// Clusters the points `idx` (ascending indices into the cloud) on voxels of o.voxel_m
/// whose cells are counted from `lo`: union-find over pairs of dense voxels (core_points
/// points or more) whose centroids lie within o.cluster_tolerance_m; a sparse voxel joins
/// the segment of its nearest dense voxel within reach. Returns the groups in order of
/// their first point, each ascending; small ones are not dropped here. The work runs in
/// up to `parts` parts on threads of their own; the segments do not depend on it.
/// `voxels_out`, when given, receives the number of occupied voxels. Throws
/// core::Error("detect: the cloud is too wide for --segment-voxel-m ...").
std::vector<std::vector<std::uint32_t>> clusterPoints(const core::PointCloud& cloud, std::span<const std::uint32_t> idx,
                                                      const glm::dvec3& lo, const SegmentOptions& o, int core_points,
                                                      std::size_t parts, std::size_t* voxels_out = nullptr);

}  // namespace detect::detail
