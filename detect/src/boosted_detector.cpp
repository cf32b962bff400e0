// detect/src/boosted_detector.cpp: the trained detector of detect/boosted_detector.hpp.
#include <detect/boosted_detector.hpp>

#include <core/error.hpp>
#include <detect/cluster_detector.hpp>
#include <detect/segment_features.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <atomic>
#include <numeric>

#include "parts.hpp"

namespace detect {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void validate(const BoostedOptions& o) {
    auto fail = [](const char* option, double value, const char* allowed) {
        std::ostringstream s;
        s << "detect: " << option << " = " << value << ": allowed " << allowed;
        throw core::Error(s.str());
    };
    if (!(o.min_probability >= 0.0 && o.min_probability <= 1.0)) fail("--min-score", o.min_probability, "[0, 1]");
    if (o.max_candidates < 1 || o.max_candidates > 1000000) fail("--max-candidates", o.max_candidates, "[1, 1000000]");
    if (o.threads < 1 || o.threads > 1024) fail("--threads", o.threads, "[1, 1024]");
}

DescribedSegments describeSegments(const core::PointCloud& cloud, const SegmentOptions& segments,
                                   const glm::dvec3& target_size_m, int threads, FeatureSet features) {
    DescribedSegments out;
    out.segmentation = segmentCloud(cloud, segments, threads);
    const auto& segs = out.segmentation.segments;
    const std::size_t columns = segmentFeatureNames(features).size();
    // The cloud's points per square metre of observed terrain, which the relative
    // features divide by.
    const double voxel_m = out.segmentation.used.voxel_m;
    const double density_m2 = out.segmentation.points_per_voxel_face / (voxel_m * voxel_m);
    out.rows.assign(segs.size() * columns, 0.0f);
    // Each segment's row is computed alone and written to its own place: the rows are the
    // same whatever the number of threads. The threads take the segments largest first,
    // one at a time, so that a forest's canopy does not leave one thread with the rest.
    std::vector<std::uint32_t> order(segs.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return segs[a].size() > segs[b].size(); });
    std::atomic<std::size_t> next{0};
    const std::size_t t =
        std::min<std::size_t>(std::size_t(std::clamp(threads, 1, 1024)), std::max<std::size_t>(segs.size(), 1));
    runParts(t, [&](std::size_t) {
        for (std::size_t k = next++; k < order.size(); k = next++) {
            const std::uint32_t s = order[k];
            const std::vector<float> f =
                segmentFeatures(cloud, segs[s], out.segmentation.height_m, target_size_m, features, density_m2);
            std::copy(f.begin(), f.end(), out.rows.begin() + std::ptrdiff_t(std::size_t(s) * columns));
        }
    });
    return out;
}

BoostedDetector::BoostedDetector(const BoostedOptions& o) : options_(o) {
    validate(options_);
    model_ = std::make_shared<const BoostedModel>(BoostedModel::read(o.model));
}

BoostedDetector::BoostedDetector(const BoostedOptions& o, std::shared_ptr<const BoostedModel> model)
    : options_(o), model_(std::move(model)) {
    validate(options_);
}

std::uint64_t BoostedDetector::memoryBytes(std::uint64_t points) {
    // Per point, at the clustering's peak: the cloud (40), the flags, heights and indices
    // of the points above the terrain (9), then, with every point its own voxel at
    // worst, each point's voxel (4), the voxels' key, count, first point and centroid
    // (40), the dense and sparse lists with their keys (12), and the first thread's
    // union-find (4) with each thread's nearest-voxel table (12, at most 4 threads: 48):
    // 157. The radix sort's two buffers (32) come before the voxel tables; SMRF's raster
    // and view tables (48) before that, and a segment's feature scratch (32) after.
    // Rounded up to 192 for the allocator. The fixed part holds the reader's chunk
    // buffer, the terrain fit's chunk of points, the terrain levelling's tables (at most
    // 9 MB; freed before the oversized segments' envelope grid, at most 8 MB, is made),
    // XGBoost and the model.
    constexpr std::uint64_t kBytesPerPoint = 192;
    constexpr std::uint64_t kFixedBytes = std::uint64_t(96) << 20;
    return kFixedBytes + points * kBytesPerPoint;
}

std::vector<Detection> BoostedDetector::detect(const core::PointCloud& cloud) const {
    BoostedStats stats;
    return detect(cloud, stats);
}

std::vector<Detection> BoostedDetector::detect(const core::PointCloud& cloud, BoostedStats& stats) const {
    BoostedStats local;
    local.points = cloud.points.size();
    const ModelInfo& info = model_->info();
    auto t0 = std::chrono::steady_clock::now();
    DescribedSegments described =
        describeSegments(cloud, info.segments, info.target_size_m, options_.threads, info.feature_set);
    local.above_points = described.segmentation.above_points;
    local.segments = described.segmentation.segments.size();
    local.ground_sigma_m = described.segmentation.ground_sigma_m;
    local.min_height_m = described.segmentation.min_height_m;
    local.core_points = described.segmentation.core_points;
    local.spacing_m = described.segmentation.spacing_m;
    local.spacing_scale = described.segmentation.spacing_scale;
    local.seconds_features = secondsSince(t0);
    t0 = std::chrono::steady_clock::now();
    const std::vector<float> margins = model_->margins(described.rows, options_.threads);
    local.seconds_trees = secondsSince(t0);

    std::vector<Detection> out;
    auto& segs = described.segmentation.segments;
    for (std::size_t s = 0; s < segs.size(); ++s) {
        const double p = model_->probability(margins[s]);
        if (!(p >= options_.min_probability)) continue;
        Detection d;
        d.points = std::move(segs[s]);
        const OrientedBox box = fitBox(cloud, d.points, 0.01);
        d.candidate.centre_world = cloud.origin + box.centre;
        d.candidate.size_m = box.size_m;
        d.candidate.yaw_deg = box.yaw_deg;
        d.candidate.score = p;
        out.push_back(std::move(d));
    }
    std::sort(out.begin(), out.end(), [](const Detection& a, const Detection& b) {
        if (a.candidate.score != b.candidate.score) return a.candidate.score > b.candidate.score;
        if (a.points.size() != b.points.size()) return a.points.size() > b.points.size();
        return a.points.front() < b.points.front();
    });
    if (out.size() > std::size_t(options_.max_candidates)) out.resize(std::size_t(options_.max_candidates));
    for (std::size_t k = 0; k < out.size(); ++k) out[k].candidate.id = "c" + std::to_string(k + 1);
    stats = local;
    return out;
}

}  // namespace detect
