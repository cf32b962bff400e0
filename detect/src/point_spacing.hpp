// detect/src/point_spacing.hpp (internal): the cloud's local point spacing, measured on the
// points the segmentation clusters, and the scale it sets for the clustering's lengths
// (detect/segmentation.hpp, step 2), so that a sparse airborne survey forms segments as a
// drone's dense cloud does.
#pragma once
#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>

namespace detect::detail {

// The spacing is measured on at most this many of the points, evenly along their list.
inline constexpr std::size_t kSpacingSamples = 4096;
// The spacing is the distance to this nearest neighbour (not the first: a survey's first
// and last returns of one pulse often lie together).
inline constexpr std::size_t kSpacingNeighbour = 2;
// The search for a neighbour stops at this distance: the spacing is then reported as
// this (a cloud that sparse gets the largest scale anyway).
inline constexpr double kSpacingMaxM = 16.0;

/// The median distance from a point of `idx` (indices into the cloud) to its nearest other
/// point of `idx`, over up to kSpacingSamples of them taken evenly along `idx`; at most
/// kSpacingMaxM, 0 when `idx` holds fewer than two points. A pure function of its inputs.
/// Exact: the neighbours are searched on a grid whose cell doubles from 0.125 m until
/// the median neighbour lies within one cell.
double medianSpacing(const core::PointCloud& cloud, std::span<const std::uint32_t> idx);

// The covered area is counted on cells of this side (larger on a cloud so wide that the
// grid would hold more than kCoverMaxCells of them).
inline constexpr double kCoverCell_m = 8.0;
inline constexpr std::size_t kCoverMaxCells = std::size_t(1) << 22;

/// The cloud's points per square metre of the ground it covers: all its points over the
/// area of the kCoverCell_m cells of x, y that hold at least one (so a drone's round
/// footprint or a survey's ragged edge is not counted as empty ground); 0 for an empty
/// cloud. One pass over the points and a bitmap of at most kCoverMaxCells cells.
double coveredDensity(const core::PointCloud& cloud);

}  // namespace detect::detail
