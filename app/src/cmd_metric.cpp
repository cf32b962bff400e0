// app/src/cmd_metric.cpp: `ladarvr metric`: the visibility metric of paper §IV-B.
// Parses and validates options (metric::validate names the option and the range), makes
// or reads the three clouds, runs the evaluator, writes DIR/views.csv, summary.json, PNGs.
#include "cli_common.hpp"
#include "cloud_budget.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/scene_file.hpp>
#include <io/trace_file.hpp>
#include <metric/clouds.hpp>
#include <metric/report.hpp>
#include <metric/trace.hpp>
#include <metric/visibility.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>
#include <study/study_folder.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

namespace app {
namespace {

struct MetricCli {
    std::string scene;
    std::string out = "out/metric";
    std::string look_at;
    std::string p1, p2, p3;
    bool json = false;
    bool no_skip = false;
    bool no_exact = false;
    std::string rasterizer = "compute";
    std::string trace;
    double trace_step_s = 0.1;
    double memory_mb = 0.0;
    metric::MetricOptions options;
};

std::string percent(double v) {
    if (std::isnan(v)) return "n/a";
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1f %%", 100.0 * v);
    return buffer;
}

// Along a trace: the target's visibility from where the operator looked. Views whose
// |I1| = 0 (target out of view) count as 0 in the whole-trace figure.
void printTraceSummary(const MetricCli& cli, const metric::MetricResult& r, std::size_t samples) {
    double visible_sum = 0.0;
    for (const metric::ViewResult& v : r.views)
        if (v.used) visible_sum += v.visible;
    const double whole = r.views.empty() ? 0.0 : visible_sum / double(r.views.size());
    std::printf(
        "metric: trace %s: %zu of %zu samples used (every %.3g s); target in view in %d; visible %s "
        "while in view, %s over the whole trace\n",
        cli.trace.c_str(), r.views.size(), samples, cli.trace_step_s, r.views_used, percent(r.visible_mean).c_str(),
        percent(whole).c_str());
}

// The scene a --trace was recorded on, into cli.scene: a trace_<N>.csv beside a study's
// study.json is trial N of that study, whose plan names its scene. A trace whose scene
// is not known needs --scene (or the three clouds): the demo scene is never assumed for
// it. Returns the line that says where the scene came from (empty when --scene gave it).
std::string resolveTraceScene(MetricCli& cli, bool from_files) {
    const std::string trace = "--trace " + core::printable(cli.trace, 400);
    const std::optional<study::RecordedTrial> recorded = study::recordedTraceTrial(cli.trace, "metric: --trace");
    if (!recorded) {
        if (cli.scene.empty() && !from_files)
            throw core::Error("metric: " + trace +
                              ": the scene it was recorded on is not known (no study.json beside a trace_<N>.csv); "
                              "give --scene (the trial's scene file) or --p1, --p2, --p3");
        return {};
    }
    const std::string trial = "trial " + std::to_string(recorded->number) + " of " +
                              core::printable((recorded->folder / "study.json").string(), 400);
    const std::filesystem::path& recorded_scene = recorded->trial.scene;
    if (recorded_scene.empty()) {  // a cloud file's trial: its scene, if any, is the researcher's to name
        if (cli.scene.empty() && !from_files)
            throw core::Error("metric: " + trace + " is " + trial + ", which ran on the cloud file " +
                              core::printable(recorded->trial.cloud.string(), 400) +
                              ", not a scene; give --scene (the scene that cloud was generated from) or --p1, --p2, "
                              "--p3");
        return {};
    }
    if (from_files) return {};  // the three clouds stand for the scene; nothing to compare them with
    if (cli.scene.empty()) {
        cli.scene = recorded_scene.string();
        return "metric: " + trace + " is " + trial + ", recorded on the scene " +
               core::printable(recorded_scene.string(), 400);
    }
    std::error_code ec;
    const bool same = std::filesystem::equivalent(cli.scene, recorded_scene, ec);
    if (!same)
        throw core::Error("metric: --scene " + core::printable(cli.scene, 400) + ": " + trace + " is " + trial +
                          ", recorded on the scene " + core::printable(recorded_scene.string(), 400) +
                          "; allowed: that scene, or no --scene");
    return {};
}

void run(MetricCli& cli) {
    metric::MetricOptions& o = cli.options;
    o.skip = !cli.no_skip;
    o.exact = !cli.no_exact;
    if (cli.rasterizer == "compute")
        o.rasterizer = metric::Rasterizer::Compute;
    else if (cli.rasterizer == "raster")
        o.rasterizer = metric::Rasterizer::Raster;
    else
        throw core::Error("metric: --rasterizer '" + cli.rasterizer + "': allowed compute, raster");
    if (!cli.look_at.empty()) o.look_at_world = parseWorldTriple(cli.look_at, "metric: --look-at");
    const bool from_files = !cli.p1.empty() || !cli.p2.empty() || !cli.p3.empty();
    std::string scene_line;
    if (!cli.trace.empty()) {
        if (!(std::isfinite(cli.trace_step_s) && cli.trace_step_s >= 0.0 && cli.trace_step_s <= 3600.0))
            throw core::Error("metric: --trace-step-s = " + std::to_string(cli.trace_step_s) +
                              ": allowed [0, 3600] seconds");
        platform::checkInputFile(cli.trace, "metric: --trace " + core::printable(cli.trace, 400));
        scene_line = resolveTraceScene(cli, from_files);
    }
    const std::filesystem::path out = cli.out;
    // Before anything is made: no input inside the folder this run replaces.
    platform::checkDistinctPaths("metric", {{"--out", out, platform::PathRole::OutputFolder, {}},
                                            {"--scene", cli.scene, platform::PathRole::Input, {}},
                                            {"--p1", cli.p1, platform::PathRole::Input, {}},
                                            {"--p2", cli.p2, platform::PathRole::Input, {}},
                                            {"--p3", cli.p3, platform::PathRole::Input, {}},
                                            {"--trace", cli.trace, platform::PathRole::Input, {}}});
    std::size_t trace_samples = 0;
    if (!cli.trace.empty()) {
        // Streamed: only the kept poses are held, at most as many as the metric evaluates.
        o.poses_world = metric::tracePoses(cli.trace, cli.trace_step_s, metric::kMaxPoses, trace_samples);
    }
    if (from_files && (cli.p1.empty() || cli.p2.empty() || cli.p3.empty()))
        throw core::Error("metric: --p1, --p2 and --p3 go together: give all three clouds");
    if (from_files && !cli.scene.empty()) throw core::Error("metric: --scene and --p1/--p2/--p3 exclude each other");
    metric::validate(o);

    // Fail on the destination before the (long) generation; the folder itself is made
    // (or replaced as a whole) by writeReport.
    createParentFolders(out, "metric: --out");
    metric::checkReportFolder(out);

    metric::MetricClouds clouds;
    std::optional<core::Scene> scene;
    if (from_files) {
        // Each cloud is held as read and again in the scene's frame (40 bytes a point each),
        // then uploaded for the GPU splats and the rasterizer (20 bytes a point each).
        refuseCloudsOverBudget("metric", cli.memory_mb, {cli.p1, cli.p2, cli.p3}, 2 * 40 + 2 * 20,
                               "--p1, --p2 and --p3 read whole");
        clouds.p1 = io::readCloud(cli.p1);
        clouds.p2 = io::readCloud(cli.p2);
        clouds.p3 = io::readCloud(cli.p3);
        if (clouds.p1.points.empty())
            throw core::Error("metric: --p1 " + cli.p1 + ": the cloud is empty; P1 must hold the target's points");
    } else {
        const std::filesystem::path path = cli.scene.empty() ? io::demoScenePath() : std::filesystem::path(cli.scene);
        scene = io::loadScene(path);
        if (!cli.json && !scene_line.empty()) std::fprintf(stderr, "%s\n", scene_line.c_str());
        if (!cli.json) std::fprintf(stderr, "metric: generating P1, P2, P3 from %s\n", path.string().c_str());
        clouds = metric::generateClouds(*scene);
    }
    metric::Evaluator evaluator(clouds, scene ? &*scene : nullptr);
    const metric::MetricResult result = evaluator.run(o);
    metric::writeReport(result, out);
    if (cli.json) {
        std::fputs(metric::summaryJson(result).c_str(), stdout);
    } else if (!cli.trace.empty()) {
        printTraceSummary(cli, result, trace_samples);
        std::printf("metric: %s mean over the samples with the target in view; %.2f s; wrote %s\n",
                    percent(result.metric_mean).c_str(), result.seconds, out.string().c_str());
    } else {
        std::printf(
            "metric: %s mean (min %s, max %s) over %d of %zu views; visible %s; depth-aware %s; exact %s; "
            "%.2f s; wrote %s\n",
            percent(result.metric_mean).c_str(), percent(result.metric_min).c_str(), percent(result.metric_max).c_str(),
            result.views_used, result.views.size(), percent(result.visible_mean).c_str(),
            percent(result.depth_visible_mean).c_str(),
            result.has_exact ? percent(result.exact_mean).c_str() : "absent", result.seconds, out.string().c_str());
        if (result.views_used < static_cast<int>(result.views.size()))
            std::printf("metric: %zu views had |I1| = 0 (target out of frame) and are left out; see views.csv\n",
                        result.views.size() - static_cast<std::size_t>(result.views_used));
    }
}

}  // namespace

void registerMetric(CLI::App& cli) {
    auto state = std::make_shared<MetricCli>();
    state->options.picture_view = 0;
    CLI::App* c = cli.add_subcommand("metric",
                                     "visibility metric of the target (paper §IV-B): mean over an "
                                     "orbit of |I2 xor I3| / |I1|, with an exact mesh reference");
    metric::MetricOptions& o = state->options;
    c->add_option("--scene", state->scene,
                  "scene file (default: the bundled demo scene; with --trace, the trial's scene as its study "
                  "folder records it)");
    addCloudMemoryOption(*c, state->memory_mb, "the clouds of --p1, --p2 and --p3");
    c->add_option("--out", state->out, "output directory for views.csv, summary.json, PNGs")->capture_default_str();
    c->add_option("--p1", state->p1, "existing target-only cloud (PCD/PLY); with --p2 --p3, no exact reference");
    c->add_option("--p2", state->p2, "existing environment-without-ground cloud");
    c->add_option("--p3", state->p3, "existing target+environment-without-ground cloud");
    c->add_option("--views", o.orbit.views, "views on the orbit, 1..65535")->capture_default_str();
    c->add_option("--radius-m", o.orbit.radius_m, "orbit radius around the look-at point, metres > 0")
        ->capture_default_str();
    c->add_option("--altitude-m", o.orbit.altitude_m, "eye height above the look-at point, metres")
        ->capture_default_str();
    c->add_option("--look-at", state->look_at, "x,y,z world metres (default: centre of the target's bounds)");
    c->add_option("--vfov-deg", o.orbit.vfov_deg, "vertical field of view, (0, 170] degrees")->capture_default_str();
    c->add_option("--width", o.width, "image width, 16..8192 pixels")->capture_default_str();
    c->add_option("--height", o.height, "image height, 16..8192 pixels")->capture_default_str();
    c->add_option("--splat-px", o.splat_px, "square point splat side, [1, 64] pixels")->capture_default_str();
    c->add_option("--picture-view", o.picture_view, "view whose I1..I4 are written as PNG, -1 for none")
        ->capture_default_str();
    c->add_option("--rasterizer", state->rasterizer, "how splats are drawn: compute (default) or raster (GL_POINTS)")
        ->capture_default_str();
    c->add_option("--depth-margin-m", o.depth_margin_m,
                  "depth-aware variant: P3 point nearer than every P2 point of its pixel by this, [0, 100] m")
        ->capture_default_str();
    CLI::Option* trace = c->add_option(
        "--trace", state->trace,
        "a study's trace_<trial>.csv: the views are the operator's head poses instead of the orbit (docs/study.md)");
    c->add_option("--trace-step-s", state->trace_step_s,
                  "with --trace, use samples at least this far apart, [0, 3600] s (0: every sample)")
        ->capture_default_str()
        ->needs(trace);  // alone it would change nothing: refused rather than ignored
    for (const char* orbit_only : {"--views", "--radius-m", "--altitude-m", "--look-at"})
        trace->excludes(c->get_option(orbit_only));
    c->add_flag("--json", state->json, "print summary.json to stdout");
    c->add_flag("--no-skip", state->no_skip,
                "render whole images and every view (the paper's literal xor over the full frame)");
    c->add_flag("--no-exact", state->no_exact, "skip the exact ray-cast reference");
    c->callback([state] { run(*state); });
}

}  // namespace app
