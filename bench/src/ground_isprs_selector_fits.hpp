// bench/src/ground_isprs_selector_fits.hpp: what the per-tile and per-segment selectors of
// SMRF's option sets share (ground_isprs_selector.hpp): each sample fitted with every set,
// trees learned and applied with XGBoost, and the table lines they print.
#pragma once
#include "common.hpp"
#include "ground_isprs_adaptive.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace core {
struct CloudPoint;
}

namespace bench {

/// A sample under every set of selectorSets(): each point's label and height above the
/// set's terrain, the base terrain's slope, curvature and height at it, and its 1 m cell.
struct SampleFits {
    std::vector<std::vector<std::uint8_t>> ground;  // per set, per point (1 = ground)
    std::vector<std::vector<float>> height_m;       // per set, per point
    std::vector<float> slope, rough_m, terrain_m;   // the base terrain, per point
    std::vector<std::uint64_t> cell;                // per point: (row << 32) | column of 1 m
    double points_per_cell = 0;                     // over the cells holding a point
};

/// Fits `points` with every set (SMRF as `ladarvr ground` runs it, the set's slope, window,
/// threshold and scalar). Throws core::Error as SMRF does.
SampleFits fitSample(const std::vector<core::CloudPoint>& points);

/// The trees' shape: few rows, so shallow trees by default.
struct TreeShape {
    int max_depth = 3;
    int rounds = 100;
    double min_child_weight = 1;
    /// "" for the default shape, else ", depth D, R rounds, min child weight W".
    std::string describe() const;
};

/// Trees learned on (train, labels, weights) predict `test` (rows of `columns` floats): per
/// row, the probability of label 1 (classes 2: binary logistic) or of each class
/// (softprob). Rounds of 0.1, subsample 0.8, seed 1. Throws core::Error.
std::vector<float> learnAndPredict(const std::vector<float>& train, const std::vector<float>& labels,
                                   const std::vector<float>& weights, const std::vector<float>& test,
                                   std::size_t columns, int classes, const TreeShape& shape = {});

/// The means over samples.
Counts meanOf(const std::vector<Counts>& c);
/// "24 31 53": the samples more than a point past CSF's published total error, or "none".
std::string pastCsf(const std::vector<AdaptiveSample>& samples, const std::vector<Counts>& c);
/// One row of the selector's table: `what`, the means, the samples past CSF's figure.
void printLine(const std::string& what, const std::vector<AdaptiveSample>& samples, const std::vector<Counts>& c);

}  // namespace bench
