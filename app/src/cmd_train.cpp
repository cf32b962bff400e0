// app/src/cmd_train.cpp: `ladarvr train CORPUS_DIR... --out MODEL`: learns the trained
// detector (detect/training.hpp) from finished corpus folders, their clouds and
// ground-truth labels, and writes the model file `ladarvr detect --model` reads.
#include "cli_common.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/training.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>
#include <platform/safe_file.hpp>
#include <sim/memory_budget.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace app {
namespace {

struct TrainCli {
    std::vector<std::string> corpora;
    std::string out;
    std::vector<double> target_size_m{7.0, 3.5, 2.5};
    double memory_mb = sim::kDefaultMemoryMb;
    bool fixed_segment_lengths = false;
    detect::TrainOptions options;
};

void run(TrainCli& cli) {
    detect::TrainOptions& o = cli.options;
    o.target_size_m = {cli.target_size_m[0], cli.target_size_m[1], cli.target_size_m[2]};
    o.segments.scale_with_spacing = !cli.fixed_segment_lengths;
    detect::validate(o);
    std::uint64_t budget = sim::memoryBudgetBytes(cli.memory_mb, "train");
    std::vector<platform::RunPath> paths;
    for (const std::string& dir : cli.corpora) paths.push_back({"corpus", dir, platform::PathRole::InputFolder, {}});
    paths.push_back({"--out", cli.out, platform::PathRole::Output, {}});
    platform::checkDistinctPaths("train", paths);
    createParentFolders(cli.out, "train: --out");
    platform::checkWritableDestination(cli.out);

    std::vector<detect::CorpusListing> listings;
    std::vector<std::string> manifests;
    platform::InputSet inputs;  // the manifests read: the model may not replace one
    std::size_t total = 0;
    for (const std::string& dir : cli.corpora) {
        // The listings stay while the items are read: what they hold leaves the rest of the budget.
        listings.push_back(detect::listCorpus(dir, budget));
        inputs.addFile(listings.back().manifest());
        budget -= std::min(budget, std::uint64_t(listings.back().held_bytes));
        manifests.push_back(listings.back().manifest_sha256);
        total += listings.back().ids.size();
    }
    std::vector<detect::TrainingItem> items;
    std::size_t done = 0;
    for (const detect::CorpusListing& l : listings)
        for (std::size_t k = 0; k < l.ids.size(); ++k) {
            const std::filesystem::path path = l.cloud(k);
            platform::checkNoLinkBelow(l.dir, std::filesystem::path("items") / l.ids[k] / l.cloud_files[k],
                                       "train: item " + l.ids[k]);
            io::CloudReader reader(path);
            sim::refuseOverBudget(
                "train", budget, detect::BoostedDetector::memoryBytes(reader.pointsBound()),
                "item " + l.ids[k] + ": a cloud of " + std::to_string(reader.pointsBound()) + " points, read whole",
                "raise --memory-mb");
            const core::PointCloud cloud = io::readCloud(reader);
            items.push_back(detect::describeLabelledCloud(cloud, path.string(), o));
            std::fprintf(stderr, "train: %zu/%zu %s: %zu segments\n", ++done, total, path.string().c_str(),
                         items.back().labels.size());
        }
    detect::TrainReport report;
    const detect::BoostedModel model = detect::trainDetector(items, o, manifests, report);
    platform::checkWritableDestination(cli.out, inputs);
    model.write(cli.out);
    std::printf(
        "train: %zu items (%zu held out), %zu segments, %zu target segments; %d trees of depth <= %d; "
        "XGBoost %s; wrote %s\n",
        report.items, report.heldout_items, report.segments, report.positives, o.boost.rounds, o.boost.max_depth,
        model.info().library_version.c_str(), cli.out.c_str());
    std::printf(
        "calibration (Platt a %.3f, b %.3f) checked on %s: %zu segments, %zu target; Brier %.4f, log loss %.4f\n",
        model.info().platt_a, model.info().platt_b,
        report.calibrated_on_heldout ? "the held-out items" : "the training items (held-out lack a class)",
        report.calibrated_on_heldout ? report.heldout_segments : report.segments - report.heldout_segments,
        report.calibrated_on_heldout ? report.heldout_positives : report.positives - report.heldout_positives,
        report.brier, report.log_loss);
    const char* bins[4] = {"[0, 0.1)", "[0.1, 0.5)", "[0.5, 0.9)", "[0.9, 1]"};
    for (int b = 0; b < 4; ++b)
        std::printf("  p in %-10s %6zu segments, mean p %.3f, share target %.3f\n", bins[b], report.bin_count[b],
                    report.bin_mean_probability[b], report.bin_positive_share[b]);
}

}  // namespace

void registerTrain(CLI::App& cli) {
    auto state = std::make_shared<TrainCli>();
    detect::TrainOptions& o = state->options;
    CLI::App* c = cli.add_subcommand(
        "train", "learn the trained detector (`detect --model`) from corpus folders' labelled clouds");
    c->add_option("corpus", state->corpora, "finished corpus folders (`ladarvr corpus`), one or more")->required();
    c->add_option("--out", state->out, "model file to write")->required();
    c->add_option("--target-size-m", state->target_size_m,
                  "the size class: target length width height, metres (default a main battle tank: 7 3.5 2.5)")
        ->expected(3);
    c->add_option("--rounds", o.boost.rounds, "boosting rounds (trees), [1, 10000]")->capture_default_str();
    c->add_option("--max-depth", o.boost.max_depth, "depth of each tree, [1, 16]")->capture_default_str();
    c->add_option("--eta", o.boost.eta, "learning rate, (0, 1]")->capture_default_str();
    c->add_option("--holdout-fraction", o.holdout_fraction, "share of the items held out for the calibration, [0, 0.9]")
        ->capture_default_str();
    c->add_option("--min-height-m", o.segments.min_height_m,
                  "points at most this high above the SMRF terrain are ground, [0, 10] m (recorded in the model)")
        ->capture_default_str();
    c->add_option("--ground-sigmas", o.segments.ground_sigmas,
                  "... or at most this many measured ground thicknesses (one sigma of a noisy sensor's ground), "
                  "[0, 20] (recorded in the model)")
        ->capture_default_str();
    c->add_option("--segment-voxel-m", o.segments.voxel_m, "voxel side of the segmentation, [0.05, 10] m")
        ->capture_default_str();
    c->add_option("--segment-tolerance-m", o.segments.cluster_tolerance_m,
                  "voxels whose centroids are closer join one segment, (voxel / 2, 10] m")
        ->capture_default_str();
    c->add_option("--segment-core-points", o.segments.core_points,
                  "a voxel with fewer points does not join two segments (it joins its nearest denser voxel), "
                  "[1, 1000]")
        ->capture_default_str();
    c->add_option("--split-height-m", o.segments.split_height_m,
                  "a segment reaching above this height over the terrain loses what stands free below it "
                  "(a vehicle against a wall or under touching crowns), 0 (no split) or [1, 100] m")
        ->capture_default_str();
    c->add_option("--level-cell-m", o.segments.level_cell_m,
                  "the terrain is levelled on the ground's own points in squares of this side (recorded in the "
                  "model), 0 (no levelling) or [1, 100] m")
        ->capture_default_str();
    c->add_flag("--fixed-segment-lengths", state->fixed_segment_lengths,
                "keep the voxel, join distance and noise bar as given on sparse clouds too, instead of scaling "
                "them with the measured point spacing (recorded in the model)");
    c->add_option("--threads", o.boost.threads, "threads for the features and XGBoost, >= 1")->capture_default_str();
    c->add_option("--seed", o.boost.seed, "XGBoost's seed")->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb,
                  "bound on what the corpus listings and one item's cloud and its segments hold, [1, 1048576] MiB")
        ->capture_default_str();
    c->callback([state] { run(*state); });
}

}  // namespace app
