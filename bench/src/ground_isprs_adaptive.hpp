// bench/src/ground_isprs_adaptive.hpp: SMRF's parameters chosen per input on the ISPRS
// samples: the oracle (each sample's best over a grid of slope, window, threshold, scalar
// and cell), written as a table for the selection rule to be fitted from.
#pragma once
#include <core/point_cloud.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace bench {

/// One sample as the adaptive measurements see it.
struct AdaptiveSample {
    std::string name;
    const std::vector<core::CloudPoint>* points = nullptr;
    const std::vector<std::uint8_t>* truth = nullptr;  // 1 = bare earth
};

/// Scores every sample over the grid of SMRF options (`ladarvr ground`'s defaults otherwise)
/// and writes one CSV line per sample and grid point to `csv`: name, the options, type I,
/// type II, total, kappa. Prints each sample's best. Throws core::Error.
void writeAdaptiveGrid(const std::vector<AdaptiveSample>& samples, const std::string& csv);

/// Writes each sample's survey traits (sim::measureSurvey with `ladarvr ground`'s SMRF
/// defaults) to `csv`: name, then one column per trait. Throws core::Error.
void writeAdaptiveTraits(const std::vector<AdaptiveSample>& samples, const std::string& csv);

}  // namespace bench
