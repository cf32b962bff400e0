// bench/src/detect.cpp: `ladarvr bench detect`: how good the baseline detector
// (detect/cluster_detector.hpp) is, against the ground-truth labels of the bundled scenes' clouds.
//
// Each scene's cloud is generated with the paper's defaults; the detector runs with its
// defaults, once with RANSAC ground (what it does on a real cloud) and once with the
// labels' ground (an upper bound: perfect ground removal). A candidate is a true positive
// when most of its cluster's points are labelled target. Precision = true positives /
// candidates; target recall = scenes whose target is among the candidates; point recall =
// target points inside true-positive clusters / all target points.
#include "common.hpp"
#include "detect_families.hpp"
#include "detect_trained.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>
#include <detect/cluster_detector.hpp>
#include <io/scene_file.hpp>
#include <sim/generator.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace bench {
namespace {

struct BenchDetectCli {
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
    double threshold = 0.5;           // a second operating point besides the detector's min_score
    detect::ClusterOptions detector;  // the detector's options (defaults unless given)
    TrainedBenchOptions trained;      // the trained detector against the baseline
    std::string families;             // "small" or "full": only the leave-one-family-out run
};

// `bench detect --families small|full`: the leave-one-family-out run alone, its own
// section of the markdown file (unless --no-md).
void runFamilies(const BenchDetectCli& cli, Clock::time_point start) {
    if (cli.families != "small" && cli.families != "full" && cli.families != "test")
        throw core::Error("bench detect: --families = '" + cli.families + "': allowed small, full or test");
    FamilyBenchOptions fo;
    fo.configuration = cli.families;
    fo.tmp = cli.trained.tmp;
    fo.threads = cli.trained.threads;
    fo.shipped_model = sourceRoot() / "assets" / "detect" / "model.ldm";
    if (!cli.no_md) {
        fo.pr_link = "docs/img/detect_families_pr.svg";
        fo.pr_svg = std::filesystem::path(cli.md).parent_path() / fo.pr_link;
    }
    const std::string body = runFamilyComparison(fo);
    std::printf("%s", body.c_str());
    if (cli.no_md) return;
    const std::string heading = "## Detector on vehicle families it never saw (ladarvr bench detect --families)";
    std::ostringstream s;
    s << heading << "\n\n"
      << "Command: `./ladarvr bench detect --families " << cli.families << " --threads " << cli.trained.threads
      << "`; machine: " << std::thread::hardware_concurrency() << " cores, " << cpuName() << "; " << utcNow() << "; "
      << fmt("%.0f", secondsSince(start)) << " s in all.\n\n"
      << "bench/src/detect_families.cpp: leave one vehicle family out (scripts/make_vehicles.py's families).\n\n"
      << body << "\n";
    replaceMarkdownSection(cli.md, heading, s.str());
    std::fprintf(stderr, "bench detect: wrote the section to %s\n", cli.md.c_str());
}

struct Row {
    std::string scene, ground;
    std::size_t points = 0, target_points = 0, clusters = 0;
    // At the detector's min_score and at the bench's threshold.
    std::size_t candidates[2] = {0, 0}, true_positives[2] = {0, 0}, target_points_found[2] = {0, 0};
    int target_rank = 0;         // 1-based rank of the best true positive; 0 if none
    double target_score = 0.0;   // its score
    std::string target_box;      // its size
    std::string target_cluster;  // the cluster holding most target points, whatever its score
    double seconds = 0.0;
};

std::string percent(std::size_t a, std::size_t b) {
    return b ? fmt("%.0f %%", 100.0 * double(a) / double(b)) : std::string("n/a");
}

Row measure(const std::string& name, const core::PointCloud& cloud, detect::ClusterOptions o,
            detect::GroundSource ground, double threshold) {
    Row r;
    r.scene = name;
    r.ground = ground == detect::GroundSource::Ransac ? "ransac" : "labels";
    r.points = cloud.points.size();
    for (const core::CloudPoint& p : cloud.points) r.target_points += p.label == core::Role::Target;
    o.ground = ground;
    const double min_score = o.min_score;
    o.min_score = 0.0;  // every cluster, to find the one holding the target
    o.max_candidates = 1000000;
    detect::ClusterStats stats;
    const auto t0 = Clock::now();
    const std::vector<detect::Detection> found = detect::ClusterDetector(o).detect(cloud, stats);
    r.seconds = secondsSince(t0);
    r.clusters = stats.clusters;
    std::size_t most_target = 0;
    int rank = 0;  // among the candidates >= min_score
    for (std::size_t k = 0; k < found.size(); ++k) {
        const detect::Detection& d = found[k];
        std::size_t target = 0;
        for (const std::uint32_t i : d.points) target += cloud.points[i].label == core::Role::Target;
        if (target > most_target) {
            most_target = target;
            r.target_cluster = std::to_string(target) + " of " + std::to_string(d.points.size()) + " points, " +
                               fmt("%.1f", d.candidate.size_m.x) + " x " + fmt("%.1f", d.candidate.size_m.y) + " x " +
                               fmt("%.1f", d.candidate.size_m.z) + ", score " + fmt("%.2f", d.candidate.score);
        }
        if (d.candidate.score < min_score) continue;
        ++rank;
        const bool tp = 2 * target > d.points.size();
        const double limits[2] = {min_score, threshold};
        for (int t = 0; t < 2; ++t) {
            if (d.candidate.score < limits[t]) continue;
            ++r.candidates[t];
            if (tp) {
                ++r.true_positives[t];
                r.target_points_found[t] += target;
            }
        }
        if (tp && r.target_rank == 0) {
            r.target_rank = rank;
            r.target_score = d.candidate.score;
            r.target_box = fmt("%.1f", d.candidate.size_m.x) + " x " + fmt("%.1f", d.candidate.size_m.y) + " x " +
                           fmt("%.1f", d.candidate.size_m.z);
        }
    }
    return r;
}

std::string table(const std::vector<Row>& rows, double min_score, double threshold) {
    std::ostringstream s;
    const std::string a = fmt("%.2f", min_score), b = fmt("%.2f", threshold);
    s << "| scene | ground | points | target points | clusters | candidates >= " << a << " | precision >= " << a
      << " | target points found >= " << a << " | candidates >= " << b << " | precision >= " << b
      << " | target points found >= " << b << " | target's rank (score, box m) | target's cluster | detect s |\n"
      << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|\n";
    for (const Row& r : rows) {
        s << "| " << r.scene << " | " << r.ground << " | " << r.points << " | " << r.target_points << " | "
          << r.clusters;
        for (int t = 0; t < 2; ++t)
            s << " | " << r.candidates[t] << " | " << percent(r.true_positives[t], r.candidates[t]) << " | "
              << percent(r.target_points_found[t], r.target_points);
        s << " | "
          << (r.target_rank
                  ? std::to_string(r.target_rank) + " (" + fmt("%.2f", r.target_score) + ", " + r.target_box + ")"
                  : std::string("not found"))
          << " | " << (r.target_cluster.empty() ? std::string("none") : r.target_cluster) << " | "
          << fmt("%.2f", r.seconds) << " |\n";
    }
    return s.str();
}

void run(const BenchDetectCli& cli) {
    detect::validate(cli.detector);
    if (!(cli.threshold >= 0.0 && cli.threshold <= 1.0))
        throw core::Error("bench detect: --threshold = " + fmt("%g", cli.threshold) + ": allowed [0, 1]");
    const auto start = Clock::now();
    if (!cli.families.empty()) return runFamilies(cli, start);
    if (!cli.trained.clouds.empty()) {  // the per-cloud table only; BENCHMARKS.md stays
        if (cli.trained.model.empty()) throw core::Error("bench detect: --clouds needs --model");
        std::printf("%s", rankClouds(cli.trained).c_str());
        return;
    }
    if (cli.trained.quick) {  // a smoke run of the trained comparison only; BENCHMARKS.md stays
        std::printf("%s", runTrainedComparison(cli.trained).c_str());
        return;
    }
    const std::filesystem::path assets = sourceRoot() / "assets";
    std::vector<Row> rows;
    for (const char* name : {"demo", "hard", "hilly"}) {
        const core::Scene scene = io::loadScene(assets / name / "scene.json");
        std::fprintf(stderr, "bench detect: generating %s\n", name);
        const core::PointCloud cloud = sim::generateCloud(scene, sim::GenerateOptions{});
        for (const detect::GroundSource g : {detect::GroundSource::Ransac, detect::GroundSource::Labels}) {
            rows.push_back(measure(name, cloud, cli.detector, g, cli.threshold));
            std::fprintf(stderr, "bench detect: %s, %s ground: %.2f s\n", name, rows.back().ground.c_str(),
                         rows.back().seconds);
        }
    }
    std::size_t found = 0, tp = 0, candidates = 0;
    for (const Row& r : rows)
        if (r.ground == "ransac") {
            found += r.true_positives[0] > 0;
            tp += r.true_positives[0];
            candidates += r.candidates[0];
        }
    const double min_score = cli.detector.min_score;
    const std::string tbl = table(rows, min_score, cli.threshold);
    std::ostringstream summary;
    summary << "With RANSAC ground and the default min score " << fmt("%.2f", min_score) << ": targets found in "
            << found << " of 3 scenes, precision " << percent(tp, candidates) << " (" << tp << " of " << candidates
            << " candidates).\n";
    std::printf("%s\n%s", tbl.c_str(), summary.str().c_str());
    const std::string trained = runTrainedComparison(cli.trained);
    std::printf("\n%s", trained.c_str());
    if (cli.no_md) return;
    // The precision-recall plot, drawn from the curves this run wrote.
    std::string plot;
    if (!cli.trained.pr_csv.empty()) {
        const std::filesystem::path png = sourceRoot() / "docs" / "img" / "detect_pr.png";
        const std::string cmd = "python3 " + shellQuote((sourceRoot() / "scripts" / "plot_detect_pr.py").string()) +
                                " " + shellQuote(cli.trained.pr_csv.string()) + " " + shellQuote(png.string());
        const int status = std::system(cmd.c_str());
        std::fprintf(stderr, "bench detect: plot %s %s\n", png.c_str(), status == 0 ? "drawn" : "FAILED");
        if (status == 0)
            plot =
                "Precision-recall curves of both detectors on the evaluation clouds above (`python3 "
                "scripts/plot_detect_pr.py " +
                cli.trained.pr_csv.string() +
                " docs/img/detect_pr.png`):\n\n![precision-recall](docs/img/detect_pr.png)\n";
    }
    std::ostringstream s;
    s << "## Detector (ladarvr bench detect)\n\n"
      << "Command: `./ladarvr bench detect --voxel-m " << fmt("%g", cli.detector.voxel_m) << " --cluster-tolerance-m "
      << fmt("%g", cli.detector.cluster_tolerance_m) << " --ground-tile-m " << fmt("%g", cli.detector.ground_tile_m)
      << " --band-m " << fmt("%g", cli.detector.ground_ransac.band_m) << " --min-score "
      << fmt("%g", cli.detector.min_score) << " --threshold " << fmt("%g", cli.threshold)
      << "`; machine: " << std::thread::hardware_concurrency() << " cores, " << cpuName() << "; " << utcNow() << "; "
      << fmt("%.0f", secondsSince(start)) << " s in all.\n\n"
      << "The baseline detector of `ladarvr detect` (docs/detect.md) (target 7 x 3.5 x 2.5 m, voxel "
      << fmt("%g", cli.detector.voxel_m) << " m, cluster tolerance " << fmt("%g", cli.detector.cluster_tolerance_m)
      << " m) on each bundled scene's cloud (`ladarvr generate` defaults), "
         "scored against the cloud's ground-truth labels. Ground: `ransac` is what the detector does on any "
         "cloud; `labels` removes exactly the ground-labelled points (perfect ground removal, an upper bound "
         "for the clustering and scoring). A candidate is a true positive when most of its cluster's points are "
         "labelled target; precision = true positives / candidates; target points found = target points in "
         "true-positive clusters / all target points; the target's rank is that of the best true positive "
         "among all candidates the detector keeps, best first. Each scene holds one target.\n\n"
      << tbl << "\n"
      << summary.str() << "\n"
      << "### The trained detector against the baseline (clouds not seen in training)\n\n"
      << "bench/src/detect_trained.cpp: training on the corpora of assets/detect/train_*.json; evaluation on "
         "new corpora of the demo, hilly, hard, slopes and forest scenes (other seeds, the tank or a box truck not in "
         "training, each item seen by the ideal sensor or one of the presets; "
      << cli.trained.eval_items
      << " items per scene) and on the bundled scenes seen by the sensor presets; both detectors rank every "
         "segment or cluster, a true positive is a candidate most of whose points are labelled target.\n\n"
      << trained << "\n"
      << plot;
    replaceMarkdownSection(cli.md, "## Detector (ladarvr bench detect)", s.str());
    std::fprintf(stderr, "bench detect: wrote the section to %s\n", cli.md.c_str());
}

}  // namespace

void registerDetect(CLI::App& parent) {
    auto state = std::make_shared<BenchDetectCli>();
    CLI::App* c = parent.add_subcommand("detect",
                                        "baseline detector's precision and recall against the ground-truth "
                                        "labels of the bundled scenes");
    c->add_option("--threshold", state->threshold, "second score threshold reported, [0, 1]")->capture_default_str();
    c->add_option("--voxel-m", state->detector.voxel_m, "the detector's voxel side, m")->capture_default_str();
    c->add_option("--cluster-tolerance-m", state->detector.cluster_tolerance_m, "the detector's cluster tolerance, m")
        ->capture_default_str();
    c->add_option("--ground-tile-m", state->detector.ground_tile_m, "the detector's RANSAC tile side, m")
        ->capture_default_str();
    c->add_option("--band-m", state->detector.ground_ransac.band_m, "the detector's RANSAC height band per tile, m")
        ->capture_default_str();
    c->add_option("--min-score", state->detector.min_score, "the detector's min score (first threshold)")
        ->capture_default_str();
    c->add_option("--md", state->md, "markdown file whose detector section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print only, leave BENCHMARKS.md alone");
    c->add_flag("--quick", state->trained.quick,
                "smoke run: only the trained-against-baseline comparison on tiny corpora; BENCHMARKS.md stays");
    c->add_option("--families", state->families,
                  "only the leave-one-family-out run (scripts/make_vehicles.py's vehicle families, synthetic scenes "
                  "and real places, across densities): small (minutes on 2 cores), full, or test (seconds, for "
                  "the tests); its own section of the markdown file");
    c->add_option("--clouds", state->trained.clouds,
                  "only rank the target in these labelled clouds with --model and the baseline; BENCHMARKS.md stays");
    c->add_option("--model", state->trained.model, "the trained model --clouds uses");
    c->add_option("--explain", state->trained.explain,
                  "with --clouds: list each cloud's this many best candidates and the target's, [0, 1000]")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    c->add_option("--eval-items", state->trained.eval_items,
                  "evaluation items per scene (each seen by the ideal sensor or a preset), [1, 1000]")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c->add_option("--train-scale", state->trained.train_scale,
                  "training corpora of this many times the items of assets/detect/train_*.json (their seeds "
                  "unchanged), [1, 50]")
        ->check(CLI::Range(1, 50))
        ->capture_default_str();
    state->trained.pr_csv = "out/bench_detect_pr.csv";
    c->add_option("--pr-csv", state->trained.pr_csv,
                  "where the precision-recall curves of both detectors go (plot: scripts/plot_detect_pr.py)")
        ->capture_default_str();
    c->add_option("--tmp", state->trained.tmp, "scratch folder for the corpora (default: a new one, removed)");
    c->add_option("--threads", state->trained.threads, "threads of the trained detector and the generator")
        ->capture_default_str();
    c->add_option("--repeats", state->trained.repeats,
                  "detections of each evaluation cloud by each detector, timed by their median, [1, 20]")
        ->check(CLI::Range(1, 20))
        ->capture_default_str();
    c->callback([state] { run(*state); });
}

}  // namespace bench
