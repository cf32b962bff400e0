// detect/boosted_model.hpp: the trained detector's model, gradient-boosted trees
// (XGBoost, Chen and Guestrin 2016) over detect/segment_features.hpp's features, with a
// Platt scaling (Platt 1999) that turns the trees' margin into a calibrated probability.
//
// The model file is our own container around XGBoost's model bytes, written atomically:
//
//   bytes 0-7    magic "LDVRDET1"
//   bytes 8-11   H, the header's length (little-endian uint32), 2 .. kMaxHeaderBytes
//   H bytes      the header, a JSON object: "format" 1, "library" "xgboost",
//                "library_version" "3.0.0", "features" [names], "target_size_m" [l, w, h],
//                "corpus_manifests_sha256" [hex], "calibration" {"a", "b"}, "segmentation"
//                {the SegmentOptions trained with}, "training" {counts}, "model_bytes" M,
//                "model_sha256" hex
//   8 bytes      M, the model's length (little-endian uint64), 1 .. kMaxModelBytes
//   M bytes      XGBoost's model (its UBJSON form)
//
// The reader checks the magic, both lengths against the file's size (which must be
// exactly 20 + H + M), the header's fields, the features against this build's list, the
// library's version against the linked one, the model's SHA-256 and the model itself
// (detect/model_check.hpp: the trees' structure, which XGBoost trusts), all before XGBoost
// sees the bytes.
#pragma once
#include <detect/segment_features.hpp>
#include <detect/segmentation.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace detect {

inline constexpr std::size_t kMaxHeaderBytes = std::size_t(1) << 20;
inline constexpr std::size_t kMaxModelBytes = std::size_t(64) << 20;

/// What a model file records besides the trees.
struct ModelInfo {
    std::string library = "xgboost";
    std::string library_version;                       // the XGBoost that trained it, "major.minor.patch"
    std::vector<std::string> features;                 // segmentFeatureNames(feature_set) at training time
    FeatureSet feature_set = kCurrentFeatures;         // the set those names are
    glm::dvec3 target_size_m{7.0, 3.5, 2.5};           // the size class the size_match feature scores against
    std::vector<std::string> corpus_manifests_sha256;  // of each training corpus's manifest.jsonl
    double platt_a = 1.0, platt_b = 0.0;               // probability = 1 / (1 + exp(-(a * margin + b)))
    SegmentOptions segments;                           // the segmentation trained with (detection uses the same)
    std::size_t items = 0, segments_total = 0, positives = 0;  // the training set
};

/// The version of the XGBoost linked into this build, "major.minor.patch".
std::string xgboostVersion();

/// Training parameters of the trees.
struct BoostParams {
    int rounds = 150;        // boosting rounds (trees), [1, 10000]
    int max_depth = 4;       // [1, 16]
    double eta = 0.1;        // learning rate, (0, 1]
    double subsample = 1.0;  // (0, 1]; 1 keeps training deterministic without relying on the seed
    int threads = 1;         // XGBoost's nthread, >= 1
    std::uint64_t seed = 1;
};

class BoostedModel {
  public:
    /// Trains trees on `rows` (row-major, features.size() columns, NaN = missing) with
    /// labels 0/1. `info.features` names the columns. Throws core::Error("train: ...").
    static BoostedModel train(const std::vector<float>& rows, const std::vector<float>& labels, ModelInfo info,
                              const BoostParams& params);
    /// Reads and checks a model file; throws core::Error("detect: --model <file>: <what is wrong>").
    static BoostedModel read(const std::filesystem::path& path);
    /// The container's bytes (see above).
    std::string serialize() const;
    /// Writes serialize() atomically.
    void write(const std::filesystem::path& path) const;

    const ModelInfo& info() const { return info_; }
    ModelInfo& info() { return info_; }
    /// The trees' margins (log-odds before calibration) of `rows` (row-major,
    /// info().features.size() columns), with XGBoost on `threads` threads; the same values
    /// whatever the thread count.
    std::vector<float> margins(const std::vector<float>& rows, int threads) const;
    /// The calibrated probability of a margin.
    double probability(double margin) const;

    BoostedModel(BoostedModel&&) noexcept;
    BoostedModel& operator=(BoostedModel&&) noexcept;
    ~BoostedModel();

  private:
    struct Booster;
    BoostedModel(ModelInfo info, std::unique_ptr<Booster> booster, std::string bytes);
    ModelInfo info_;
    std::unique_ptr<Booster> booster_;
    std::string bytes_;  // XGBoost's model bytes as saved or read
};

/// Platt scaling: a, b that minimise the log loss of 1 / (1 + exp(-(a m + b))) against
/// `labels` (0/1), with Platt's smoothed targets; a = 1, b = 0 when either class is absent.
void fitPlatt(const std::vector<float>& margins, const std::vector<float>& labels, double& a, double& b);

}  // namespace detect
