// detect/segmentation.hpp: the segments a trained detector classifies. The ground is a
// fitted terrain, not a plane: SMRF (sim/ground.hpp, Pingel et al. 2013) gives each point
// its height above a surface that follows hills and slopes, so a target on a slope stands
// out of it instead of merging into a tilted "ground" left over by a per-tile plane.
//
//   1) terrain: SMRF on the whole cloud, fed each point with its view, so on a noisy
//      sensor's thick ground each view's height error is taken off and the terrain runs
//      through the ground's centre (sim's whole-cloud fit, docs/ground.md); every point
//      gets its height above the terrain, and the ground's thickness is measured;
//   2) the points higher than min_height_m or ground_sigmas thicknesses above it (and not
//      SMRF ground) are binned into voxels of voxel_m; two dense voxels (core_points
//      points or more) whose centroids are within cluster_tolerance_m join one segment
//      (union-find, the Euclidean clustering of Rusu's thesis on voxel centroids, as the
//      baseline does); a sparse voxel joins the segment of its nearest dense voxel
//      within reach (DBSCAN's border points), so it never chains two segments;
//   3) segments under min_points points are dropped as noise;
//   4) a segment reaching above split_height_m gives up what stands free below that
//      height: the points below it in columns of its footprint that do not rise without
//      a gap to above it (walls, trunks) are clustered as in step 2, and each cluster of
//      ten times min_points or more becomes a segment (a vehicle against a wall, or
//      under crowns that touch each other); the rest stays one segment.
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
};

/// Throws core::Error("detect: <option> = <value>: allowed <range>").
void validate(const SegmentOptions& o);

struct Segmentation {
    /// One height above the terrain per point of the cloud, metres.
    std::vector<float> height_m;
    /// Each segment's point indices, ascending; segments ordered by their first point.
    std::vector<std::vector<std::uint32_t>> segments;
    std::size_t above_points = 0;      // points that went into step 2
    std::size_t voxels = 0;            // the voxels step 2 clustered them on
    double ground_sigma_m = 0;         // the ground thickness step 1 measured (one sigma)
    double min_height_m = 0;           // the height threshold step 2 used
    double points_per_voxel_face = 0;  // the cloud's points per voxel_m^2 of observed terrain
    int core_points = 1;               // the dense voxels' bar step 2 used
    std::size_t split_segments = 0;    // segments step 4 split
};

/// Steps 1-4 on `cloud`: a pure function of the cloud and the options, the same whatever
/// `threads` (the clustering's parts run on up to that many threads, at most 4). Throws
/// core::Error for clouds SMRF cannot grid.
Segmentation segmentCloud(const core::PointCloud& cloud, const SegmentOptions& o, int threads = 1);

}  // namespace detect
