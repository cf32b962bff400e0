// bench/src/ground_isprs_learned.hpp: the learned refinement of SMRF
// (sim/ground_learned.hpp) on the ISPRS samples: its trees learned with XGBoost, scored
// leave-one-site-out (a sample's labels come from trees that saw no sample of its site),
// and the shipped model learned from all samples.
#pragma once
#include <core/point_cloud.hpp>
#include <sim/ground_learned.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace bench {

/// What the trees are learned with.
/// The refinement changes SMRF's answer where the trees disagree with it by a logit of
/// more than this: the best of 0, 1, 2 and 3 leave-one-site-out (--learned-variants).
inline constexpr double kRefineConfidence = 1.0;

/// What the trees are learned with; the defaults did best leave-one-site-out.
struct TreeParams {
    int rounds = 200;
    int max_depth = 8;
    double eta = 0.1;
    double subsample = 0.8;
    std::uint64_t seed = 1;
    int threads = 2;
    /// Feature columns left out (learned from zeros: never split on).
    std::vector<std::size_t> left_out;
};

/// One sample's points, reference labels (1 = bare earth) and feature rows.
struct LearnedSample {
    std::string name;
    int site = 0;  // the first digit of the sample's number
    std::vector<float> rows;
    std::vector<std::uint8_t> truth, smrf;
};

/// Features of a sample for the refinement of SMRF `o`.
LearnedSample describeSample(const std::string& name, const std::vector<core::CloudPoint>& points,
                             const std::vector<std::uint8_t>& truth, const sim::SmrfOptions& o);

/// Trees learned from `samples` (each sample weighing as much as any other, whatever its
/// number of points), as the model file holds them. Throws core::Error.
sim::GroundModel learnGroundModel(const std::vector<const LearnedSample*>& samples, const TreeParams& p);

/// Each sample's margins (the trees' logit of ground) from trees learned on the samples of
/// the other sites.
std::vector<std::vector<float>> leaveOneSiteOut(const std::vector<LearnedSample>& samples, const TreeParams& p);

/// Labels (1 = ground) from margins: SMRF's answer, changed where the trees disagree with
/// it by more than `confidence` (logit; 0: the trees' answer alone).
std::vector<std::uint8_t> refinedLabels(const LearnedSample& s, const std::vector<float>& margins, double confidence);

}  // namespace bench
