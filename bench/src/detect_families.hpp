// bench/src/detect_families.hpp: the trained detector on vehicle families it never saw
// (part of `ladarvr bench detect`, its --families run): leave one family out.
#pragma once
#include <filesystem>
#include <string>

namespace bench {

struct FamilyBenchOptions {
    std::string configuration = "small";  // "full", "small" (minutes on 2 cores) or "test" (seconds)
    std::filesystem::path tmp;            // scratch folder, kept, the models in tmp/models (empty: a temporary one)
    int threads = 2;                      // the generator's, the features' and XGBoost's threads
    std::filesystem::path shipped_model;  // evaluated beside the others (empty: not)
    std::filesystem::path pr_svg;         // the precision-recall curves drawn here (empty: none)
    std::string pr_link;                  // ... and linked from the section by this path
};

/// Generates the vehicle families (scripts/make_vehicles.py), builds a training and an
/// evaluation corpus per family (other vehicles of the family in each) on synthetic scenes
/// and on real places (training and evaluation on different ISPRS sites), trains one model
/// per family on all the other families' items and one on all, and evaluates on each
/// family's clouds: the model that never saw the family, the model trained on all, the
/// shipped model and the clustering baseline; then the first and the last on every
/// evaluation cloud thinned, per band of density on the target. Returns the markdown
/// section's body.
std::string runFamilyComparison(const FamilyBenchOptions& o);

}  // namespace bench
