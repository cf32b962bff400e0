// app/src/cmd_study.cpp: `ladarvr study PLAN.json --out DIR` and `ladarvr study --replay
// DIR --trial N` (docs/study.md): the options, parsed into study::StudyOptions and the
// viewer's options; the run itself is study/study_run.hpp. Cloud trials in above-ground
// colours get their ground from view's terrain producer (view_terrain.hpp).
#include "cli_common.hpp"
#include "cloud_budget.hpp"
#include "commands.hpp"
#include "view_terrain.hpp"

#include <core/error.hpp>
#include <platform/cleanup.hpp>
#include <platform/safe_file.hpp>
#include <study/design.hpp>
#include <study/study_folder.hpp>
#include <study/study_run.hpp>
#include <viewer/viewer.hpp>

#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace app {

namespace {
struct StudyArgs {
    std::string plan, participant, out, script, log_json, mirror = "both", colour = "file";
    std::string replay, screenshot;
    int trial = 1;
    long frames = 0;
    double timeout_s = 0.0;
    bool no_xr = false, no_metric = false;
    double memory_mb = 0.0;
    int width = 1280, height = 720;
    double pick_angle_deg = 0.5;
    bool cut = false;            // the cutting volume on from each trial's start
    double cut_radius_m = 15.0;  // its radius
    double hit_radius_m = -1.0;  // < 0: the plan's
    double orbit_radius_m = -1.0, orbit_height_m = std::nan(""), orbit_period_s = -1.0;  // unset: the plan's
};

// The names a study writes into --out (and --replay reads there).
bool studyFile(const std::string& name) { return study::isStudyFile(name); }

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

// The folders of `out` that do not exist yet, deepest first: what createParentFolders
// will make for it.
std::vector<std::filesystem::path> missingFolders(std::filesystem::path out) {
    std::vector<std::filesystem::path> missing;
    if (!out.has_filename()) out = out.parent_path();  // "a/b/" is the folder a/b
    for (std::filesystem::path p = out; !p.empty(); p = p.parent_path()) {
        struct stat st{};
        if (::lstat(p.c_str(), &st) == 0) break;
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    return missing;
}

// Removes the folders a run made (missingFolders(), deepest first) while they are empty:
// rmdir takes an empty folder only, so whatever anyone put there stays.
void removeEmptyFolders(const std::vector<std::filesystem::path>& made) {
    for (const std::filesystem::path& p : made)
        if (::rmdir(p.c_str()) != 0) return;
}

// A trial's terrain, built as `view` builds a cloud's (view_terrain.hpp): a failure to
// start is the feed's, said by the viewer like any other.
struct TrialTerrainJob final : study::TerrainJob {
    std::unique_ptr<TerrainProducer> producer;
};

study::CloudTerrain startTrialTerrain(const std::filesystem::path& cloud) {
    study::CloudTerrain out;
    try {
        StartedTerrain t = startCloudTerrain(cloud, cloud, "the file's", "study");
        out.feed = std::move(t.feed);
        if (t.producer) {
            auto job = std::make_unique<TrialTerrainJob>();
            job->producer = std::move(t.producer);
            out.job = std::move(job);
        }
    } catch (const std::exception& e) {
        if (!out.feed) out.feed = std::make_shared<viewer::TerrainFeed>();
        out.feed->fail(e.what());
    }
    return out;
}

/// `--replay DIR --trial N`: trial N's trace in the mirror, over its cloud.
int runReplay(const StudyArgs& a) {
    platform::checkDistinctPaths("study", {{"--replay", a.replay, platform::PathRole::InputFolder, studyFile},
                                           {"--log-json", a.log_json, platform::PathRole::Output, {}},
                                           {"--screenshot", a.screenshot, platform::PathRole::Output, {}}});
    viewer::ViewerOptions o = windowOptions(a);
    o.screenshot = a.screenshot;
    study::Replay replay(a.replay, a.trial, o);
    replay.setTerrain(startTrialTerrain);
    prepareOutputFile(replay.viewerOptions().log_json, "study: --log-json");
    prepareOutputFile(replay.viewerOptions().screenshot, "study: --screenshot");
    return replay.run();
}

int runStudy(const StudyArgs& a) {
    if (!a.replay.empty() && !a.plan.empty()) throw core::Error("study: give PLAN.json or --replay DIR, not both");
    if (!a.replay.empty()) return runReplay(a);
    if (a.plan.empty()) throw core::Error("study: give PLAN.json (or --replay DIR)");
    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<platform::Watchdog> watchdog = viewerWatchdog("study", a.timeout_s);
    if (a.out.empty()) throw core::Error("study: --out DIR is required (the folder for trials.csv and the traces)");
    platform::checkDistinctPaths("study", {{"plan", a.plan, platform::PathRole::Input, {}},
                                           {"--script", a.script, platform::PathRole::Input, {}},
                                           {"--out", a.out, platform::PathRole::OutputFolder, studyFile},
                                           {"--log-json", a.log_json, platform::PathRole::Output, {}},
                                           {"--screenshot", a.screenshot, platform::PathRole::Output, {}}});

    study::StudyOptions s;
    // A design (a top-level "conditions" key) runs one participant's session; a plan its trials.
    // Text that does not parse is reported as such, whatever --participant says.
    const std::string shown = core::printable(a.plan, 400);
    const bool design =
        study::isDesignText(platform::readTextFile(a.plan, study::kMaxDesignBytes, "study: " + shown + ":"), shown);
    if (design && a.participant.empty())
        throw core::Error("study: " + core::printable(a.plan, 400) +
                          " is a design (it has 'conditions'): give --participant ID, one of its participants");
    if (!design && !a.participant.empty())
        throw core::Error("study: --participant is for a design (a file with 'conditions'); " +
                          core::printable(a.plan, 400) + " is a plan");
    (design ? s.design : s.plan) = a.plan;
    s.participant = a.participant;
    s.out = a.out;
    s.script = a.script;
    s.viewer = windowOptions(a);
    s.viewer.use_xr = !a.no_xr;
    s.viewer.vsync = a.frames == 0;
    s.viewer.pick.angle_deg = a.pick_angle_deg;
    s.viewer.cut_enabled = a.cut;
    s.viewer.cut_radius_m = a.cut_radius_m;
    if (a.hit_radius_m >= 0.0) s.hit_radius_m = a.hit_radius_m;
    if (a.orbit_radius_m > 0.0) s.orbit_radius_m = a.orbit_radius_m;
    if (!std::isnan(a.orbit_height_m)) s.orbit_height_m = a.orbit_height_m;
    if (a.orbit_period_s > 0.0) s.orbit_period_s = a.orbit_period_s;
    s.metric = !a.no_metric;
    s.terrain = startTrialTerrain;
    study::StudyRun run(std::move(s));
    // A trial's cloud file is held whole while it runs, as view holds it (one at a time).
    for (std::size_t k = 0; k < run.plan().trials.size(); ++k)
        if (const std::filesystem::path& cloud = run.plan().trials[k].cloud; !cloud.empty())
            refuseCloudsOverBudget("study", a.memory_mb, {cloud}, 40 + 20 + 24,
                                   "trial " + std::to_string(k + 1) + "'s cloud held whole");
    // A run that ends before its first trial starts leaves --out as it found it: StudyRun
    // removes its study.json, and the folders made here go while they are empty.
    const std::vector<std::filesystem::path> made = missingFolders(a.out);
    int status = 1;
    try {
        createParentFolders(std::filesystem::path(a.out) / "trials.csv", "study: --out");
        run.checkFolder();
        prepareOutputFile(run.viewerOptions().log_json, "study: --log-json");
        status = run.run(start);
    } catch (...) {
        removeEmptyFolders(made);
        throw;
    }
    removeEmptyFolders(made);
    return status;
}
}  // namespace

void registerStudy(CLI::App& cli) {
    auto args = std::make_shared<StudyArgs>();
    CLI::App* cmd = cli.add_subcommand("study",
                                       "run a target-search study: the plan's trials in the viewer, logged to --out "
                                       "(see docs/study.md)");
    cmd->add_option("plan", args->plan,
                    "PLAN.json: the trials (clouds or scenes, candidates, time limits); or DESIGN.json: "
                    "conditions, blocks and participants (a top-level 'conditions' key)");
    cmd->add_option("--participant", args->participant,
                    "with a design: the participant whose session runs (resumed when --out holds it)");
    CLI::Option* replay =
        cmd->add_option("--replay", args->replay, "replay a study's trace in the mirror: the --out folder of a study");
    // Alone they would change nothing: refused rather than ignored.
    cmd->add_option("--trial", args->trial, "with --replay: the trial (1 = the first run)")
        ->capture_default_str()
        ->needs(replay);
    cmd->add_option("--screenshot", args->screenshot, "with --replay: write the mirror as PNG at the last frame")
        ->needs(replay);
    cmd->add_option("--out", args->out,
                    "folder for trials.csv, candidates.csv and trace_<N>.csv (new or empty; or, with a design, "
                    "the participant's stopped session to resume)");
    cmd->add_flag("--no-xr", args->no_xr, "desktop mode only, do not look for an OpenXR runtime");
    cmd->add_option("--mirror", args->mirror, "eyes shown in the desktop mirror: left, right, both")
        ->capture_default_str();
    cmd->add_option("--colour", args->colour,
                    "point colours: file, height, white, label, above-ground, class, intensity, return")
        ->capture_default_str();
    cmd->add_option("--frames", args->frames, "stop after N frames of the whole run (0 = until the trials end)")
        ->capture_default_str();
    cmd->add_option("--timeout", args->timeout_s, "give up this many seconds after the start, exit 1 (0 = never)")
        ->capture_default_str();
    cmd->add_option(
        "--script", args->script,
        "operator actions at frames of the run: '<frame> next|designate|confirm|reject|no_target|space|"
        "escape', '<frame> aim X Y Z', '<frame> grab_scale S', '<frame> answer N|TEXT' (a questionnaire item), "
        "'<frame> point_answer N' (the same, clicked on the headset panel)");
    cmd->add_option("--log-json", args->log_json, "write the viewer's run log (states, frames, actions)");
    cmd->add_option("--width", args->width, "window width, pixels")->capture_default_str();
    cmd->add_option("--height", args->height, "window height, pixels")->capture_default_str();
    cmd->add_option("--pick-angle", args->pick_angle_deg, "the pointer's angular radius, degrees (0, 10]")
        ->capture_default_str();
    cmd->add_flag("--cut", args->cut,
                  "the cutting volume on from each trial's start: once a point is designated, only points within "
                  "--cut-radius of it are drawn (a condition's 'cut' overrides it)");
    cmd->add_option("--cut-radius", args->cut_radius_m,
                    "the cutting volume's radius, metres [0.1, 10000] (a condition's 'cut_radius_m' overrides it)")
        ->capture_default_str();
    cmd->add_option("--hit-radius", args->hit_radius_m,
                    "a designation this close to a target point is a hit, metres "
                    "(default: the plan's, else 1)");
    cmd->add_option("--orbit-radius", args->orbit_radius_m,
                    "automatic orbit radius, metres (default: the plan's, else 60)");
    cmd->add_option("--orbit-height", args->orbit_height_m,
                    "automatic orbit height above the centre, metres "
                    "(default: the plan's, else 40)");
    cmd->add_option("--orbit-period", args->orbit_period_s,
                    "seconds per turn of the automatic orbit "
                    "(default: the plan's, else 60)");
    addCloudMemoryOption(*cmd, args->memory_mb, "a trial's cloud file");
    cmd->add_flag("--no-metric", args->no_metric, "leave visibility_metric empty (skip the metric of scene trials)");
    // `study report ...` is its own subcommand; this callback runs after it, with nothing to do.
    CLI::App* report = registerStudyReport(*cmd);
    cmd->callback([args, report] {
        if (report->parsed()) return;
        const int status = runStudy(*args);
        if (status != 0) throw CLI::RuntimeError(status);
    });
}

}  // namespace app
