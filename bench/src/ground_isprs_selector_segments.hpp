// bench/src/ground_isprs_selector_segments.hpp: SMRF's option sets chosen per patch where
// they disagree (`bench ground-isprs --selector`): the points a set labels otherwise than
// the base set, joined into connected patches through 2 m cells, each patch described
// (its size, its heights above both terrains, its planarity, the step to the ground
// around it) and given the set's labels where trees learned on the other sites' patches
// say the set is right there (leave-one-site-out), beside the per-patch oracle.
#pragma once
#include "ground_isprs_selector_fits.hpp"

#include <vector>

namespace bench {

/// The connected patches of the points `fits` labels differently under set `g` and the
/// base: for each patch, its points (indices). Two points join when their 2 m cells touch
/// (8 neighbours).
std::vector<std::vector<std::size_t>> disagreementPatches(const SampleFits& fits, std::size_t g);

/// Prints one oracle line and one selector line per subset of the sets (the table rows of
/// runSelector; with `three_only` only the selector over the base, gentle and steep sets)
/// and returns, per sample, the counts of that selector. Throws core::Error.
std::vector<Counts> printSegmentSelector(const std::vector<AdaptiveSample>& samples,
                                         const std::vector<SampleFits>& fits, const TreeShape& shape,
                                         bool three_only = false);

}  // namespace bench
