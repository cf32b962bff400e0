// detect/cluster_detector.hpp: the baseline 3D ATR, so that target validation works
// without an outside detector: remove the ground, cluster what is left, fit each cluster
// an oriented box and score the box by how well its size matches the target's.
//
//   1) ground: the cloud's labels (ground role), the generator's whitening (white points),
//      paper §III-C's iterative RANSAC run on square tiles of the cloud (a whole scene
//      is not one plane; a tile of a few tens of metres nearly is), or one of the
//      generator's terrain-following filters (SMRF, CSF) on the whole cloud, for ground
//      with more relief than a tile's height band holds;
//   2) the other points are binned into small voxels and the voxels' centroids are
//      clustered by PCL's Euclidean cluster extraction (two centroids closer than the
//      tolerance join one cluster); every point follows its voxel;
//   3) each cluster gets an oriented box: yaw from the principal axis of its points' x, y
//      (PCA), length along that axis, width across it, height from z, each extent between
//      quantiles (trim_fraction) so that a barrel or an antenna does not count; the
//      slices at the ends of its length that hold few points (thin_end_fraction: a gun
//      barrel of a densely sampled vehicle) are left out; with a terrain (SMRF, CSF) the
//      box stands on the terrain under the cluster, so the lowest part of a vehicle that
//      the filter took with the ground still counts in its height;
//   4) score = exp(-sum_i ln(size_i / target_i)^2 / (2 ln(size_tolerance)^2)) over length,
//      width, height: 1 for a box of exactly the target's size, exp(-1/2) when one side is
//      off by the factor size_tolerance, ~0 for a wall or a tree.
#pragma once
#include <detect/detector.hpp>
#include <sim/ground.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace detect {

enum class GroundSource {
    Ransac,  // §III-C RANSAC per tile (works on any cloud)
    Smrf,    // SMRF's terrain fitted to the whole cloud (sim/ground.hpp; any cloud)
    Csf,     // CSF's cloth dropped on the whole cloud (sim/ground.hpp; any cloud)
    Labels,  // points labelled ground (needs a cloud with labels: ground truth)
    White,   // white points (the generator's whitening; needs rgb)
};

struct ClusterOptions {
    glm::dvec3 target_size_m{7.0, 3.5, 2.5};  // length, width, height; default a main battle tank
    double size_tolerance = 1.5;              // factor (> 1) that costs a side exp(-1/2) of the score
    GroundSource ground = GroundSource::Ransac;
    double ground_tile_m = 30.0;       // side of the square RANSAC tiles (> 0)
    sim::RansacOptions ground_ransac;  // per tile
    sim::SmrfOptions ground_smrf;      // with GroundSource::Smrf
    sim::CsfOptions ground_csf;        // with GroundSource::Csf
    double voxel_m = 0.25;             // voxel side of step 2 (> 0)
    double cluster_tolerance_m = 0.5;  // Euclidean cluster distance (> voxel_m / 2)
    /// Fraction of a cluster's points left out at each end of each box axis (quantiles),
    /// [0, 0.5): thin protrusions such as a gun barrel do not count in the box's size.
    double trim_fraction = 0.01;
    /// Step 3: cut along the box's length into 0.25 m slices, the slices at either end
    /// holding fewer than this fraction of the median slice's points (a gun barrel seen
    /// by many rays, which trim_fraction cannot drop) are left out of the box; 0 keeps
    /// them, [0, 1).
    double thin_end_fraction = 0.25;
    int min_cluster_points = 20;  // smaller clusters are noise (>= 1)
    double min_score = 0.05;      // candidates below are dropped, [0, 1]
    int max_candidates = 50;      // best first (>= 1)
    std::uint64_t seed = 1;       // RANSAC's shuffles
    bool progress = false;        // progress bar over the tiles (tty only)
};

/// Throws core::Error("detect: <option> = <value>: allowed <range>"), or sim's
/// ("ground: ...") for the ground filters' options (all three filters' are checked).
void validate(const ClusterOptions& o);

struct ClusterStats {
    std::size_t points = 0, ground_points = 0, voxels = 0, clusters = 0;
    double seconds_ground = 0, seconds_cluster = 0, seconds_boxes = 0;
};

class ClusterDetector final : public Detector {
  public:
    /// Throws core::Error for invalid options (validate).
    explicit ClusterDetector(const ClusterOptions& o);
    const ClusterOptions& options() const { return options_; }

    /// Runs steps 1-4 on `cloud`; returns the detections with score >= min_score, best
    /// first (ties by cluster size), at most max_candidates, ids "c1", "c2", ... in that
    /// order; each detection's points are its cluster's. Throws core::Error("detect:
    /// ...") when the ground source needs a field the cloud does not carry.
    std::vector<Detection> detect(const core::PointCloud& cloud) const override;
    /// The same, and the run's counts and seconds into `stats`.
    std::vector<Detection> detect(const core::PointCloud& cloud, ClusterStats& stats) const;

    /// At most what reading a cloud of `points` points and detecting in it holds, in
    /// bytes: the cloud itself plus every per-point buffer of steps 1-4 (checked against
    /// --memory-mb before the cloud is read, sim/memory_budget.hpp).
    static std::uint64_t memoryBytes(std::uint64_t points);

  private:
    ClusterOptions options_;
};

/// Oriented box of points (local frame) by PCA of x, y: centre (local), size (length >=
/// width), yaw in degrees (-90, 90]. Each extent runs between the `trim` and 1 - `trim`
/// quantiles of the points along it, in [0, 0.5). `points` must not be empty.
struct OrientedBox {
    glm::dvec3 centre{0.0};
    glm::dvec3 size_m{0.0};
    double yaw_deg = 0.0;
};
OrientedBox fitBox(const core::PointCloud& cloud, const std::vector<std::uint32_t>& points, double trim = 0.0);

/// Step 4's score of a box size against the target size (both length, width, height;
/// the horizontal sides are compared longest to longest). In [0, 1].
double sizeScore(const glm::dvec3& size_m, const glm::dvec3& target_size_m, double size_tolerance);

}  // namespace detect
