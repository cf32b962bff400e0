// detect/training.hpp: learning the trained detector from labelled clouds (corpus items,
// whose points carry the ground truth target/environment/ground). A segment is a
// positive example when more than half of its points are labelled target, unless it holds
// less than a tenth of the cloud's target points: such a scrap of the target (a piece the
// segmentation cut off, a few mixed returns) is left out, neither positive nor negative.
//
// The items are split by item (never by segment, so a held-out item's segments are all
// unseen): every item k with floor((k + 1) f) > floor(k f) is held out (f the holdout
// fraction, spread evenly along the list). The trees learn from the others; the Platt
// scaling is fitted on the held-out items' margins, so the score is a probability checked
// on clouds the trees never saw. Without both classes among the held-out segments the
// scaling is fitted on the training margins instead, and the report says so.
#pragma once
#include <detect/boosted_model.hpp>
#include <detect/segment_features.hpp>
#include <detect/segmentation.hpp>

#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace detect {

struct TrainOptions {
    glm::dvec3 target_size_m{7.0, 3.5, 2.5};  // the size class (the size_match feature)
    SegmentOptions segments;
    BoostParams boost;
    double holdout_fraction = 0.2;           // [0, 0.9]
    FeatureSet features = kCurrentFeatures;  // the features learned (a comparison may pick the first list)
};

/// Throws core::Error("train: <option> = <value>: allowed <range>").
void validate(const TrainOptions& o);

/// One labelled cloud's segments: a row of features and a 0/1 label each.
struct TrainingItem {
    std::string name;
    std::vector<float> rows, labels;
};

/// Segments and describes a labelled cloud. Throws core::Error("train: <name>: ...") when
/// the cloud has no label field.
TrainingItem describeLabelledCloud(const core::PointCloud& cloud, const std::string& name, const TrainOptions& o);

/// The items of one finished corpus folder (docs/corpus.md): DIR/manifest.jsonl's lines
/// in order, each item's cloud file, and the manifest's SHA-256.
struct CorpusListing {
    std::filesystem::path dir;
    std::vector<std::string> ids;
    std::vector<std::string> cloud_files;  // each item's cloud file name (cloud.pcd, cloud.laz, ...)
    /// Item k's cloud: DIR/items/<id>/<cloud file>. Made when asked, so that the listing
    /// holds two short strings an item, not a path of five parts.
    std::filesystem::path cloud(std::size_t k) const { return dir / "items" / ids[k] / cloud_files[k]; }
    /// The manifest the listing was read from: DIR/manifest.jsonl.
    std::filesystem::path manifest() const { return dir / "manifest.jsonl"; }
    std::string manifest_sha256;
    std::size_t held_bytes = 0;  // what the listing holds in memory (the manifest's text is not kept)
};
/// Throws core::Error("train: <dir>: ...") naming what is missing or malformed (a manifest
/// line without an id or a cloud file, an id that is not digits, a duplicate key or a NUL
/// in a line's JSON), or when the manifest's text and the listing made of it would hold
/// more than `budget_bytes` (the run's --memory-mb), counted as the lines are read.
CorpusListing listCorpus(const std::filesystem::path& dir,
                         std::size_t budget_bytes = std::numeric_limits<std::size_t>::max());

/// How the training went; the calibration check is on the held-out items.
struct TrainReport {
    std::size_t items = 0, segments = 0, positives = 0;
    std::size_t heldout_items = 0, heldout_segments = 0, heldout_positives = 0;
    bool calibrated_on_heldout = false;
    double brier = 0.0;     // mean (p - label)^2 on the held-out segments (training ones without)
    double log_loss = 0.0;  // the same segments
    // Reliability: segments by calibrated probability in [0, .1), [.1, .5), [.5, .9), [.9, 1].
    std::size_t bin_count[4] = {0, 0, 0, 0};
    double bin_mean_probability[4] = {0, 0, 0, 0}, bin_positive_share[4] = {0, 0, 0, 0};
};

/// Trains on `items` (in this order) and calibrates. `manifests_sha256` goes into the model.
BoostedModel trainDetector(const std::vector<TrainingItem>& items, const TrainOptions& o,
                           const std::vector<std::string>& manifests_sha256, TrainReport& report);

}  // namespace detect
