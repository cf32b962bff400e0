// sim/src/ground_internal.hpp: what the ground filter factories (ground_filter.cpp) need
// from each filter's own file.
#pragma once
#include <sim/ground.hpp>

#include <memory>

namespace sim {

/// Throws core::Error("ground: <parameter> = <value>: allowed <allowed>"), the line
/// every filter's option check gives (ground_filter.cpp).
[[noreturn]] void failGroundOption(const char* parameter, double value, const char* allowed);

/// ground_ransac.cpp: the paper's per-view filter.
std::unique_ptr<const ViewGroundFilter> makeRansacFilter(const RansacOptions& o);
/// ground_smrf.cpp: the whole-cloud simple morphological filter.
std::unique_ptr<const CloudGroundFilter> makeSmrfFilter(const SmrfOptions& o);
/// ground_csf.cpp: the whole-cloud cloth simulation filter.
std::unique_ptr<const CloudGroundFilter> makeCsfFilter(const CsfOptions& o);

/// A whole-cloud filter: each run fits a fresh `Fit` (a TerrainFit built from `Options`).
template <class Fit, class Options, GroundMethod kMethod>
class WholeCloudFilter final : public CloudGroundFilter {
  public:
    explicit WholeCloudFilter(const Options& o) : options_(o) {}
    GroundMethod method() const override { return kMethod; }
    std::unique_ptr<TerrainFit> startCloud() const override { return std::make_unique<Fit>(options_); }

  private:
    Options options_;
};

}  // namespace sim
