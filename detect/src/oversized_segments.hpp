// detect/src/oversized_segments.hpp (internal): the segmentation's step 5
// (detect/segmentation.hpp), a segment larger in plan than any vehicle split
// hierarchically. A vehicle that touches low clutter (a real place's 0.5 m boxes of
// hedges and parked cars, or a noisy sensor's sheet of ground the terrain fit left half a
// metre up) joins it into one low segment many metres across, which the model scores as
// clutter. Such a segment's points are measured against its own lower envelope (the
// lowest height above the terrain within kEnvelopeReach_m of each point), and the points
// in each of kOversizeBands above it are clustered again (as in step 2): each cluster of
// vehicle size (at most max_vehicle_length_m by max_vehicle_width_m along its principal
// axes in plan, kChildMinFactor x min_points points or more) takes every point of the
// segment inside its convex hull in plan (widened by kHullMargin voxels; under a cap, only
// up to the cluster's own top and a voxel) as a segment of its own; what no cluster took
// stays one segment. Its tables per point of the one segment split at a time stay under
// step 2's peak for the whole cloud, and its envelope grid under 8 MB.
#pragma once
#include <detect/segmentation.hpp>

#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace detect::detail {

/// The height bands above a segment's lower envelope whose points are clustered again,
/// metres (lower cut, upper cap), tried in this order: cuts rising from 0.3 m (a vehicle
/// beside low clutter or in a raised sheet of ground), then caps falling from 3 m (a
/// vehicle under a crown that reaches down to its roof).
struct OversizeBand {
    double cut_m;
    double cap_m;
};
inline constexpr double kNoCap = 1e9;
inline constexpr std::array<OversizeBand, 6> kOversizeBands = {
    {{0.3, kNoCap}, {0.6, kNoCap}, {1.0, kNoCap}, {0.3, 3.0}, {0.3, 2.5}, {0.3, 2.0}}};
/// The lower envelope at a point: the lowest point of the segment within this many
/// metres in plan (a square window of envelope cells): more than half the widest
/// vehicle, so that the envelope under a vehicle's roof is the ground beside it.
inline constexpr double kEnvelopeReach_m = 2.0;
/// The envelope's cells are this many voxels a side (1 m at the default voxel).
inline constexpr double kEnvelopeCellVoxels = 4.0;
/// A child's hull in plan is widened by this many voxels (the points' noise; a wider
/// margin takes the clutter that touches the vehicle).
inline constexpr double kHullMargin = 0.5;
/// The envelope's grid has at most this many cells (larger cells past it).
inline constexpr double kMaxEnvelopeCells = double(1 << 20);

/// A segment's extents in plan along its principal axes, metres: length >= width.
struct PlanExtent {
    double length_m = 0;
    double width_m = 0;
};

/// The plan extents of the points `idx` of `cloud` along the principal axes of their
/// (x, y) covariance; zero for an empty set.
PlanExtent planExtent(const core::PointCloud& cloud, std::span<const std::uint32_t> idx);

/// Step 5 on every segment of `out` that is oversized (longer than o.max_vehicle_length_m
/// or wider than o.max_vehicle_width_m in plan) and not tall (no point above
/// o.split_height_m when that is set): its vehicle-sized children become segments of their
/// own and the rest one segment; segments under o.min_points are dropped. Segments stay in
/// order of their first point. Does nothing when o.max_vehicle_length_m is 0. The result
/// does not depend on `work_parts`.
void splitOversizedSegments(const core::PointCloud& cloud, const glm::dvec3& lo, const SegmentOptions& o,
                            std::size_t work_parts, Segmentation& out);

}  // namespace detect::detail
