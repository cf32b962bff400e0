// sim/ground_learned.hpp: a learned refinement of SMRF's ground (`ladarvr ground
// --method learned`). SMRF runs as `ladarvr ground` runs it, with the terrains of a few
// other slopes and windows made from the same openings; each point is then described by
// local geometric measures taken from those terrains and from a raster of per-cell
// statistics gathered in the same streamed pass (heights above the terrains and above the
// lowest points around it, slope, curvature, roughness, gaps), and gradient-boosted trees
// say whether it is bare earth. The trees are learned from the ISPRS filter-test samples
// (`ladarvr bench ground-isprs --write-model`); the model file holds them in a format of
// our own, read here without XGBoost. Scored on a site the trees never saw it lowered
// SMRF's error too little to replace it (docs/ground-isprs.md), so `ladarvr ground` does not
// run it: this is the bench's and an experiment's tool.
#pragma once
#include <sim/ground.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sim {

/// The names of the features, in the order of a feature row.
const std::vector<std::string>& learnedFeatureNames();

/// One regression tree: node k splits on feature[k] (row[feature] < value[k] goes to
/// left[k], else right[k]; a missing value, NaN, goes where default_left says) or, when
/// feature[k] < 0, is a leaf worth value[k]. Children come after their parent.
struct GroundTree {
    std::vector<std::int32_t> feature, left, right;
    std::vector<float> value;
    std::vector<std::uint8_t> default_left;
};

/// Gradient-boosted trees over learnedFeatureNames(): a point is ground when the sum of
/// its leaves (the logit of the probability) is above 0.
struct GroundModel {
    std::vector<GroundTree> trees;
    /// The sum of the trees' leaves for one feature row (learnedFeatureNames().size() values).
    double margin(const float* row) const;
};

/// The model file's format version this build reads and writes.
inline constexpr int kGroundModelVersion = 1;
/// A model file is refused above this size.
inline constexpr std::size_t kMaxGroundModelBytes = std::size_t(8) << 20;

/// The model as text (what --write-model writes; floats to 9 digits, so it reads back
/// exactly).
std::string serializeGroundModel(const GroundModel& m);
/// Throws core::Error("<where>: line N: ... ; allowed ...") on anything but a model of
/// this version over these features, with trees whose nodes all lie in range.
GroundModel parseGroundModel(std::string_view text, const std::string& where);
/// Reads and checks a model file (parseGroundModel), at most kMaxGroundModelBytes.
GroundModel loadGroundModel(const std::filesystem::path& path);

/// A whole-cloud run of SMRF (`o`, validate(o) passed) refined by `model`: classify()
/// gives SMRF's answer, changed where the trees disagree with it by a logit of more than
/// `confidence` (0: the trees' answer alone), and the height above SMRF's terrain.
std::unique_ptr<TerrainFit> startLearned(const SmrfOptions& o, std::shared_ptr<const GroundModel> model,
                                         double confidence);

/// The feature rows of `points` (learnedFeatureNames().size() per point, point by point)
/// and, in `smrf_ground`, SMRF's own answer: what the trees are learned from.
std::vector<float> learnedFeatures(std::span<const core::CloudPoint> points, const SmrfOptions& o,
                                   std::vector<std::uint8_t>* smrf_ground = nullptr);

}  // namespace sim
