// detect/src/boosted_detector.cpp: the trained detector of detect/boosted_detector.hpp.
#include <detect/boosted_detector.hpp>

#include <core/error.hpp>
#include <detect/cluster_detector.hpp>
#include <detect/segment_features.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <thread>

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
                                   const glm::dvec3& target_size_m, int threads) {
    DescribedSegments out;
    out.segmentation = segmentCloud(cloud, segments);
    const auto& segs = out.segmentation.segments;
    const std::size_t columns = segmentFeatureNames().size();
    out.rows.assign(segs.size() * columns, 0.0f);
    // Each segment's row is computed alone and written to its own place: the rows are the
    // same whatever the number of threads.
    auto work = [&](std::size_t first, std::size_t step) {
        for (std::size_t s = first; s < segs.size(); s += step) {
            const std::vector<float> f = segmentFeatures(cloud, segs[s], out.segmentation.height_m, target_size_m);
            std::copy(f.begin(), f.end(), out.rows.begin() + std::ptrdiff_t(s * columns));
        }
    };
    const std::size_t t = std::size_t(std::clamp(threads, 1, 1024));
    if (t == 1 || segs.size() < 2) {
        work(0, 1);
        return out;
    }
    std::vector<std::thread> pool;
    for (std::size_t k = 1; k < t; ++k) pool.emplace_back(work, k, t);
    work(0, t);
    for (auto& th : pool) th.join();
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
    // Per point: the cloud (40), SMRF's flags and heights with its raster's and the
    // views' corrections' share (48), the voxel of each point and the voxel tables with
    // each voxel's dense neighbour (24), the segments' index lists (8), a segment's
    // feature scratch (32): 152, rounded up to 192 for the allocator. The fixed part
    // holds the reader's chunk buffer, the terrain fit's chunk of points, XGBoost and
    // the model.
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
    DescribedSegments described = describeSegments(cloud, info.segments, info.target_size_m, options_.threads);
    local.above_points = described.segmentation.above_points;
    local.segments = described.segmentation.segments.size();
    local.ground_sigma_m = described.segmentation.ground_sigma_m;
    local.min_height_m = described.segmentation.min_height_m;
    local.core_points = described.segmentation.core_points;
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
