// detect/segmentation.hpp: the segments a trained detector classifies. The ground is a
// fitted terrain, not a plane: SMRF (sim/ground.hpp, Pingel et al. 2013) gives each point
// its height above a surface that follows hills and slopes, so a target on a slope stands
// out of it instead of merging into a tilted "ground" left over by a per-tile plane.
//
//   1) terrain: SMRF on the whole cloud, fed each point with its view, so on a noisy
//      sensor's thick ground each view's height error is taken off and the terrain runs
//      through the ground's centre (sim's whole-cloud fit, docs/ground.md); every point
//      gets its height above the terrain, and the ground's thickness is measured; on a
//      cloud so sparse that the terrain's cells would hold fewer than
//      kTerrainPointsPerCell points on average (an airborne survey at a metre's spacing
//      or more), the cell grows to hold that many (the window stays in metres): most
//      cells of a finer grid are empty and only interpolated, at a cost that grows with
//      their number;
//   1b) with level_cell_m > 0, the terrain is levelled on the ground's own points: in
//      squares of that side, the heights of the low points gather in a narrow band (the
//      ground; a vehicle's or a shrub's points spread), whose mean height is taken off
//      (interpolated between the squares), so ground the fit passed under (a patch of
//      misregistered views on a sparse orbit) no longer stands above it;
//   2) the points higher than min_height_m or ground_sigmas thicknesses above it (and not
//      SMRF ground) are binned into voxels of voxel_m; two dense voxels (core_points
//      points or more) whose centroids are within cluster_tolerance_m join one segment
//      (union-find, the Euclidean clustering of Rusu's thesis on voxel centroids, as the
//      baseline does); a sparse voxel joins the segment of its nearest dense voxel
//      within reach (DBSCAN's border points), so it never chains two segments;
//      on a sparsely sampled cloud (an airborne survey at a metre's spacing) the voxel,
//      the join distance and min_points follow the measured point spacing (the median
//      distance from a point above the terrain to its second nearest, as a survey's
//      first and last returns of one pulse often lie together): past a spacing of the
//      join distance itself, the join distance grows three times as fast as the spacing,
//      the voxel by the same factor (at most kMaxSpacingScale) and min_points shrinks by
//      its square (not under kMinScaledPoints); on a drone's dense cloud the factor is 1
//      and nothing changes;
//   3) segments under min_points points are dropped as noise;
//   4) a segment reaching above split_height_m gives up what stands free below that
//      height: the points below it in columns of its footprint that do not rise without
//      a gap to above it (walls, trunks) are clustered as in step 2, and each cluster of
//      ten times min_points or more becomes a segment (a vehicle against a wall, or
//      under crowns that touch each other); the rest stays one segment;
//   5) a segment that is not tall but larger in plan than any vehicle (longer than
//      max_vehicle_length_m or wider than max_vehicle_width_m along its principal axes: a
//      vehicle that touched low clutter or a raised sheet of noisy ground) is split
//      hierarchically: its points more than 0.3, 0.6 and 1.0 m above its own lower
//      envelope (the lowest height above the terrain within 2 m), then those between 0.3
//      m and 3, 2.5 or 2 m above it (under a crown), are clustered as in step 2, and each
//      cluster of vehicle size and ten times min_points or more takes the segment's
//      points inside its hull in plan (up to its own top under a cap) as a segment of its
//      own; the rest stays one segment.
#pragma once
#include <core/point_cloud.hpp>
#include <sim/ground.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace detect {

struct SegmentOptions {
    sim::SmrfOptions terrain;          // step 1 (PDAL's defaults)
    double min_height_m = 0.25;        // step 2: points at most this high above the terrain are ground
    double ground_sigmas = 3.0;        // step 2: ... or at most this many ground thicknesses (sigma), [0, 20]
    double voxel_m = 0.25;             // step 2's voxel side, [0.05, 10] m
    double cluster_tolerance_m = 0.5;  // step 2, (voxel_m / 2, 10] m
    int core_points =
        3;  // step 2: a voxel with fewer points joins no two segments (at most half a voxel face's share of the points), [1, 1000]
    int min_points = 20;  // step 3, >= 1
    // step 4: segments reaching above this height over the terrain give up what stands
    // free below it; 0 splits none, else [1, 100] m
    double split_height_m = 4.0;
    // step 2: whether voxel_m, cluster_tolerance_m and min_points follow the cloud's
    // measured point spacing where it is sparser than cluster_tolerance_m
    bool scale_with_spacing = true;
    // step 1b: the terrain levelled on the ground's own points in squares of this side
    // (the fullest height band of each square's low points is its ground); 0 levels
    // nothing (models written before the step), else [1, 100] m
    double level_cell_m = 8.0;
    // step 5: segments longer or wider than these in plan (the vehicle families reach
    // 12 m by 3.6 m) are split into vehicle-sized children; length 0 splits none (models
    // written before the step), else length [2, 100] m and width [1, length] m
    double max_vehicle_length_m = 14.0;
    double max_vehicle_width_m = 5.0;
};

/// Step 1's terrain cell holds at least this many of the cloud's points on average.
inline constexpr double kTerrainPointsPerCell = 2.0;

/// The largest factor step 2 scales its lengths by on a sparse cloud.
inline constexpr double kMaxSpacingScale = 8.0;
/// A scaled min_points goes no lower than this (nor than min_points itself).
inline constexpr int kMinScaledPoints = 4;

/// Throws core::Error("detect: <option> = <value>: allowed <range>").
void validate(const SegmentOptions& o);

struct Segmentation {
    /// One height above the terrain per point of the cloud, metres.
    std::vector<float> height_m;
    /// Each segment's point indices, ascending; segments ordered by their first point.
    std::vector<std::vector<std::uint32_t>> segments;
    std::size_t above_points = 0;        // points that went into step 2
    std::size_t voxels = 0;              // the voxels step 2 clustered them on
    double ground_sigma_m = 0;           // the ground thickness step 1 measured (one sigma)
    double min_height_m = 0;             // the height threshold step 2 used
    double points_per_voxel_face = 0;    // the cloud's points per voxel_m^2 of observed terrain
    int core_points = 1;                 // the dense voxels' bar step 2 used
    std::size_t split_segments = 0;      // segments step 4 split
    std::size_t oversized_segments = 0;  // segments step 5 split
    double spacing_m = 0;                // the points' median nearest-neighbour distance (0 unmeasured)
    double spacing_scale = 1;            // the factor step 2 scaled its lengths by (1: as given)
    double terrain_cell_m = 0;           // the terrain cell step 1 used (SmrfOptions::cell_m or larger)
    SegmentOptions used;                 // the options steps 2-4 ran with, after that scaling
};

/// The options steps 2-4 use on a cloud of median point spacing `spacing_m`: `o` itself
/// when o.scale_with_spacing is off or the spacing is at most o.cluster_tolerance_m;
/// else the voxel and join distance times scale = min((3 spacing - 2 tolerance) /
/// tolerance, kMaxSpacingScale) and min_points over scale^2 (rounded, at least
/// min(min_points, kMinScaledPoints)). Returns the scale through `scale_out`.
SegmentOptions scaledForSpacing(const SegmentOptions& o, double spacing_m, double* scale_out = nullptr);

/// Step 1's SMRF options on a cloud of `density_m2` points per square metre of covered
/// ground: `o` itself when its cell holds kTerrainPointsPerCell points or more on
/// average (or the density is unknown, 0), else the cell that holds that many, rounded
/// up to 0.1 m (at most the window, so that one opening remains).
sim::SmrfOptions terrainForDensity(const sim::SmrfOptions& o, double density_m2);

/// Steps 1-5 on `cloud`: a pure function of the cloud and the options, the same whatever
/// `threads` (the clustering's parts run on up to that many threads, at most 4). Throws
/// core::Error for clouds SMRF cannot grid.
Segmentation segmentCloud(const core::PointCloud& cloud, const SegmentOptions& o, int threads = 1);

}  // namespace detect
