// bench/src/ground_isprs_selector.hpp: a learned selector of SMRF's options per place on
// the ISPRS samples (`bench ground-isprs --selector`). Each sample is fitted with a few
// option sets; each square tile is described by what the sets say there (the share of
// points each calls ground, how far their terrains part, the heights above them, the
// terrain's slope and roughness, the density as a ratio to the sample's); gradient-boosted
// trees (XGBoost) learned on the other sites' tiles choose the set whose labels the tile's
// points take (leave-one-site-out), beside the per-tile oracle over the same sets. The same
// choice per patch where the sets disagree is ground_isprs_selector_segments.hpp.
#pragma once
#include "ground_isprs_adaptive.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace bench {

/// One option set the selector chooses among; cell 1 m, low outliers and raised segments
/// as `ladarvr ground` (sim::surveySmrfOptions).
struct SelectorSet {
    const char* name;
    double slope, window_m, threshold_m, scalar;
};

/// The sets, `ladarvr ground`'s first (the base the others are compared with).
const std::vector<SelectorSet>& selectorSets();

/// The pairwise trees' choice for a tile: `beats_base[g]` is the probability that set
/// g + 1 labels the tile better than the base set; the most probable over 0.5 is chosen,
/// else the base (0). Returns an index into the sets compared.
std::size_t choosePairwise(const std::vector<double>& beats_base);

/// A pairwise training row's label and weight: label 1 when the other set gets fewer points
/// wrong than the base; weight the difference, as a percentage of the sample's points (the
/// mean total error the choice moves). Weight 0 where they tie.
struct PairTarget {
    float label = 0, weight = 0;
};
PairTarget pairTarget(double wrong_base, double wrong_other, double sample_points);

/// Scores the selector leave-one-site-out (the site is the sample name's first digit) over
/// tile sizes, subsets of the sets, kinds and shapes of trees, and per patch of
/// disagreement; prints one line per variant and a per-sample table of the variant fixed
/// beforehand (3 sets, 50 m tiles, pairwise trees) beside `ladarvr ground`'s set, the oracle
/// and the patches, and returns that variant's labels per sample (1 = ground). Needs
/// samples of at least two sites. Throws core::Error.
std::vector<std::vector<std::uint8_t>> runSelector(const std::vector<AdaptiveSample>& samples);

}  // namespace bench
