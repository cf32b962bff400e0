// app/src/cmd_detect.cpp: `ladarvr detect CLOUD --out candidates.json [--model MODEL]`:
// the baseline 3D ATR of detect/cluster_detector.hpp, or with --model the trained detector
// of detect/boosted_detector.hpp, so `view --candidates` and studies have something to
// validate. Writes io/candidates_file.hpp's JSON. The clustering options are the
// baseline's own group, its terrain filters' (--smrf-*, --csf-*) the generator's groups;
// --model and --threads are the trained detector's.
#include "cli_common.hpp"
#include "commands.hpp"
#include "ground_options.hpp"

#include <core/error.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/cluster_detector.hpp>
#include <io/candidates_file.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>
#include <sim/memory_budget.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace app {
namespace {

struct DetectCli {
    std::string cloud;
    std::string out;
    std::vector<double> target_size_m{7.0, 3.5, 2.5};
    std::string ground = "ransac";
    bool json = false;
    double memory_mb = sim::kDefaultMemoryMb;
    detect::ClusterOptions options;
    std::string model;  // the trained detector's model file; empty = the clustering baseline
    int threads = 1;
    bool target_size_given = false, min_score_given = false;
};

detect::GroundSource parseGround(const std::string& name) {
    if (name == "ransac") return detect::GroundSource::Ransac;
    if (name == "smrf") return detect::GroundSource::Smrf;
    if (name == "csf") return detect::GroundSource::Csf;
    if (name == "labels") return detect::GroundSource::Labels;
    if (name == "white") return detect::GroundSource::White;
    throw core::Error("detect: --ground '" + name + "': allowed ransac, smrf, csf, labels, white");
}

// The trained detector: the model decides the segmentation and the size class.
void runModel(DetectCli& cli) {
    detect::BoostedOptions bo;
    bo.model = cli.model;
    bo.threads = cli.threads;
    bo.max_candidates = cli.options.max_candidates;
    if (cli.min_score_given) bo.min_probability = cli.options.min_score;
    detect::validate(bo);
    const std::uint64_t budget = sim::memoryBudgetBytes(cli.memory_mb, "detect");
    const std::filesystem::path out = cli.out;
    platform::checkDistinctPaths("detect", {{"cloud", cli.cloud, platform::PathRole::Input, {}},
                                            {"--model", cli.model, platform::PathRole::Input, {}},
                                            {"--out", out, platform::PathRole::Output, {}}});
    const detect::BoostedDetector detector(bo);  // reads and checks the model
    const glm::dvec3 size = detector.model().info().target_size_m;
    if (cli.target_size_given &&
        (cli.target_size_m[0] != size.x || cli.target_size_m[1] != size.y || cli.target_size_m[2] != size.z))
        throw core::Error("detect: --target-size-m " + std::to_string(cli.target_size_m[0]) + " " +
                          std::to_string(cli.target_size_m[1]) + " " + std::to_string(cli.target_size_m[2]) +
                          ": the model " + cli.model + " was trained for " + std::to_string(size.x) + " " +
                          std::to_string(size.y) + " " + std::to_string(size.z) +
                          "; allowed that size or none (train a model for another size class)");
    createParentFolders(out, "detect: --out");
    platform::checkWritableDestination(out);
    io::CloudReader reader(cli.cloud);
    sim::refuseOverBudget("detect", budget, detect::BoostedDetector::memoryBytes(reader.pointsBound()),
                          "a cloud of " + std::to_string(reader.pointsBound()) + " points, read whole",
                          "raise --memory-mb, or detect in a thinned or cropped cloud");
    const core::PointCloud cloud = io::readCloud(reader);
    detect::BoostedStats stats;
    const std::vector<detect::Detection> found = detector.detect(cloud, stats);
    std::vector<core::Candidate> candidates;
    for (const detect::Detection& d : found) candidates.push_back(d.candidate);
    io::writeCandidates(out, candidates);
    if (cli.json) {
        nlohmann::json j;
        j["cloud"] = cli.cloud;
        j["out"] = cli.out;
        j["model"] = cli.model;
        j["points"] = stats.points;
        j["above_points"] = stats.above_points;
        j["segments"] = stats.segments;
        j["candidates"] = candidates.size();
        j["seconds"] = {{"segments_and_features", stats.seconds_features}, {"trees", stats.seconds_trees}};
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf(
        "detect: %zu points, %zu above the terrain, %zu segments, %zu candidates with probability >= %.2f "
        "(model %s); %.2f s; wrote %s\n",
        stats.points, stats.above_points, stats.segments, candidates.size(), bo.min_probability, cli.model.c_str(),
        stats.seconds_features + stats.seconds_trees, cli.out.c_str());
    for (std::size_t k = 0; k < candidates.size() && k < 5; ++k) {
        const core::Candidate& c = candidates[k];
        std::printf("  %-4s p %.3f  centre %.2f %.2f %.2f  size %.2f x %.2f x %.2f m  yaw %.1f deg  %zu points\n",
                    c.id.c_str(), c.score, c.centre_world.x, c.centre_world.y, c.centre_world.z, c.size_m.x, c.size_m.y,
                    c.size_m.z, c.yaw_deg, found[k].points.size());
    }
    if (candidates.size() > 5) std::printf("  ... %zu more in %s\n", candidates.size() - 5, cli.out.c_str());
}

void run(DetectCli& cli) {
    if (!cli.model.empty()) return runModel(cli);
    detect::ClusterOptions& o = cli.options;
    o.target_size_m = {cli.target_size_m[0], cli.target_size_m[1], cli.target_size_m[2]};
    o.ground = parseGround(cli.ground);
    o.progress = true;                          // drawn only when stderr is a terminal
    const detect::ClusterDetector detector(o);  // validates the options

    const std::uint64_t budget = sim::memoryBudgetBytes(cli.memory_mb, "detect");

    const std::filesystem::path out = cli.out;
    platform::checkDistinctPaths("detect", {{"cloud", cli.cloud, platform::PathRole::Input, {}},
                                            {"--out", out, platform::PathRole::Output, {}}});
    createParentFolders(out, "detect: --out");
    platform::checkWritableDestination(out);

    // The header first: a cloud that would not fit the budget is refused before a point is read.
    io::CloudReader reader(cli.cloud);
    sim::refuseOverBudget("detect", budget, detect::ClusterDetector::memoryBytes(reader.pointsBound()),
                          "a cloud of " + std::to_string(reader.pointsBound()) + " points, read whole",
                          "raise --memory-mb, or detect in a thinned or cropped cloud");
    const core::PointCloud cloud = io::readCloud(reader);
    detect::ClusterStats stats;
    const std::vector<detect::Detection> found = detector.detect(cloud, stats);
    std::vector<core::Candidate> candidates;
    for (const detect::Detection& d : found) candidates.push_back(d.candidate);
    io::writeCandidates(out, candidates);

    if (cli.json) {
        nlohmann::json j;
        j["cloud"] = cli.cloud;
        j["out"] = cli.out;
        j["points"] = stats.points;
        j["ground_points"] = stats.ground_points;
        j["voxels"] = stats.voxels;
        j["clusters"] = stats.clusters;
        j["candidates"] = candidates.size();
        j["seconds"] = {
            {"ground", stats.seconds_ground}, {"cluster", stats.seconds_cluster}, {"boxes", stats.seconds_boxes}};
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf(
        "detect: %zu points, %zu ground (%s), %zu clusters, %zu candidates with score >= %.2f; "
        "%.2f s; wrote %s\n",
        stats.points, stats.ground_points, cli.ground.c_str(), stats.clusters, candidates.size(), o.min_score,
        stats.seconds_ground + stats.seconds_cluster + stats.seconds_boxes, cli.out.c_str());
    for (std::size_t k = 0; k < candidates.size() && k < 5; ++k) {
        const core::Candidate& c = candidates[k];
        std::printf("  %-4s score %.3f  centre %.2f %.2f %.2f  size %.2f x %.2f x %.2f m  yaw %.1f deg  %zu points\n",
                    c.id.c_str(), c.score, c.centre_world.x, c.centre_world.y, c.centre_world.z, c.size_m.x, c.size_m.y,
                    c.size_m.z, c.yaw_deg, found[k].points.size());
    }
    if (candidates.size() > 5) std::printf("  ... %zu more in %s\n", candidates.size() - 5, cli.out.c_str());
}

}  // namespace

void registerDetect(CLI::App& cli) {
    auto state = std::make_shared<DetectCli>();
    detect::ClusterOptions& o = state->options;
    CLI::App* c =
        cli.add_subcommand("detect",
                           "baseline 3D ATR: cluster the non-ground points, fit oriented boxes, score them by how well "
                           "their size matches the target's; writes candidates for `view --candidates`");
    c->add_option("cloud", state->cloud, "the cloud (PCD, PLY, LAS or LAZ)")->required();
    c->add_option("--out", state->out, "candidates file to write (JSON)")->required();
    c->add_option("--model", state->model,
                  "a trained detector's model file (`ladarvr train`); without it the clustering baseline runs");
    c->add_option("--threads", state->threads,
                  "with --model: threads for the segmentation, the features and the trees, [1, 1024] (results do not "
                  "depend on it)")
        ->capture_default_str();
    c->add_option("--target-size-m", state->target_size_m,
                  "target length width height, metres (default a main battle tank: 7 3.5 2.5); with --model it "
                  "must match the model's size class")
        ->expected(3);
    c->add_option("--size-tolerance", o.size_tolerance, "size factor (> 1) that costs one side exp(-1/2) of the score")
        ->capture_default_str();
    c->add_option("--ground", state->ground,
                  "what is ground: ransac (paper's RANSAC per tile; flat ground), smrf or csf (the generator's "
                  "terrain-following filters on the whole cloud, for hilly or sloped ground), labels (the cloud's "
                  "ground-truth labels), white (the generator's whitened points)")
        ->check(CLI::IsMember({"ransac", "smrf", "csf", "labels", "white"}))
        ->capture_default_str();
    c->add_option("--ground-tile-m", o.ground_tile_m, "side of the RANSAC tiles, metres > 0")->capture_default_str();
    c->add_option("--band-m", o.ground_ransac.band_m, "RANSAC height band above each tile's lowest point, metres > 0")
        ->capture_default_str();
    addSmrfOptions(*c, o.ground_smrf);
    addCsfOptions(*c, o.ground_csf);
    c->add_option("--voxel-m", o.voxel_m, "voxel side for clustering, [0.01, 100] m")->capture_default_str();
    c->add_option("--cluster-tolerance-m", o.cluster_tolerance_m,
                  "voxels closer than this join one cluster, (voxel/2, 1000] m")
        ->capture_default_str();
    c->add_option("--trim-fraction", o.trim_fraction,
                  "fraction of a cluster's points ignored at each end of each box side (a gun barrel), [0, 0.5)")
        ->capture_default_str();
    c->add_option("--min-cluster-points", o.min_cluster_points, "smaller clusters are noise, >= 1")
        ->capture_default_str();
    c->add_option("--min-score", o.min_score,
                  "drop candidates scoring below, [0, 1] (with --model: the probability, default 0.01)")
        ->capture_default_str();
    c->add_option("--max-candidates", o.max_candidates, "keep at most this many, best first")->capture_default_str();
    c->add_option("--seed", o.seed, "seed of RANSAC's shuffles")->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb,
                  "bound on what the run holds, the cloud included, [1, 1048576] MiB: a cloud "
                  "whose header declares more points than fit is refused before it is read")
        ->capture_default_str();
    c->add_flag("--json", state->json, "print the run's figures as JSON on stdout");
    c->callback([state, c] {
        state->target_size_given = c->count("--target-size-m") > 0;
        state->min_score_given = c->count("--min-score") > 0;
        run(*state);
    });
}

}  // namespace app
