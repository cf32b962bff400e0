// bench/src/detect_trained.hpp: the trained detector against the clustering baseline on
// clouds neither saw in training (part of `ladarvr bench detect`).
#pragma once
#include <filesystem>
#include <string>
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

}  // namespace bench
