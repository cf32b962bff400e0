// detect/detector.hpp: the seam between a cloud and the target candidates found in it.
// `ladarvr detect`, the benchmarks and the studies see detectors only through this.
//
// Detectors:
//   - ClusterDetector (detect/cluster_detector.hpp): the baseline, no training: ground
//     removal, Euclidean clustering, an oriented box per cluster scored by its size.
//   - A trained detector (a network run on the cloud) goes beside it: its own header
//     detect/include/detect/<name>_detector.hpp with its own options struct (the model
//     file, thresholds), its own source detect/src/<name>_detector.cpp, and its own
//     option group in app/src/cmd_detect.cpp. Its runtime library is linked PRIVATE to
//     this module, as PCL is for the clustering.
#pragma once
#include <core/candidates.hpp>
#include <core/point_cloud.hpp>

#include <cstdint>
#include <vector>

namespace detect {

/// One candidate and the points it was found on. Point indices refer to the input cloud.
struct Detection {
    core::Candidate candidate;          // world coordinates (cloud origin added)
    std::vector<std::uint32_t> points;  // the candidate's points, ascending
};

class Detector {
  public:
    virtual ~Detector() = default;
    /// The candidates in `cloud`, best first, ids "c1", "c2", ... in that order.
    /// Throws core::Error("detect: ...") when the cloud lacks a field the detector needs.
    virtual std::vector<Detection> detect(const core::PointCloud& cloud) const = 0;
};

}  // namespace detect
