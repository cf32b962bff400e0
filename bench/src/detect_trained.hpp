// bench/src/detect_trained.hpp: the trained detector against the clustering baseline on
// clouds neither saw in training (part of `ladarvr bench detect`).
#pragma once
#include <core/point_cloud.hpp>
#include <detect/detector.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace bench {

struct TrainedBenchOptions {
    bool quick = false;                         // tiny corpora and clouds: a smoke run, figures not meaningful
    std::filesystem::path tmp;                  // scratch folder (empty: a new one under the temp dir, removed)
    int threads = 2;                            // the trained detector's and the generator's threads
    int eval_items = 10;                        // evaluation items per scene
    int train_scale = 1;                        // training corpora of this many times their SPEC's items
    std::vector<std::filesystem::path> clouds;  // --clouds: only the per-cloud table of these
    std::filesystem::path model;                // --model: the model --clouds uses
    int explain = 0;                            // --clouds: list this many best candidates of each cloud
    std::filesystem::path pr_csv;               // the precision-recall curves of both detectors (empty: none)
    int repeats = 3;                            // detections of each cloud by each detector; its time is their median
};

/// Trains on the corpora of assets/detect/train_*.json, evaluates both detectors on new
/// corpora (other seeds, terrains, a target model not in training) and on the bundled
/// scenes seen by the sensor presets; returns the markdown section's body.
std::string runTrainedComparison(const TrainedBenchOptions& o);

/// Each of o.clouds with o.model and the baseline: the target's rank with each, the
/// segment holding most target points (its size, its target points), the points above
/// the terrain, the measured ground thickness; returns a markdown table. With o.explain > 0,
/// a second table lists each cloud's o.explain best candidates and the target's: what
/// outranks the target.
std::string rankClouds(const TrainedBenchOptions& o);

// What the detector benchmarks share (bench/src/detect_trained.cpp).

/// One detector on one labelled cloud.
struct Outcome {
    int rank = 0;                                 // 1-based rank of the first true positive, 0 when none
    double seconds = 0;                           // median of the repeated detections
    double seconds_min = 0, seconds_max = 0;      // their spread
    std::vector<std::pair<double, bool>> scored;  // every candidate: score, true positive
};

/// Outcomes over clouds: rank-1 and top-3 counts, and the false candidates per cloud at
/// the highest score threshold that still finds >= 90 % of the targets (-1: not reached).
struct Summary {
    std::size_t clouds = 0, rank1 = 0, top3 = 0, found = 0;
    double threshold = -1, false_per_cloud = -1, median_s = 0, max_s = 0;
};

/// Detects `repeats` times (the time their median); every run must give the same
/// candidates. A candidate is a true positive when most of its points are labelled target.
Outcome evaluate(const detect::Detector& d, const core::PointCloud& c, int repeats, const std::string& name);
Summary summarise(const std::vector<Outcome>& outcomes);
/// A markdown row: name, clouds, ranked 1st, top 3, found, threshold, false per cloud, times.
std::string summaryRow(const char* name, const Summary& s);
/// One point of a precision-recall curve over clouds, per distinct score threshold from
/// the highest down: precision = true candidates / candidates at or above it, recall =
/// clouds whose target a candidate at or above it finds / clouds, and the false
/// candidates per cloud there.
struct PrPoint {
    double threshold, precision, recall, false_per_cloud;
};
std::vector<PrPoint> prCurve(const std::vector<Outcome>& outcomes);
/// Writes SPEC `spec` as DIR/NAME.json; returns its path.
std::filesystem::path writeSpec(const std::filesystem::path& dir, const std::string& name, nlohmann::json spec);
/// Builds a corpus; with allow_failed, items that cannot be planned are left out with a
/// line each and their count returned.
std::size_t buildCorpus(const std::filesystem::path& spec, const std::filesystem::path& out, int threads,
                        bool allow_failed = false);
/// Each item's sensor preset, from its manifest line's replay options (no --sensor: ideal).
std::map<std::string, std::string> sensorOfItems(const std::filesystem::path& dir);

}  // namespace bench
