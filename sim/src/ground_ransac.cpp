// sim/ground_ransac.cpp: paper §III-C, ground whitening by iterative RANSAC with PCL's
// SACSegmentation (SACMODEL_PLANE, SAC_RANSAC). The only file of sim that sees PCL.
//
//   1) PC = points with z in [z_min, z_min + band_m]
//   2) RANSAC on PC
//   3) add the plane's inliers to PG if the plane is horizontal. The paper prints
//      "normal(plane).z < 0.9", which would keep walls and drop the ground, against its
//      own text ("to remove vertical plane detections ... building walls"); we implement
//      the intent: |normal.z| >= min_normal_z.
//   4) remove the plane's inliers from PC. The paper says "remove the PG points"; when the
//      plane was rejected (a wall) nothing joined PG, PC would not shrink and steps 2-4
//      would find the same wall forever, so the inliers leave PC either way.
//   5) repeat from 2) until |PC| < stop_fraction * |PC at step 1| (or max_planes).
//
// Our addition (RansacOptions::min_plane_fraction, 0 restores the paper's rule): a
// horizontal plane must also hold a minimum share of the band. Without it, once the
// ground is removed RANSAC's best "plane" is often a horizontal slab cut through all the
// walls at one height, or a vehicle's roof, and both would turn white. Since no smaller
// plane can be accepted, the loop also stops once PC is smaller than that share, and each
// RANSAC runs only the iterations needed to find a plane of that share with probability
// 0.99 (capped by ransac_iterations), which keeps whitening fast.
#include "ground_internal.hpp"

#include <core/error.hpp>
#include <core/random.hpp>

#include <pcl/ModelCoefficients.h>
#include <pcl/console/print.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numeric>
#include <random>
#include <string>

namespace sim {

void validate(const RansacOptions& o) {
    if (!(std::isfinite(o.band_m) && o.band_m > 0.0)) failGroundOption("band_m (--band-m)", o.band_m, "> 0");
    if (!(std::isfinite(o.distance_threshold_m) && o.distance_threshold_m > 0.0))
        failGroundOption("distance_threshold_m (--ransac-distance-m)", o.distance_threshold_m, "> 0");
    if (!(o.min_normal_z >= 0.0 && o.min_normal_z <= 1.0))
        failGroundOption("min_normal_z (--min-normal-z)", o.min_normal_z, "[0, 1]");
    if (!(o.stop_fraction >= 0.0 && o.stop_fraction <= 1.0))
        failGroundOption("stop_fraction (--stop-fraction)", o.stop_fraction, "[0, 1]");
    if (!(o.min_plane_fraction >= 0.0 && o.min_plane_fraction <= 1.0))
        failGroundOption("min_plane_fraction (--min-plane-fraction)", o.min_plane_fraction, "[0, 1]");
    if (o.max_planes < 0 || o.max_planes > 100000)
        failGroundOption("max_planes (--max-planes)", o.max_planes, "[0, 100000]");
    if (o.ransac_sample_points < 0 || (o.ransac_sample_points > 0 && o.ransac_sample_points < 3))
        failGroundOption("ransac_sample_points (--ransac-sample-points)", o.ransac_sample_points, "0 (all) or >= 3");
    if (o.ransac_iterations < 1 || o.ransac_iterations > 10000000)
        failGroundOption("ransac_iterations (--ransac-iterations)", o.ransac_iterations, "[1, 10000000]");
}

std::vector<std::uint8_t> findGround(std::span<const glm::vec3> points, const RansacOptions& o, std::uint64_t seed,
                                     GroundStats* stats) {
    std::vector<std::uint8_t> is_ground(points.size(), 0);
    GroundStats local;
    if (points.empty()) {
        if (stats) *stats = local;
        return is_ground;
    }
    // Step 1: the band above this view's lowest point.
    float z_min = points[0].z;
    for (const glm::vec3& p : points) z_min = std::min(z_min, p.z);
    const double z_top = double(z_min) + o.band_m;
    std::vector<std::uint32_t> band;  // indices into `points`
    band.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        if (double(points[i].z) <= z_top) band.push_back(std::uint32_t(i));
    local.band_points = band.size();
    if (band.size() < 3) {
        if (stats) *stats = local;
        return is_ground;
    }
    std::mt19937_64 rng(seed);
    core::shuffle(band.begin(), band.end(), rng);

    // PC: `cloud` holds its points in the shuffled order, and band[k] is the index in
    // `points` of cloud point k; both shrink together, keeping that order, as planes
    // leave PC. PCL sees the same points in the same order as it would through indices
    // into a fixed cloud (its samples are drawn by position in the index list), and the
    // passes below read PC from start to end.
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    cloud->resize(band.size());
    // Centre the band before PCL fits planes in float: the view's points may be far from
    // the local origin (they are not, usually, but a large scene can be kilometres wide).
    const glm::vec3 shift = points[band[0]];
    for (std::size_t k = 0; k < band.size(); ++k) {
        const glm::vec3 p = points[band[k]] - shift;
        (*cloud)[k] = pcl::PointXYZ(p.x, p.y, p.z);
    }

    pcl::SACSegmentation<pcl::PointXYZ> seg;  // random_ = false: PCL seeds its RNG with 12345
    seg.setOptimizeCoefficients(true);
    seg.setModelType(pcl::SACMODEL_PLANE);
    seg.setMethodType(pcl::SAC_RANSAC);
    seg.setDistanceThreshold(o.distance_threshold_m);
    seg.setMaxIterations(o.ransac_iterations);
    seg.setInputCloud(cloud);  // the same cloud, shrunk in place, for every plane

    // Degenerate samples (collinear or repeated points) are expected in small remainders
    // of PC; PCL would print a line for each. Outcomes are reported through GroundStats.
    static std::once_flag quiet;
    std::call_once(quiet, [] { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); });

    const double min_plane_count = o.min_plane_fraction * double(band.size());
    const double stop_count = std::max(o.stop_fraction, o.min_plane_fraction) * double(band.size());
    std::vector<std::uint8_t> inlier;  // per point of PC
    int planes = 0;
    // Step 5's test before each pass of steps 2-4.
    while (cloud->size() >= 3 && !(double(cloud->size()) < stop_count) && planes < o.max_planes) {
        const std::size_t n = cloud->size();
        int iterations = o.ransac_iterations;
        if (min_plane_count > 0.0) {
            // Trials for a 3-point sample of a plane holding share w of PC: log(0.01) / log(1 - w^3).
            const double w = std::min(1.0, min_plane_count / double(n));
            const double needed = std::ceil(std::log(0.01) / std::log1p(-std::min(w * w * w, 0.999999)));
            iterations = int(std::clamp(needed, 1.0, double(o.ransac_iterations)));
        }
        seg.setMaxIterations(iterations);
        // PC keeps its shuffled order, so its first points are a uniform sample.
        const bool sampled = o.ransac_sample_points > 0 && n > std::size_t(o.ransac_sample_points);
        auto indices = std::make_shared<pcl::Indices>(sampled ? std::size_t(o.ransac_sample_points) : n);
        std::iota(indices->begin(), indices->end(), 0);
        seg.setIndices(indices);
        pcl::PointIndices inliers;
        pcl::ModelCoefficients plane;
        seg.segment(inliers, plane);  // step 2
        if (inliers.indices.empty() || plane.values.size() < 4) break;
        ++planes;
        const double n_len = std::hypot(plane.values[0], plane.values[1], plane.values[2]);
        inlier.assign(n, 0);
        std::size_t count = 0;
        if (sampled && n_len > 0.0) {
            // The plane's inliers among all of PC, as PCL's selectWithinDistance would.
            const double a = plane.values[0] / n_len, b = plane.values[1] / n_len, c = plane.values[2] / n_len,
                         d = plane.values[3] / n_len;
            const pcl::PointXYZ* p = cloud->data();
            for (std::size_t k = 0; k < n; ++k) {
                const bool in = std::abs(a * p[k].x + b * p[k].y + c * p[k].z + d) <= o.distance_threshold_m;
                inlier[k] = in;
                count += in;
            }
            if (count == 0) break;  // cannot happen (the sample's inliers are in PC)
        } else {
            for (const pcl::index_t k : inliers.indices) inlier[std::size_t(k)] = 1;
            count = inliers.indices.size();
        }
        const bool horizontal = n_len > 0.0 && std::abs(plane.values[2]) / n_len >= o.min_normal_z;
        const bool big_enough = double(count) >= min_plane_count;
        const bool accept = horizontal && big_enough;
        (accept ? local.planes_accepted : local.planes_rejected)++;
        if (horizontal && !big_enough) local.planes_too_small++;
        // Step 3 (the plane's inliers join PG) and step 4 (they leave PC, the others keep
        // their order).
        std::size_t kept = 0;
        for (std::size_t k = 0; k < n; ++k) {
            if (inlier[k]) {
                if (accept) is_ground[band[k]] = 1;
                continue;
            }
            (*cloud)[kept] = (*cloud)[k];
            band[kept] = band[k];
            ++kept;
        }
        cloud->resize(kept);
        band.resize(kept);
    }
    local.ground_points = std::size_t(std::count(is_ground.begin(), is_ground.end(), 1));
    if (stats) *stats = local;
    return is_ground;
}

namespace {

// The paper's filter behind the per-view seam: findGround on each view.
class RansacFilter final : public ViewGroundFilter {
  public:
    explicit RansacFilter(const RansacOptions& o) : options_(o) {}
    GroundMethod method() const override { return GroundMethod::Ransac; }
    std::vector<std::uint8_t> classifyView(std::span<const glm::vec3> points, std::uint64_t seed,
                                           GroundStats* stats) const override {
        return findGround(points, options_, seed, stats);
    }

  private:
    RansacOptions options_;
};

}  // namespace

std::unique_ptr<const ViewGroundFilter> makeRansacFilter(const RansacOptions& o) {
    return std::make_unique<RansacFilter>(o);
}

}  // namespace sim
