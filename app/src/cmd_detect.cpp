// app/src/cmd_detect.cpp: `ladarvr detect CLOUD --out candidates.json [--model MODEL]`:
// the baseline 3D ATR of detect/cluster_detector.hpp, or with --model the trained detector
// of detect/boosted_detector.hpp, so `view --candidates` and studies have something to
// validate. Writes io/candidates_file.hpp's JSON. The clustering options are the
// baseline's own group, its terrain filters' (--smrf-*, --csf-*) the generator's groups;
// --model and --threads are the trained detector's. A survey in feet is detected in
// metres and its candidates' centres written in its own coordinates (detect/cloud_units.hpp).
#include "cli_common.hpp"
#include "commands.hpp"
#include "ground_options.hpp"

#include <core/error.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/cloud_units.hpp>
#include <detect/cluster_detector.hpp>
#include <io/candidates_file.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>
#include <platform/safe_file.hpp>
#include <sim/ground_units.hpp>
#include <sim/memory_budget.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
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

// One detector as `detect` runs it: the detection (a detect::Detector's, with the figures
// it keeps while it runs), what it holds for a cloud, and those figures as the report
// prints them. A new detector is a new DetectRun beside these two; the path from the
// cloud to the report (detectAndReport) stays one.
class DetectRun {
  public:
    virtual ~DetectRun() = default;
    /// At most what reading a cloud of `points` points and detecting in it holds, bytes.
    virtual std::uint64_t memoryBytes(std::uint64_t points) const = 0;
    /// The candidates in `cloud`, best first; the run's figures are kept for the report.
    virtual std::vector<detect::Detection> detect(const core::PointCloud& cloud) = 0;
    /// The run's figures as fields of the --json object.
    virtual void addFigures(nlohmann::json& j) const = 0;
    /// Prints the first line of the text report.
    virtual void printSummary(std::size_t candidates, const std::string& out) const = 0;
    /// The word before each listed candidate's score.
    virtual const char* scoreName() const = 0;
};

// The clustering baseline.
class ClusterRun final : public DetectRun {
  public:
    ClusterRun(const detect::ClusterDetector& detector, std::string ground)
        : detector_(detector), ground_(std::move(ground)) {}
    std::uint64_t memoryBytes(std::uint64_t points) const override {
        return detect::ClusterDetector::memoryBytes(points);
    }
    std::vector<detect::Detection> detect(const core::PointCloud& cloud) override {
        return detector_.detect(cloud, stats_);
    }
    void addFigures(nlohmann::json& j) const override {
        j["points"] = stats_.points;
        j["ground_points"] = stats_.ground_points;
        j["voxels"] = stats_.voxels;
        j["clusters"] = stats_.clusters;
        j["seconds"] = {
            {"ground", stats_.seconds_ground}, {"cluster", stats_.seconds_cluster}, {"boxes", stats_.seconds_boxes}};
    }
    void printSummary(std::size_t candidates, const std::string& out) const override {
        std::printf(
            "detect: %zu points, %zu ground (%s), %zu clusters, %zu candidates with score >= %.2f; "
            "%.2f s; wrote %s\n",
            stats_.points, stats_.ground_points, ground_.c_str(), stats_.clusters, candidates,
            detector_.options().min_score, stats_.seconds_ground + stats_.seconds_cluster + stats_.seconds_boxes,
            out.c_str());
    }
    const char* scoreName() const override { return "score"; }

  private:
    const detect::ClusterDetector& detector_;
    std::string ground_;
    detect::ClusterStats stats_;
};

// The trained detector.
class ModelRun final : public DetectRun {
  public:
    ModelRun(const detect::BoostedDetector& detector, const detect::BoostedOptions& options)
        : detector_(detector), options_(options) {}
    std::uint64_t memoryBytes(std::uint64_t points) const override {
        return detect::BoostedDetector::memoryBytes(points);
    }
    std::vector<detect::Detection> detect(const core::PointCloud& cloud) override {
        return detector_.detect(cloud, stats_);
    }
    void addFigures(nlohmann::json& j) const override {
        j["model"] = options_.model.string();
        j["points"] = stats_.points;
        j["above_points"] = stats_.above_points;
        j["segments"] = stats_.segments;
        if (stats_.spacing_scale > 1.0)
            j["segment_scale"] = {{"spacing_m", stats_.spacing_m}, {"scale", stats_.spacing_scale}};
        j["seconds"] = {{"segments_and_features", stats_.seconds_features}, {"trees", stats_.seconds_trees}};
    }
    void printSummary(std::size_t candidates, const std::string& out) const override {
        std::printf(
            "detect: %zu points, %zu above the terrain, %zu segments, %zu candidates with probability >= %.2f "
            "(model %s); %.2f s; wrote %s\n",
            stats_.points, stats_.above_points, stats_.segments, candidates, options_.min_probability,
            options_.model.c_str(), stats_.seconds_features + stats_.seconds_trees, out.c_str());
        if (stats_.spacing_scale > 1.0)
            std::printf("  sparse cloud: point spacing %.2f m, segment voxel and join distance scaled %.2f times\n",
                        stats_.spacing_m, stats_.spacing_scale);
    }
    const char* scoreName() const override { return "p"; }

  private:
    const detect::BoostedDetector& detector_;
    detect::BoostedOptions options_;
    detect::BoostedStats stats_;
};

// The one path of every detector, once its options and the run's paths are checked: the
// destination made ready and kept off the run's `inputs`, the cloud's header weighed
// against the budget (a cloud that would not fit is refused before a point is read), the
// cloud read, the candidates found, written and reported (JSON or text, the first five
// listed).
void detectAndReport(const DetectCli& cli, const platform::InputSet& inputs, std::uint64_t budget, DetectRun& run) {
    const sim::CoordinateUnits units = sim::readCoordinateUnits(cli.cloud, "detect");
    const std::filesystem::path out = cli.out;
    createParentFolders(out, "detect: --out");
    platform::checkWritableDestination(out, inputs);
    io::CloudReader reader(cli.cloud);
    sim::refuseOverBudget("detect", budget, run.memoryBytes(reader.pointsBound()),
                          "a cloud of " + std::to_string(reader.pointsBound()) + " points, read whole",
                          "raise --memory-mb, or detect in a thinned or cropped cloud");
    core::PointCloud cloud = io::readCloud(reader);
    detect::scaleToMetres(cloud, units);
    const std::vector<detect::Detection> found = run.detect(cloud);
    std::vector<core::Candidate> candidates;
    for (const detect::Detection& d : found) candidates.push_back(d.candidate);
    candidates = detect::centresInUnits(std::move(candidates), cloud.origin, units);
    io::writeCandidates(out, candidates, detect::candidateUnits(units));
    if (cli.json) {
        nlohmann::json j;
        j["cloud"] = cli.cloud;
        j["out"] = cli.out;
        j["candidates"] = candidates.size();
        if (!units.metres()) j["units"] = sim::describe(units);
        run.addFigures(j);
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    run.printSummary(candidates.size(), cli.out);
    if (!units.metres())
        std::printf("  coordinates in %s: detected in metres, centres written in the cloud's coordinates\n",
                    sim::describe(units).c_str());
    for (std::size_t k = 0; k < candidates.size() && k < 5; ++k) {
        const core::Candidate& c = candidates[k];
        std::printf("  %-4s %s %.3f  centre %.2f %.2f %.2f  size %.2f x %.2f x %.2f m  yaw %.1f deg  %zu points\n",
                    c.id.c_str(), run.scoreName(), c.score, c.centre_world.x, c.centre_world.y, c.centre_world.z,
                    c.size_m.x, c.size_m.y, c.size_m.z, c.yaw_deg, found[k].points.size());
    }
    if (candidates.size() > 5) std::printf("  ... %zu more in %s\n", candidates.size() - 5, cli.out.c_str());
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
    platform::checkDistinctPaths("detect", {{"cloud", cli.cloud, platform::PathRole::Input, {}},
                                            {"--model", cli.model, platform::PathRole::Input, {}},
                                            {"--out", cli.out, platform::PathRole::Output, {}}});
    const detect::BoostedDetector detector(bo);  // reads and checks the model
    const glm::dvec3 size = detector.model().info().target_size_m;
    if (cli.target_size_given &&
        (cli.target_size_m[0] != size.x || cli.target_size_m[1] != size.y || cli.target_size_m[2] != size.z))
        throw core::Error("detect: --target-size-m " + std::to_string(cli.target_size_m[0]) + " " +
                          std::to_string(cli.target_size_m[1]) + " " + std::to_string(cli.target_size_m[2]) +
                          ": the model " + cli.model + " was trained for " + std::to_string(size.x) + " " +
                          std::to_string(size.y) + " " + std::to_string(size.z) +
                          "; allowed that size or none (train a model for another size class)");
    platform::InputSet inputs;
    inputs.addFile(cli.cloud);
    inputs.addFile(cli.model);
    ModelRun run(detector, bo);
    detectAndReport(cli, inputs, budget, run);
}

// The clustering baseline: its own options, and the ground the --ground option names.
void run(DetectCli& cli) {
    if (!cli.model.empty()) return runModel(cli);
    detect::ClusterOptions& o = cli.options;
    o.target_size_m = {cli.target_size_m[0], cli.target_size_m[1], cli.target_size_m[2]};
    o.ground = parseGround(cli.ground);
    o.progress = true;                          // drawn only when stderr is a terminal
    const detect::ClusterDetector detector(o);  // validates the options
    const std::uint64_t budget = sim::memoryBudgetBytes(cli.memory_mb, "detect");
    platform::checkDistinctPaths("detect", {{"cloud", cli.cloud, platform::PathRole::Input, {}},
                                            {"--out", cli.out, platform::PathRole::Output, {}}});
    platform::InputSet inputs;
    inputs.addFile(cli.cloud);
    ClusterRun run(detector, cli.ground);
    detectAndReport(cli, inputs, budget, run);
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
