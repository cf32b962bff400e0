// app/src/cmd_study.cpp: `ladarvr study PLAN.json --out DIR`, a target-search study in the
// viewer (docs/study.md): the plan's trials one after another, each on a ready
// screen then in automatic mode, the operator designating and deciding; trials.csv,
// candidates.csv and a trace per trial written as the trials end.
#include "cli_common.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <io/scene_file.hpp>
#include <io/strict_json.hpp>
#include <metric/clouds.hpp>
#include <metric/visibility.hpp>
#include <platform/atomic_file.hpp>
#include <platform/cleanup.hpp>
#include <platform/safe_file.hpp>
#include <sim/generator.hpp>
#include <study/plan.hpp>
#include <study/study_log.hpp>
#include <study/study_source.hpp>
#include <viewer/viewer.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

namespace app {

namespace {
struct StudyArgs {
    std::string plan, out, script, log_json, mirror = "both", colour = "file";
    std::string replay, screenshot;
    int trial = 1;
    long frames = 0;
    double timeout_s = 0.0;
    bool no_xr = false, no_metric = false;
    int width = 1280, height = 720;
    double pick_angle_deg = 0.5;
    double hit_radius_m = -1.0;                       // < 0: the plan's
    double orbit_radius_m = -1.0, orbit_height_m = std::nan(""), orbit_period_s = -1.0;   // unset: the plan's
};

// The window and mirror settings both runs share.
viewer::ViewerOptions windowOptions(const StudyArgs& a) {
    viewer::ViewerOptions o;
    o.mirror = viewer::parseMirrorEyes(a.mirror);
    o.style.colour = viewer::parseColourMode(a.colour);
    o.frames = a.frames;
    o.timeout_s = a.timeout_s;
    o.window_width = a.width;
    o.window_height = a.height;
    o.log_json = a.log_json;
    return o;
}

/// Refuses an --out folder that already holds a study, so one run never mixes its rows
/// with another's; creates it otherwise.
void prepareOut(const std::filesystem::path& out) {
    createParentFolders(out / "trials.csv", "study: --out");
    std::error_code ec;
    if (!std::filesystem::is_directory(out, ec))
        throw core::Error("study: --out " + out.string() + ": not a folder");
    for (const auto& entry : std::filesystem::directory_iterator(out, ec)) {
        const std::string name = entry.path().filename().string();
        if (name == "trials.csv" || name == "candidates.csv" || name == "study.json" ||
            (name.starts_with("trace_") && name.ends_with(".csv")))
            throw core::Error("study: --out " + out.string() + ": already holds a study (" + name +
                                "); allowed: a new or empty folder");
    }
}

/// `--replay DIR --trial N`: trial N's trace in the mirror, over its cloud (from the plan
/// that DIR/study.json names).
int runReplay(const StudyArgs& a) {
    const std::filesystem::path dir(a.replay);
    const std::string shown = core::printable((dir / "study.json").string(), 400);
    const nlohmann::json study = io::parseStrictJson(
        platform::readTextFile(dir / "study.json", std::size_t(1) << 20, "study: --replay " + shown + ":"),
        "study: --replay " + shown);
    if (!study.is_object() || !study.contains("plan") || !study["plan"].is_string() || !study.contains("order") ||
        !study["order"].is_array())
        throw core::Error("study: --replay " + shown + ": not a study's record (needs 'plan' and 'order')");
    const study::Plan plan = study::readPlan(study["plan"].get<std::string>());
    std::vector<int> order;
    for (const auto& v : study["order"]) {
        if (!v.is_number_unsigned() || v.get<std::size_t>() >= plan.trials.size())
            throw core::Error("study: --replay " + shown + ": 'order' does not match the plan's trials");
        order.push_back(v.get<int>());
    }
    if (a.trial < 1 || a.trial > static_cast<int>(order.size()))
        throw core::Error("study: --trial " + std::to_string(a.trial) + ": allowed 1.." + std::to_string(order.size()));
    viewer::ViewerOptions o = windowOptions(a);
    o.use_xr = false;
    o.replay = study::readTrace(dir / ("trace_" + std::to_string(a.trial) + ".csv"));
    if (o.replay.empty()) throw core::Error("study: --replay: trace_" + std::to_string(a.trial) + ".csv has no frame");
    o.screenshot = a.screenshot;
    viewer::validate(o);
    prepareOutputFile(o.log_json, "study: --log-json");
    prepareOutputFile(o.screenshot, "study: --screenshot");
    study::StudySource source(plan, order);
    viewer::CloudFeed feed;
    feed.enableLodOrder();
    source.begin(a.trial - 1, feed);
    int status = 1;
    try {
        status = viewer::runViewer(o, feed);
    } catch (...) {
        source.end(a.trial - 1);
        throw;
    }
    source.end(a.trial - 1);
    return status;
}

int runStudy(const StudyArgs& a) {
    if (!a.replay.empty() && !a.plan.empty()) throw core::Error("study: give PLAN.json or --replay DIR, not both");
    if (!a.replay.empty()) return runReplay(a);
    if (a.plan.empty()) throw core::Error("study: give PLAN.json (or --replay DIR)");
    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<platform::Watchdog> watchdog = viewerWatchdog("study", a.timeout_s);
    if (a.out.empty()) throw core::Error("study: --out DIR is required (the folder for trials.csv and the traces)");
    study::Plan plan = study::readPlan(a.plan);
    if (a.hit_radius_m >= 0.0) plan.hit_radius_m = a.hit_radius_m;
    if (!(plan.hit_radius_m > 0.0)) throw core::Error("study: --hit-radius must be > 0 m");

    viewer::ViewerOptions o = windowOptions(a);
    o.use_xr = !a.no_xr;
    o.vsync = a.frames == 0;
    o.pick.angle_deg = a.pick_angle_deg;
    o.modes.orbit.radius_m = a.orbit_radius_m > 0.0 ? a.orbit_radius_m : plan.orbit_radius_m;
    o.modes.orbit.altitude_m = std::isnan(a.orbit_height_m) ? plan.orbit_height_m : a.orbit_height_m;
    o.modes.orbit_period_s = a.orbit_period_s > 0.0 ? a.orbit_period_s : plan.orbit_period_s;
    if (!a.script.empty()) o.script = viewer::readScript(a.script);
    viewer::validate(o);
    const std::filesystem::path out(a.out);
    prepareOut(out);
    prepareOutputFile(o.log_json, "study: --log-json");

    const std::vector<int> order = study::trialOrder(plan);
    auto source = std::make_unique<study::StudySource>(plan, order);
    // What --replay needs to find a trial's cloud again: the plan and the order run.
    platform::writeFileAtomic(out / "study.json",
                            nlohmann::json{{"plan", std::filesystem::absolute(a.plan).string()}, {"order", order}}.dump(2) + "\n");

    // The paper's visibility metric of each scene, before the window opens (it renders
    // with its own EGL context); once per scene however many trials name it.
    std::map<std::filesystem::path, double> metrics;
    if (!a.no_metric) {
        for (const study::PlanTrial& t : plan.trials) {
            if (t.scene.empty() || metrics.count(t.scene)) continue;
            std::fprintf(stderr, "ladarvr: study: visibility metric of %s\n", t.scene.string().c_str());
            const core::Scene scene = io::loadScene(t.scene);
            sim::GenerateOptions g;
            g.orbit.xres = plan.xres;
            g.orbit.yres = plan.yres;
            g.orbit.views = plan.views;
            const metric::MetricClouds clouds = metric::generateClouds(scene, g);
            metric::MetricOptions m;
            m.orbit.radius_m = o.modes.orbit.radius_m;
            m.orbit.altitude_m = o.modes.orbit.altitude_m;
            metric::Evaluator evaluator(clouds, &scene);
            metrics[t.scene] = evaluator.run(m).metric_mean;
        }
    }
    study::StudyLog log(
        out,
        [&](int trial) {
            const study::PlanTrial& t = source->planTrial(trial);
            study::TrialInfo info;
            info.source = t.source;
            if (const auto it = metrics.find(t.scene); !t.scene.empty() && it != metrics.end() && std::isfinite(it->second))
                info.visibility_metric = it->second;
            return info;
        },
        plan.hit_radius_m);
    if (o.timeout_s > 0.0)
        o.timeout_s = std::max(0.001, o.timeout_s - std::chrono::duration<double>(
                                                       std::chrono::steady_clock::now() - start).count());
    int status = viewer::runTrials(o, *source, log);
    if (!log.error().empty()) {
        std::fprintf(stderr, "ladarvr: study: %s\n", log.error().c_str());
        if (status == 0) status = 1;
    }
    std::fprintf(stderr, "ladarvr: study: %zu of %zu trials written to %s\n", log.trialsWritten(), plan.trials.size(),
                 (out / "trials.csv").string().c_str());
    return status;
}
}  // namespace

void registerStudy(CLI::App& cli) {
    auto args = std::make_shared<StudyArgs>();
    CLI::App* cmd = cli.add_subcommand(
        "study", "run a target-search study: the plan's trials in the viewer, logged to --out "
                 "(see docs/study.md)");
    cmd->add_option("plan", args->plan, "PLAN.json: the trials (clouds or scenes, candidates, time limits)");
    cmd->add_option("--replay", args->replay, "replay a study's trace in the mirror: the --out folder of a study");
    cmd->add_option("--trial", args->trial, "with --replay: the trial (1 = the first run)")->capture_default_str();
    cmd->add_option("--screenshot", args->screenshot, "with --replay: write the mirror as PNG at the last frame");
    cmd->add_option("--out", args->out, "folder for trials.csv, candidates.csv and trace_<N>.csv (new or empty)");
    cmd->add_flag("--no-xr", args->no_xr, "desktop mode only, do not look for an OpenXR runtime");
    cmd->add_option("--mirror", args->mirror, "eyes shown in the desktop mirror: left, right, both")->capture_default_str();
    cmd->add_option("--colour", args->colour, "point colours: file, height, white, label")->capture_default_str();
    cmd->add_option("--frames", args->frames, "stop after N frames of the whole run (0 = until the trials end)")
        ->capture_default_str();
    cmd->add_option("--timeout", args->timeout_s, "give up this many seconds after the start, exit 1 (0 = never)")
        ->capture_default_str();
    cmd->add_option("--script", args->script,
                    "operator actions at frames of the run: '<frame> next|designate|confirm|reject|no_target|space|"
                    "escape', '<frame> aim X Y Z', '<frame> grab_scale S'");
    cmd->add_option("--log-json", args->log_json, "write the viewer's run log (states, frames, actions)");
    cmd->add_option("--width", args->width, "window width, pixels")->capture_default_str();
    cmd->add_option("--height", args->height, "window height, pixels")->capture_default_str();
    cmd->add_option("--pick-angle", args->pick_angle_deg, "the pointer's angular radius, degrees (0, 10]")
        ->capture_default_str();
    cmd->add_option("--hit-radius", args->hit_radius_m, "a designation this close to a target point is a hit, metres "
                                                        "(default: the plan's, else 1)");
    cmd->add_option("--orbit-radius", args->orbit_radius_m, "automatic orbit radius, metres (default: the plan's, else 60)");
    cmd->add_option("--orbit-height", args->orbit_height_m, "automatic orbit height above the centre, metres "
                                                            "(default: the plan's, else 40)");
    cmd->add_option("--orbit-period", args->orbit_period_s, "seconds per turn of the automatic orbit "
                                                            "(default: the plan's, else 60)");
    cmd->add_flag("--no-metric", args->no_metric, "leave visibility_metric empty (skip the metric of scene trials)");
    cmd->callback([args] {
        const int status = runStudy(*args);
        if (status != 0) throw CLI::RuntimeError(status);
    });
}

}  // namespace app
