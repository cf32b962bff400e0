// detect/src/cluster_detector.cpp: the baseline detector of detect/cluster_detector.hpp.
// PCL is used here for the Euclidean cluster extraction only (its k-d tree answers the
// radius searches); the ground filters (RANSAC, SMRF, CSF) are sim's (sim/ground.hpp).
#include <detect/cluster_detector.hpp>

#include <core/error.hpp>
#include <core/spatial_hash.hpp>
#include <platform/progress.hpp>

#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

namespace detect {
namespace {

[[noreturn]] void fail(const char* option, double value, const char* allowed) {
    std::ostringstream s;
    s << "detect: " << option << " = " << value << ": allowed " << allowed;
    throw core::Error(s.str());
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Step 1 with RANSAC: §III-C on each square tile of side tile_m (x, y of the local frame).
std::vector<std::uint8_t> ransacGroundByTile(const core::PointCloud& cloud, const ClusterOptions& o) {
    const auto& pts = cloud.points;
    std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::uint32_t>> tiles;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto tx = static_cast<std::int64_t>(std::floor(double(pts[i].position.x) / o.ground_tile_m));
        const auto ty = static_cast<std::int64_t>(std::floor(double(pts[i].position.y) / o.ground_tile_m));
        tiles[{tx, ty}].push_back(std::uint32_t(i));
    }
    std::vector<std::uint8_t> ground(pts.size(), 0);
    platform::Progress progress("detect: ground", tiles.size(), false);
    std::vector<glm::vec3> positions;
    std::uint64_t tile_index = 0;
    for (const auto& [key, indices] : tiles) {
        positions.clear();
        for (const std::uint32_t i : indices) positions.push_back(pts[i].position);
        const std::vector<std::uint8_t> flags = sim::findGround(positions, o.ground_ransac, o.seed ^ tile_index++);
        for (std::size_t k = 0; k < indices.size(); ++k) ground[indices[k]] = flags[k];
        if (o.progress) progress.advance();
    }
    if (o.progress) progress.finish();
    return ground;
}

// Step 1 with a terrain-following filter: the generator's whole-cloud run (a TerrainFit),
// fed the points with their views, so that on a real sensor's cloud each view's height
// error is taken off as the generator does; a cloud without views is fitted as one view.
// The points are copied in chunks only when their view must be set.
std::vector<std::uint8_t> terrainGround(const core::PointCloud& cloud, sim::TerrainFit& fit,
                                        std::vector<float>& height_m) {
    const std::size_t n = cloud.points.size();
    if (cloud.fields.view) {
        fit.add(cloud.points);
    } else {
        constexpr std::size_t kChunk = std::size_t(1) << 16;
        std::vector<core::CloudPoint> chunk;
        for (std::size_t i = 0; i < n; i += kChunk) {
            chunk.assign(cloud.points.begin() + std::ptrdiff_t(i),
                         cloud.points.begin() + std::ptrdiff_t(std::min(n, i + kChunk)));
            for (core::CloudPoint& p : chunk) p.view = 0;
            fit.add(chunk);
        }
    }
    fit.fit();
    std::vector<std::uint8_t> ground(n, 0);
    height_m.assign(n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
        core::CloudPoint p = cloud.points[i];
        if (!cloud.fields.view) p.view = 0;
        ground[i] = fit.classify(p, height_m[i]) ? 1 : 0;
    }
    return ground;
}

// Step 1: whether each point is ground; with a terrain-following filter also each
// point's height above the terrain into `height_m` (left empty otherwise).
std::vector<std::uint8_t> findGroundPoints(const core::PointCloud& cloud, const ClusterOptions& o,
                                           std::vector<float>& height_m) {
    std::vector<std::uint8_t> ground(cloud.points.size(), 0);
    switch (o.ground) {
        case GroundSource::Labels:
            if (!cloud.fields.label)
                throw core::Error("detect: --ground labels: the cloud has no label field; use --ground ransac");
            for (std::size_t i = 0; i < cloud.points.size(); ++i)
                ground[i] = cloud.points[i].label == core::Role::Ground;
            return ground;
        case GroundSource::White:
            if (!cloud.fields.rgb)
                throw core::Error("detect: --ground white: the cloud has no rgb field; use --ground ransac");
            for (std::size_t i = 0; i < cloud.points.size(); ++i) ground[i] = cloud.points[i].rgb == core::kWhite;
            return ground;
        case GroundSource::Smrf: return terrainGround(cloud, *sim::startSmrf(o.ground_smrf), height_m);
        case GroundSource::Csf: return terrainGround(cloud, *sim::startCsf(o.ground_csf), height_m);
        case GroundSource::Ransac: break;
    }
    return ransacGroundByTile(cloud, o);
}

// The median of `v` (not empty), reordered.
double medianOf(std::vector<double>& v) {
    const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

// Step 3's thin ends: the cluster's points cut along the box's length into slices of
// kSliceM; from each end, slices holding fewer than thin_end_fraction of the median
// slice's points (a gun barrel, a mast, a wire) are left out. Returns the points kept
// (all of them when nothing is thin, or when the cut would leave under half).
constexpr double kSliceM = 0.25;
std::vector<std::uint32_t> withoutThinEnds(const core::PointCloud& cloud, const std::vector<std::uint32_t>& points,
                                           const OrientedBox& box, double thin_end_fraction) {
    if (thin_end_fraction <= 0.0 || box.size_m.x < 4.0 * kSliceM) return points;
    const double yaw = box.yaw_deg * std::numbers::pi / 180.0, c = std::cos(yaw), s = std::sin(yaw);
    const glm::dvec3 centre = box.centre;
    const auto along = [&](std::uint32_t i) {
        const glm::dvec3 p = glm::dvec3(cloud.points[i].position) - centre;
        return c * p.x + s * p.y;
    };
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const std::uint32_t i : points) {
        lo = std::min(lo, along(i));
        hi = std::max(hi, along(i));
    }
    const std::size_t slices = std::size_t((hi - lo) / kSliceM) + 1;
    std::vector<std::size_t> count(slices, 0);
    const auto sliceOf = [&](std::uint32_t i) { return std::min(slices - 1, std::size_t((along(i) - lo) / kSliceM)); };
    for (const std::uint32_t i : points) ++count[sliceOf(i)];
    std::vector<double> occupied;
    for (const std::size_t k : count)
        if (k > 0) occupied.push_back(double(k));
    const double bar = thin_end_fraction * medianOf(occupied);
    std::size_t first = 0, last = slices;
    while (first < last && double(count[first]) < bar) ++first;
    while (last > first && double(count[last - 1]) < bar) --last;
    if (first == 0 && last == slices) return points;
    std::vector<std::uint32_t> kept;
    for (const std::uint32_t i : points) {
        const std::size_t k = sliceOf(i);
        if (k >= first && k < last) kept.push_back(i);
    }
    return 2 * kept.size() >= points.size() ? kept : points;
}

// Steps 3 and 4's box of one cluster: fitBox without the thin ends; with a terrain
// (`height_m` not empty) its bottom reaches down to the terrain under the cluster (the
// median of the terrain's heights under its points), so the lowest part of a vehicle
// that the filter took with the ground still counts in its height.
OrientedBox clusterBox(const core::PointCloud& cloud, const std::vector<std::uint32_t>& points,
                       const std::vector<float>& height_m, const ClusterOptions& o) {
    OrientedBox box = fitBox(cloud, points, o.trim_fraction);
    const std::vector<std::uint32_t> kept = withoutThinEnds(cloud, points, box, o.thin_end_fraction);
    if (kept.size() != points.size()) box = fitBox(cloud, kept, o.trim_fraction);
    if (height_m.empty()) return box;
    std::vector<double> terrain;
    terrain.reserve(kept.size());
    for (const std::uint32_t i : kept) terrain.push_back(double(cloud.points[i].position.z) - double(height_m[i]));
    const double top = box.centre.z + 0.5 * box.size_m.z;
    const double bottom = std::min(box.centre.z - 0.5 * box.size_m.z, medianOf(terrain));
    box.size_m.z = top - bottom;
    box.centre.z = 0.5 * (top + bottom);
    return box;
}

}  // namespace

void validate(const ClusterOptions& o) {
    for (int k = 0; k < 3; ++k)
        if (!(std::isfinite(o.target_size_m[k]) && o.target_size_m[k] > 0.0 && o.target_size_m[k] <= 1000.0))
            fail("--target-size-m", o.target_size_m[k], "three sizes in (0, 1000] m");
    if (!(std::isfinite(o.size_tolerance) && o.size_tolerance > 1.0 && o.size_tolerance <= 100.0))
        fail("--size-tolerance", o.size_tolerance, "(1, 100]");
    if (!(std::isfinite(o.ground_tile_m) && o.ground_tile_m > 0.0)) fail("--ground-tile-m", o.ground_tile_m, "> 0 m");
    if (!(std::isfinite(o.voxel_m) && o.voxel_m >= 0.01 && o.voxel_m <= 100.0))
        fail("--voxel-m", o.voxel_m, "[0.01, 100] m");
    if (!(std::isfinite(o.cluster_tolerance_m) && o.cluster_tolerance_m > o.voxel_m / 2.0 &&
          o.cluster_tolerance_m <= 1000.0))
        fail("--cluster-tolerance-m", o.cluster_tolerance_m, "(voxel_m / 2, 1000] m");
    if (!(o.trim_fraction >= 0.0 && o.trim_fraction < 0.5)) fail("--trim-fraction", o.trim_fraction, "[0, 0.5)");
    if (!(o.thin_end_fraction >= 0.0 && o.thin_end_fraction < 1.0))
        fail("thin_end_fraction", o.thin_end_fraction, "[0, 1)");
    if (o.min_cluster_points < 1) fail("--min-cluster-points", o.min_cluster_points, ">= 1");
    if (!(o.min_score >= 0.0 && o.min_score <= 1.0)) fail("--min-score", o.min_score, "[0, 1]");
    if (o.max_candidates < 1 || o.max_candidates > 1000000) fail("--max-candidates", o.max_candidates, "[1, 1000000]");
    sim::validate(o.ground_ransac);
    sim::validate(o.ground_smrf);
    sim::validate(o.ground_csf);
}

double sizeScore(const glm::dvec3& size_m, const glm::dvec3& target_size_m, double size_tolerance) {
    // Compare the longer horizontal side with the longer one, the shorter with the shorter.
    const double s_long = std::max(size_m.x, size_m.y), s_short = std::min(size_m.x, size_m.y);
    const double t_long = std::max(target_size_m.x, target_size_m.y),
                 t_short = std::min(target_size_m.x, target_size_m.y);
    const double kFloor = 0.01;  // a flat or thin cluster: a tiny side, a finite log
    const double sides[3][2] = {{s_long, t_long}, {s_short, t_short}, {size_m.z, target_size_m.z}};
    double sum = 0.0;
    for (const auto& side : sides) {
        const double l = std::log(std::max(side[0], kFloor) / side[1]);
        sum += l * l;
    }
    const double sigma = std::log(size_tolerance);
    return std::exp(-sum / (2.0 * sigma * sigma));
}

OrientedBox fitBox(const core::PointCloud& cloud, const std::vector<std::uint32_t>& points, double trim) {
    // Moments about the first point, in double: the local frame may be far from the cluster.
    const glm::dvec3 ref = glm::dvec3(cloud.points[points.front()].position);
    double mx = 0, my = 0;
    for (const std::uint32_t i : points) {
        mx += double(cloud.points[i].position.x) - ref.x;
        my += double(cloud.points[i].position.y) - ref.y;
    }
    const double n = double(points.size());
    mx /= n;
    my /= n;
    double sxx = 0, syy = 0, sxy = 0;
    for (const std::uint32_t i : points) {
        const double dx = double(cloud.points[i].position.x) - ref.x - mx;
        const double dy = double(cloud.points[i].position.y) - ref.y - my;
        sxx += dx * dx;
        syy += dy * dy;
        sxy += dx * dy;
    }
    double theta = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // the principal axis of x, y
    // Extents along u (the axis at `angle`), v (across) and z, each between the trim and
    // 1 - trim quantiles of the points: a gun barrel or an antenna, thin and holding few
    // points, does not lengthen the box, while a box's faces hold far more than `trim`.
    std::vector<double> us(points.size()), vs(points.size()), zs(points.size());
    auto quantiles = [trim](std::vector<double>& x, double& lo, double& hi) {
        const std::size_t k = std::min(x.size() - 1, std::size_t(trim * double(x.size())));
        std::nth_element(x.begin(), x.begin() + std::ptrdiff_t(k), x.end());
        lo = x[k];
        std::nth_element(x.begin(), x.begin() + std::ptrdiff_t(x.size() - 1 - k), x.end());
        hi = x[x.size() - 1 - k];
    };
    // The extents along u and v at `angle`; z's do not depend on it and are taken once.
    auto extents = [&](double angle, double lo[2], double hi[2]) {
        const double c = std::cos(angle), s = std::sin(angle);
        for (std::size_t k = 0; k < points.size(); ++k) {
            const glm::dvec3 p = glm::dvec3(cloud.points[points[k]].position) - ref;
            us[k] = c * p.x + s * p.y;
            vs[k] = -s * p.x + c * p.y;
        }
        quantiles(us, lo[0], hi[0]);
        quantiles(vs, lo[1], hi[1]);
    };
    double lo[2], hi[2], zlo, zhi;
    for (std::size_t k = 0; k < points.size(); ++k) zs[k] = double(cloud.points[points[k]].position.z) - ref.z;
    quantiles(zs, zlo, zhi);
    extents(theta, lo, hi);
    const double measured = theta;
    if (hi[1] - lo[1] > hi[0] - lo[0]) theta += std::numbers::pi / 2.0;  // length is the longer side
    // Yaw in (-90, 90] degrees: a box is the same turned by 180. The extents are taken
    // again at the final angle when it is not the one measured.
    while (theta > std::numbers::pi / 2.0) theta -= std::numbers::pi;
    while (theta <= -std::numbers::pi / 2.0) theta += std::numbers::pi;
    if (theta != measured) extents(theta, lo, hi);
    const double c = std::cos(theta), s = std::sin(theta);
    const double cu = 0.5 * (lo[0] + hi[0]), cv = 0.5 * (lo[1] + hi[1]);
    OrientedBox box;
    box.centre = ref + glm::dvec3(c * cu - s * cv, s * cu + c * cv, 0.5 * (zlo + zhi));
    box.size_m = {hi[0] - lo[0], hi[1] - lo[1], zhi - zlo};
    box.yaw_deg = theta * 180.0 / std::numbers::pi;
    return box;
}

ClusterDetector::ClusterDetector(const ClusterOptions& o) : options_(o) { validate(options_); }

std::uint64_t ClusterDetector::memoryBytes(std::uint64_t points) {
    // Per point, at the larger of the two steps (each bound rounded up):
    // step 1, RANSAC per tile: the cloud (40), tile index lists with vector growth (8), the
    //   ground flags (1), one tile's positions with growth (24), findGround's buffers (64,
    //   as in sim's memory plan), its flags (1): 138; SMRF or CSF instead: the cloud, the
    //   flags, the terrain's raster and view tables (48, as the trained detector counts
    //   them) and each point's height above the terrain (4): 93;
    // step 2: the cloud, flags, the non-ground copy (40) and its indices with growth (8),
    //   the voxel bins (16), centroids (16), PCL's k-d tree (40), cluster indices (4), with a
    //   terrain the heights kept from step 1 (4): 169.
    // 256 leaves room for the allocator; the fixed part holds the reader's chunk buffer
    // (1 Mi points of 40 bytes), PCL's and the process's own.
    constexpr std::uint64_t kBytesPerPoint = 256;
    constexpr std::uint64_t kFixedBytes = std::uint64_t(64) << 20;
    return kFixedBytes + points * kBytesPerPoint;
}

std::vector<Detection> ClusterDetector::detect(const core::PointCloud& cloud) const {
    ClusterStats stats;
    return detect(cloud, stats);
}

std::vector<Detection> ClusterDetector::detect(const core::PointCloud& cloud, ClusterStats& stats) const {
    const ClusterOptions& o = options_;
    ClusterStats local;
    local.points = cloud.points.size();
    if (cloud.points.size() >= std::size_t(UINT32_MAX))
        throw core::Error("detect: the cloud has too many points (at most 4294967294)");

    auto t0 = std::chrono::steady_clock::now();
    std::vector<float> height_m;
    const std::vector<std::uint8_t> ground = findGroundPoints(cloud, o, height_m);
    local.ground_points = std::size_t(std::count(ground.begin(), ground.end(), 1));
    local.seconds_ground = secondsSince(t0);

    // Step 2: voxels of the non-ground points, their centroids clustered.
    t0 = std::chrono::steady_clock::now();
    std::vector<core::CloudPoint> above;
    std::vector<std::uint32_t> above_index;
    above.reserve(cloud.points.size() - local.ground_points);
    for (std::size_t i = 0; i < cloud.points.size(); ++i)
        if (!ground[i]) {
            above.push_back(cloud.points[i]);
            above_index.push_back(std::uint32_t(i));
        }
    const core::CellBins bins = core::binByCell(above, o.voxel_m);
    local.voxels = bins.cells();
    auto centroids = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    centroids->resize(bins.cells());
    for (std::size_t c = 0; c < bins.cells(); ++c) {
        glm::dvec3 sum{0.0};
        for (const std::uint32_t k : bins.cell(c)) sum += glm::dvec3(above[k].position);
        const glm::dvec3 m = sum / double(bins.cell(c).size());
        (*centroids)[c] = pcl::PointXYZ(float(m.x), float(m.y), float(m.z));
    }
    std::vector<pcl::PointIndices> clusters;
    if (!centroids->empty()) {
        auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
        tree->setInputCloud(centroids);
        pcl::EuclideanClusterExtraction<pcl::PointXYZ> extract;
        extract.setClusterTolerance(o.cluster_tolerance_m);
        extract.setMinClusterSize(1);
        extract.setMaxClusterSize(std::numeric_limits<int>::max());
        extract.setSearchMethod(tree);
        extract.setInputCloud(centroids);
        extract.extract(clusters);
    }
    local.seconds_cluster = secondsSince(t0);

    // Steps 3 and 4.
    t0 = std::chrono::steady_clock::now();
    std::vector<Detection> out;
    for (const pcl::PointIndices& cluster : clusters) {
        Detection d;
        for (const auto cell : cluster.indices)
            for (const std::uint32_t k : bins.cell(std::size_t(cell))) d.points.push_back(above_index[k]);
        if (d.points.size() < std::size_t(o.min_cluster_points)) continue;
        ++local.clusters;
        std::sort(d.points.begin(), d.points.end());
        const OrientedBox box = clusterBox(cloud, d.points, height_m, o);
        d.candidate.centre_world = cloud.origin + box.centre;
        d.candidate.size_m = box.size_m;
        d.candidate.yaw_deg = box.yaw_deg;
        d.candidate.score = sizeScore(box.size_m, o.target_size_m, o.size_tolerance);
        if (d.candidate.score >= o.min_score) out.push_back(std::move(d));
    }
    std::sort(out.begin(), out.end(), [](const Detection& a, const Detection& b) {
        if (a.candidate.score != b.candidate.score) return a.candidate.score > b.candidate.score;
        if (a.points.size() != b.points.size()) return a.points.size() > b.points.size();
        return a.points.front() < b.points.front();
    });
    if (out.size() > std::size_t(o.max_candidates)) out.resize(std::size_t(o.max_candidates));
    for (std::size_t k = 0; k < out.size(); ++k) out[k].candidate.id = "c" + std::to_string(k + 1);
    local.seconds_boxes = secondsSince(t0);
    stats = local;
    return out;
}

}  // namespace detect
