// detect/boosted_detector.hpp: the trained detector. It segments the cloud
// (detect/segmentation.hpp), describes every segment (detect/segment_features.hpp) and
// lets a trained model (detect/boosted_model.hpp) give each the probability that it is
// the target. Candidates are the segments' oriented boxes (the baseline's fitBox), best
// first, their score that probability.
#pragma once
#include <detect/boosted_model.hpp>
#include <detect/detector.hpp>
#include <detect/segment_features.hpp>
#include <detect/segmentation.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

namespace detect {

struct BoostedOptions {
    std::filesystem::path model;    // a file written by `ladarvr train`
    double min_probability = 0.01;  // candidates below are dropped, [0, 1]
    int max_candidates = 50;        // best first, >= 1
    int threads = 1;                // segmentation, feature and tree threads (>= 1); results do not depend on it
};

/// Throws core::Error("detect: <option> = <value>: allowed <range>").
void validate(const BoostedOptions& o);

/// The segments of a cloud and one row of features per segment (row-major).
struct DescribedSegments {
    Segmentation segmentation;
    std::vector<float> rows;
};
/// Segments `cloud` and computes every segment's features of `features` on `threads`
/// threads (the result does not depend on the count).
DescribedSegments describeSegments(const core::PointCloud& cloud, const SegmentOptions& segments,
                                   const glm::dvec3& target_size_m, int threads,
                                   FeatureSet features = kCurrentFeatures);

struct BoostedStats {
    std::size_t points = 0, above_points = 0, segments = 0;
    int core_points = 1;                          // the segmentation's dense voxels' bar
    double ground_sigma_m = 0, min_height_m = 0;  // the segmentation's measured ground thickness and threshold
    double spacing_m = 0, spacing_scale = 1;      // the points' measured spacing and the lengths' scale
    double seconds_segment = 0, seconds_features = 0, seconds_trees = 0;
};

class BoostedDetector final : public Detector {
  public:
    /// Reads the model (BoostedModel::read) and validates the options.
    explicit BoostedDetector(const BoostedOptions& o);
    /// A model in memory (a test's or the benchmark's freshly trained one).
    BoostedDetector(const BoostedOptions& o, std::shared_ptr<const BoostedModel> model);
    const BoostedModel& model() const { return *model_; }

    /// Candidates with probability >= min_probability, best first (ties by size, then
    /// first point), ids "c1", "c2", ...; each with its segment's points.
    std::vector<Detection> detect(const core::PointCloud& cloud) const override;
    std::vector<Detection> detect(const core::PointCloud& cloud, BoostedStats& stats) const;

    /// At most what reading a cloud of `points` points and detecting in it holds, bytes.
    static std::uint64_t memoryBytes(std::uint64_t points);

  private:
    BoostedOptions options_;
    std::shared_ptr<const BoostedModel> model_;
};

}  // namespace detect
