// corpus/src/apply.hpp: a sampled value of a generator parameter into sim::GenerateOptions.
#pragma once
#include <sim/generator.hpp>

#include <string_view>

namespace corpus::detail {

/// Sets the generator parameter named by vary key `key` to `value` (integers already
/// whole). Keys that are not generator parameters (the target's and C's placement,
/// environment_keep_fraction) are left to the planner and ignored here.
void applyToOptions(sim::GenerateOptions& o, std::string_view key, double value);

}  // namespace corpus::detail
