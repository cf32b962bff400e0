// sim/src/ground_internal.hpp: what the ground filter factory (ground_filter.cpp) needs
// from each filter's own file.
#pragma once
#include <sim/ground.hpp>

#include <memory>

namespace sim {

/// ground_ransac.cpp: checks RANSAC's fields of GroundOptions.
void validateRansac(const GroundOptions& o);
/// ground_ransac.cpp: the paper's per-view filter.
std::unique_ptr<GroundFilter> makeRansacFilter(const GroundOptions& o);
/// ground_smrf.cpp: the whole-cloud simple morphological filter.
std::unique_ptr<GroundFilter> makeSmrfFilter(const SmrfOptions& o);
/// ground_csf.cpp: the whole-cloud cloth simulation filter.
std::unique_ptr<GroundFilter> makeCsfFilter(const CsfOptions& o);

}  // namespace sim
