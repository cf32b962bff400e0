// app/src/cmd_view.cpp: `ladarvr view [CLOUD | --scene S]`, the immersive viewer (paper §IV-A).
//
// A COPC file (a LAZ whose first VLR is COPC's info record) is read node by node by
// viewer::CopcSource within --cache-mb (its hierarchy within --memory-mb); any other cloud file is streamed whole by the
// viewer's own loader thread, unless it is large: then it is indexed into COPC first (into
// the user's cache folder, view_index.hpp) and that index is read node by node. With no
// file (or --scene) the
// cloud is generated here, in memory, by sim::generateCloud on a worker thread and handed to
// the viewer through viewer::CloudFeed: the app links sim, the viewer never links Embree.
// Several files, or a folder of LAS/LAZ/COPC tiles, are viewed as one survey through one
// COPC index of them all (view_index.hpp). The ground under a cloud file whose points do
// not carry their height above ground is built in the background while the view runs
// (view_terrain.hpp), for the above-ground colours.
#include "cli_common.hpp"
#include "cloud_budget.hpp"
#include "commands.hpp"
#include "view_index.hpp"
#include "view_terrain.hpp"

#include <core/error.hpp>
#include <detect/cloud_units.hpp>
#include <io/candidates_file.hpp>
#include <io/cloud_info.hpp>
#include <io/copc.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>
#include <platform/cleanup.hpp>
#include <platform/input_set.hpp>
#include <platform/safe_file.hpp>
#include <sim/generator.hpp>
#include <sim/ground_units.hpp>
#include <sim/memory_budget.hpp>
#include <viewer/copc_source.hpp>
#include <viewer/open_point_source.hpp>
#include <viewer/viewer.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace app {

namespace fs = std::filesystem;

namespace {

// The most tiles a folder or a command line may give one survey.
constexpr std::size_t kMostSurveyFiles = 65536;

struct ViewArgs {
    std::vector<std::string> clouds;  // as given: files, or one folder of tiles
    std::vector<fs::path> survey;     // several files viewed as one (from clouds)
    std::string survey_folder;        // the folder they came from, if one
    std::string cloud, scene, script, screenshot, log_json, mirror = "both", colour = "file";
    std::string rasterizer = "auto";
    long frames = 0;
    double timeout_s = 0.0;
    bool no_xr = false, attenuate = false, no_edl = false;
    float point_size_px = 2.0f;
    int width = 1280, height = 720;
    std::size_t upload_budget = 1u << 18;
    std::size_t point_budget = 3000000;
    bool no_cull = false;
    double orbit_period_s = 60.0;
    double orbit_radius_m = 60.0, orbit_height_m = 40.0;
    bool orbit_given = false;  // --orbit-radius or --orbit-height: no fit to the cloud
    double pick_angle_deg = 0.5, cut_radius_m = 15.0;
    std::string candidates;
    bool no_snap_turn = false, no_vignette = false, no_headset_panel = false;
    double memory_mb = 0.0;
    double cache_mb = 512.0;
    ViewIndexOptions index;  // which path a cloud file that is not COPC takes
    bool cut = false;        // the cutting volume on from the start
    double gpu_mb = 2048.0, upload_mb = 0.0;
    std::string adaptive_budget;  // on, off; empty: on unless --frames
    std::string measure_budget;   // on, off; empty: on unless --frames, --script or --screenshot
    bool point_budget_given = false, upload_budget_given = false;
    sim::OrbitOptions orbit;  // only for the generated cloud
};

/// The index of a large cloud file that is not COPC, for viewer::openPointSource: made, or
/// found in the cache folder (view_index.hpp); a cached index that does not open is
/// written again, once.
class ViewIndexer final : public viewer::CloudIndexer {
  public:
    explicit ViewIndexer(const ViewIndexOptions& options) : options_(options) {}
    bool wantsIndex(const std::filesystem::path& cloud) override { return shouldIndex(cloud, options_); }
    std::filesystem::path index(const std::filesystem::path& cloud, const std::string& failed_open) override {
        if (failed_open.empty()) {
            last_ = indexForView(cloud, options_);
            return last_.copc;
        }
        if (last_.path != ViewPath::IndexReused) return {};
        warn("view: the cached index does not open (" + failed_open + "); indexing again");
        last_ = indexForView(cloud, options_, true);
        return last_.copc;
    }

  private:
    const ViewIndexOptions& options_;
    ViewCloud last_;
};

/// The viewer's options from the command line, checked (the cloud and its outputs are
/// checked by runView).
viewer::ViewerOptions viewerOptions(const ViewArgs& a) {
    viewer::ViewerOptions o;
    o.use_xr = !a.no_xr;
    o.mirror = viewer::parseMirrorEyes(a.mirror);
    o.style.colour = viewer::parseColourMode(a.colour);
    o.style.point_size_px = a.point_size_px;
    o.style.attenuate = a.attenuate;
    o.style.eye_dome = !a.no_edl;
    if (a.rasterizer != "auto" && a.rasterizer != "points" && a.rasterizer != "compute")
        throw core::Error("view: --rasterizer '" + a.rasterizer + "' is not one of auto, points, compute");
    o.rasterizer_auto = a.rasterizer == "auto";
    if (!o.rasterizer_auto) o.style.rasterizer = viewer::parseRasterizer(a.rasterizer);
    o.frames = a.frames;
    o.timeout_s = a.timeout_s;
    o.window_width = a.width;
    o.window_height = a.height;
    o.upload_points_per_frame = a.upload_budget;
    o.point_budget = a.point_budget;
    o.point_budget_auto = !a.point_budget_given;
    if (a.upload_budget_given && a.upload_mb > 0.0)
        throw core::Error("view: give --upload-budget (points) or --upload-mb (MiB) per frame, not both");
    if (!(a.gpu_mb >= 1.0 / 64.0 && a.gpu_mb <= 1048576.0))
        throw core::Error("view: --gpu-mb " + core::shownNumber(a.gpu_mb) + " is not in [1/64, 1048576]");
    if (!(a.upload_mb == 0.0 || (a.upload_mb >= 1.0 / 64.0 && a.upload_mb <= 65536.0)))
        throw core::Error("view: --upload-mb " + core::shownNumber(a.upload_mb) + " is not in [1/64, 65536]");
    o.gpu_bytes = static_cast<std::size_t>(a.gpu_mb * 1048576.0);
    o.upload_bytes_per_frame = static_cast<std::size_t>(a.upload_mb * 1048576.0);
    if (a.adaptive_budget != "" && a.adaptive_budget != "on" && a.adaptive_budget != "off")
        throw core::Error("view: --adaptive-budget '" + a.adaptive_budget + "' is not one of on, off");
    o.adaptive_budget = a.adaptive_budget.empty() ? a.frames == 0 : a.adaptive_budget == "on";
    if (a.measure_budget != "" && a.measure_budget != "on" && a.measure_budget != "off")
        throw core::Error("view: --measure-budget '" + a.measure_budget + "' is not one of on, off");
    // Measured by default only when a person is viewing: a scripted or counted run must draw
    // the same points every time.
    const bool person = a.frames == 0 && a.script.empty() && a.screenshot.empty();
    o.measure_budget = a.measure_budget.empty() ? person : a.measure_budget == "on";
    o.cull = !a.no_cull;
    o.modes.orbit_period_s = a.orbit_period_s;
    o.modes.orbit.radius_m = a.orbit_radius_m;
    o.modes.orbit.altitude_m = a.orbit_height_m;
    o.modes.fit_to_cloud = !a.orbit_given;
    o.pick.angle_deg = a.pick_angle_deg;
    o.cut_radius_m = a.cut_radius_m;
    o.cut_enabled = a.cut;
    o.snap_turn = !a.no_snap_turn;
    o.vignette = !a.no_vignette;
    o.headset_panel = !a.no_headset_panel;
    o.vsync = a.frames == 0;
    if (!a.script.empty()) o.script = viewer::readScript(a.script);
    o.screenshot = a.screenshot;
    o.log_json = a.log_json;
    viewer::validate(o);
    return o;
}

/// What is left of a --timeout that counts from `start` (0: none), at least a millisecond.
double timeLeft(double timeout_s, std::chrono::steady_clock::time_point start) {
    if (timeout_s <= 0.0) return timeout_s;
    return std::max(0.001, timeout_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// The command line's clouds into one cloud file (a.cloud) or a survey of several
// (a.survey): a folder gives its LAS/LAZ/COPC files, in name order.
void resolveClouds(ViewArgs& a) {
    const auto isFolder = [](const std::string& path) {
        std::error_code ec;
        return fs::is_directory(path, ec);
    };
    if (a.clouds.size() == 1 && !isFolder(a.clouds.front())) {
        a.cloud = a.clouds.front();
        return;
    }
    for (const std::string& given : a.clouds) {
        if (!isFolder(given)) {
            a.survey.emplace_back(given);
            continue;
        }
        if (a.clouds.size() > 1)
            throw core::Error("view: '" + core::printable(given, 400) +
                              "' is a folder; allowed: one folder of tiles alone, or cloud files");
        a.survey_folder = given;
        std::vector<fs::path> tiles = lasFilesIn(given, "view", kMostSurveyFiles);
        if (tiles.empty())
            throw core::Error("view: cloud '" + core::printable(given, 400) +
                              "': is a directory; allowed: a regular file, or a folder of .las/.laz tiles (this one "
                              "holds none)");
        a.survey = std::move(tiles);
    }
    if (a.survey.size() > kMostSurveyFiles)
        throw core::Error("view: " + std::to_string(a.survey.size()) + " cloud files; allowed at most " +
                          std::to_string(kMostSurveyFiles));
    if (a.survey.size() == 1) {  // a folder of one tile
        a.cloud = a.survey.front().string();
        a.survey.clear();
    }
}

// The panel's units line and the pick panel's symbols, from the cloud's CRS.
void setUnits(viewer::ViewerOptions& o, const io::LasCrs& crs) {
    o.units = sim::describeUnits(crs);
    const sim::UnitSymbols symbols = sim::unitSymbols(crs);
    o.length_unit = symbols.horizontal;
    o.height_unit = symbols.vertical;
    try {
        o.height_unit_m = sim::coordinateUnits(crs, {}, "view").vertical_m;
    } catch (const core::Error&) {
        o.height_unit_m = 1.0;  // an angle or an unknown length: the reader names it below
    }
}

// The --candidates file's candidates over `cloud` (empty: a generated cloud, in metres),
// their sizes turned into the cloud's units; refused when their centres are in other units.
void setCandidates(viewer::ViewerOptions& o, const ViewArgs& a, const std::string& cloud) {
    if (a.candidates.empty()) return;
    io::CandidateUnits file_units;
    std::vector<core::Candidate> read = io::readCandidates(a.candidates, &file_units);
    const sim::CoordinateUnits units = cloud.empty() ? sim::CoordinateUnits{} : sim::readCoordinateUnits(cloud, "view");
    o.candidates = detect::sizesInCloudUnits(std::move(read), file_units, units,
                                             "view: --candidates " + core::printable(a.candidates, 400));
}

// A file's CRS and units in words, for the refusal of unlike files.
std::string crsWords(const io::LasCrs& crs) {
    if (crs.source.empty()) return "no CRS";
    std::string s = crs.name.empty() ? std::string("unnamed CRS") : "'" + crs.name + "'";
    if (crs.epsg != 0) s += " EPSG:" + std::to_string(crs.epsg);
    if (const std::string units = sim::describeUnits(crs); !units.empty()) s += ", " + units;
    return s;
}

// Throws Error("view: <file>: its CRS (...) differs from <first>'s (...); ...") unless
// every file of the survey declares the same CRS and units.
void checkSurveyCrs(const std::vector<fs::path>& files) {
    const std::string first = crsWords(io::readCloudCrs(files.front(), "view"));
    for (const fs::path& file : files) {
        const std::string crs = crsWords(io::readCloudCrs(file, "view"));
        if (crs != first)
            throw core::Error("view: " + core::printable(file.string(), 400) + ": its CRS (" + crs + ") differs from " +
                              core::printable(files.front().string(), 400) + "'s (" + first +
                              "); files viewed as one survey must share their CRS and units");
    }
}

// The ground under `cloud` for `--colour above-ground`, built from `read` (the file the
// viewer reads: the cloud itself or its index) on a thread of its own, unless the cloud's
// points carry their height above ground. Only when the view starts in that mode: the
// sample read and the fit take a core for a few seconds, which a view in another mode
// should not pay. A cloud whose units cannot take lengths in metres gets the feed's
// failure at once. Null when no terrain is built.
std::unique_ptr<TerrainProducer> startTerrain(viewer::ViewerOptions& o, const fs::path& cloud, const fs::path& read,
                                              const std::string& what) {
    if (o.style.colour != viewer::ColourMode::AboveGround) return nullptr;
    StartedTerrain t = startCloudTerrain(cloud, read, what, "view");
    o.terrain = std::move(t.feed);
    return std::move(t.producer);
}

// Several cloud files viewed as one survey: checked as inputs, alike in CRS and units,
// indexed together (or their cached index found) and read node by node.
int runSurvey(const ViewArgs& a, std::chrono::steady_clock::time_point start) {
    std::vector<platform::RunPath> paths;
    platform::InputSet inputs;
    if (!a.survey_folder.empty())
        paths.push_back({"cloud folder", a.survey_folder, platform::PathRole::InputFolder,
                         [](const std::string& name) { return isLasName(name); }});
    for (const fs::path& file : a.survey) {
        paths.push_back({"cloud", file, platform::PathRole::Input, {}});
        inputs.addFile(file);
    }
    for (const auto& [option, path] :
         {std::pair<const char*, const std::string*>{"--script", &a.script}, {"--candidates", &a.candidates}})
        paths.push_back({option, *path, platform::PathRole::Input, {}});
    paths.push_back({"--screenshot", a.screenshot, platform::PathRole::Output, {}});
    paths.push_back({"--log-json", a.log_json, platform::PathRole::Output, {}});
    paths.push_back({"--index-to", a.index.index_to, platform::PathRole::Output, {}});
    platform::checkDistinctPaths("view", paths);
    viewer::ViewerOptions o = viewerOptions(a);
    if (!(a.cache_mb >= 1.0 / 64.0 && a.cache_mb <= 1048576.0))
        throw core::Error("view: --cache-mb " + std::to_string(a.cache_mb) + " is not in [1/64, 1048576]");
    validate(a.index);
    if (a.index.in_core)
        throw core::Error(
            "view: --in-core applies to one cloud file; allowed: several files viewed through their index");
    for (const fs::path& file : a.survey)
        platform::checkInputFile(file, "view: cloud '" + core::printable(file.string(), 400) + "'");
    checkSurveyCrs(a.survey);
    setUnits(o, io::readCloudCrs(a.survey.front(), "view"));
    setCandidates(o, a, a.survey.front().string());
    prepareOutputFile(o.screenshot, "view: --screenshot");
    prepareOutputFile(o.log_json, "view: --log-json");
    for (const std::string& out : {o.screenshot.string(), o.log_json.string(), a.index.index_to})
        if (!out.empty()) inputs.checkNotAnInput(out);
    viewer::OpenSourceOptions open;
    open.copc.cache_bytes = static_cast<std::size_t>(a.cache_mb * 1048576.0);
    open.copc.hierarchy_bytes = sim::memoryBudgetBytes(a.memory_mb, "view");
    ViewCloud index = indexSurveyForView(a.survey, a.index);
    viewer::OpenedCloud opened;
    try {
        opened = viewer::openPointSource(index.copc, viewer::SourcePath::Copc, open);
    } catch (const core::Error& e) {
        if (index.path != ViewPath::IndexReused) throw;
        warn(std::string("view: the cached index does not open (") + e.what() + "); indexing again");
        index = indexSurveyForView(a.survey, a.index, true);
        opened = viewer::openPointSource(index.copc, viewer::SourcePath::Copc, open);
    }
    viewer::CopcSource& source = *opened.copc;
    std::fprintf(stderr,
                 "ladarvr: view: %s is COPC: %zu nodes, %zu points, read node by node within a %.6g MB cache "
                 "(the survey of %zu files)\n",
                 core::printable(opened.file.string(), 400).c_str(), source.nodeCount(), source.totalPoints(),
                 a.cache_mb, a.survey.size());
    const std::unique_ptr<TerrainProducer> terrain = startTerrain(o, a.survey.front(), opened.file, "the survey's");
    o.timeout_s = timeLeft(o.timeout_s, start);
    return viewer::runViewer(o, source);
}

int runView(const ViewArgs& a) {
    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<platform::Watchdog> watchdog = viewerWatchdog("view", a.timeout_s);
    const bool from_file = !a.cloud.empty() || !a.survey.empty();
    if (from_file && !a.scene.empty()) throw core::Error("view: give a cloud file or --scene, not both");
    const sim::OrbitOptions paper;
    if (from_file && (a.orbit.xres != paper.xres || a.orbit.yres != paper.yres || a.orbit.views != paper.views))
        throw core::Error("view: --xres/--yres/--views apply to a generated cloud, not to a cloud file");
    if (!a.survey.empty()) return runSurvey(a, start);
    platform::checkDistinctPaths("view", {{"cloud", a.cloud, platform::PathRole::Input, {}},
                                          {"--scene", a.scene, platform::PathRole::Input, {}},
                                          {"--script", a.script, platform::PathRole::Input, {}},
                                          {"--candidates", a.candidates, platform::PathRole::Input, {}},
                                          {"--screenshot", a.screenshot, platform::PathRole::Output, {}},
                                          {"--log-json", a.log_json, platform::PathRole::Output, {}},
                                          {"--index-to", a.index.index_to, platform::PathRole::Output, {}}});
    viewer::ViewerOptions o = viewerOptions(a);
    if (!(a.cache_mb >= 1.0 / 64.0 && a.cache_mb <= 1048576.0))
        throw core::Error("view: --cache-mb " + std::to_string(a.cache_mb) + " is not in [1/64, 1048576]");
    validate(a.index);
    // The cloud first: a regular file (checkDistinctPaths keeps the outputs off it).
    if (!a.cloud.empty()) platform::checkInputFile(a.cloud, "view: cloud '" + core::printable(a.cloud, 400) + "'");
    // The panel's units line, from the cloud's CRS (a file that does not read says so below).
    if (!a.cloud.empty()) {
        try {
            setUnits(o, io::readCloudCrs(a.cloud, "view"));
        } catch (const core::Error&) {
            o.units.clear();  // not shown: the reader names what is wrong with the file below
        }
    }
    setCandidates(o, a, a.cloud);
    ViewIndexer indexer(a.index);
    viewer::OpenSourceOptions open;
    open.copc.cache_bytes = static_cast<std::size_t>(a.cache_mb * 1048576.0);
    open.indexer = &indexer;
    const viewer::SourcePath path = a.cloud.empty() ? viewer::SourcePath::Whole : viewer::choosePath(a.cloud, &indexer);
    if (!a.index.index_to.empty() && (a.cloud.empty() || path == viewer::SourcePath::Copc))
        throw core::Error("view: --index-to applies to a cloud file that is not COPC");
    // A large cloud that is not COPC is indexed (or its cached index found) first, once the
    // outputs are checked, so a bad name does not wait for the indexing.
    if (path != viewer::SourcePath::Whole) {
        prepareOutputFile(o.screenshot, "view: --screenshot");
        prepareOutputFile(o.log_json, "view: --log-json");
        // --memory-mb bounds the hierarchy (its tree and the pages being read); the points
        // held are --cache-mb's.
        open.copc.hierarchy_bytes = sim::memoryBudgetBytes(a.memory_mb, "view");
        const viewer::OpenedCloud opened = viewer::openPointSource(a.cloud, path, open);
        viewer::CopcSource& source = *opened.copc;
        const std::size_t pages = source.stats() ? source.stats()->pages_unread : 0;
        std::fprintf(stderr,
                     "ladarvr: view: %s is COPC: %zu nodes, %zu points, read node by node within a %.6g MB cache "
                     "(nodes of the root hierarchy page; %zu child pages read as the view reaches them)\n",
                     core::printable(opened.file.string(), 400).c_str(), source.nodeCount(), source.totalPoints(),
                     a.cache_mb, pages);
        const std::unique_ptr<TerrainProducer> terrain = startTerrain(o, a.cloud, opened.file, "the file's");
        o.timeout_s = timeLeft(o.timeout_s, start);
        return viewer::runViewer(o, source);
    }
    if (!a.cloud.empty()) {
        platform::checkInputFile(a.cloud, "view: cloud '" + core::printable(a.cloud, 400) + "'");
        // Held whole: the points as read, their GPU chunks and the pick index over them.
        try {
            refuseCloudsOverBudget("view", a.memory_mb, {a.cloud}, kInCoreBytesPerPoint, "the cloud file held whole");
        } catch (const core::Error& e) {
            const std::string what = e.what();
            // The header's own errors read as the loader's do ("view: pcd: <file>: ...").
            throw core::Error(what.rfind("view: ", 0) == 0 ? what : "view: " + what);
        }
    }
    prepareOutputFile(o.screenshot, "view: --screenshot");
    prepareOutputFile(o.log_json, "view: --log-json");

    viewer::OpenedCloud opened;
    std::thread generator;
    std::unique_ptr<TerrainProducer> terrain;
    if (!a.cloud.empty()) {
        std::fprintf(stderr, "ladarvr: view: %s is not COPC: streamed and held whole\n",
                     core::printable(a.cloud, 400).c_str());
        opened = viewer::openPointSource(a.cloud, path, open);
        terrain = startTerrain(o, a.cloud, a.cloud, "the file's");
    } else {
        opened.feed = std::make_unique<viewer::CloudFeed>();
        // LOD order of each chunk on the generator thread, not in the frame loop.
        opened.feed->enableLodOrder();
        // Load (and validate) the scene now, so a bad scene fails before a window opens.
        const std::filesystem::path scene_path = a.scene.empty() ? io::demoScenePath() : std::filesystem::path(a.scene);
        auto scene = std::make_shared<core::Scene>(io::loadScene(scene_path));
        std::fprintf(stderr, "ladarvr: view: generating the cloud of %s\n", scene_path.string().c_str());
        sim::GenerateOptions check;
        check.orbit = a.orbit;
        sim::validate(check);
        generator = std::thread([&feed = *opened.feed, scene, orbit = a.orbit] {
            try {
                sim::GenerateOptions g;
                g.orbit = orbit;
                feed.feedCloud(sim::generateCloud(*scene, g));
            } catch (const std::exception& e) {
                feed.finish(std::string("generate: ") + e.what());
            }
        });
    }
    // --timeout counts from the start of the command: the loop gets what start-up left.
    o.timeout_s = timeLeft(o.timeout_s, start);
    int status = 1;
    try {
        status = viewer::runViewer(o, *opened.feed);
    } catch (...) {
        if (generator.joinable()) generator.join();
        throw;
    }
    if (generator.joinable()) generator.join();
    return status;
}
}  // namespace

void registerView(CLI::App& cli) {
    auto args = std::make_shared<ViewArgs>();
    CLI::App* cmd = cli.add_subcommand("view",
                                       "view a cloud in an OpenXR HMD with a desktop mirror, or on the desktop "
                                       "(space: automatic orbit <-> free mode; see docs/viewer.md)");
    cmd->add_option("cloud", args->clouds,
                    "PCD, PLY, LAS, LAZ or COPC cloud; several LAS/LAZ files, or a folder of them, are viewed as one "
                    "survey through one index (default: generate the bundled demo scene)");
    cmd->add_option("--scene", args->scene, "generate this scene's cloud and view it");
    addCloudMemoryOption(*cmd, args->memory_mb, "a cloud file");
    cmd->add_option("--cache-mb", args->cache_mb,
                    "COPC files: MiB of decoded nodes held in RAM at most (least recently wanted dropped first)")
        ->capture_default_str();
    cmd->add_flag("--no-xr", args->no_xr, "desktop mode only, do not look for an OpenXR runtime");
    cmd->add_option("--mirror", args->mirror, "eyes shown in the desktop mirror: left, right, both")
        ->capture_default_str();
    cmd->add_option("--colour", args->colour,
                    "point colours: file, height (jet), white, label (ground truth: "
                    "target red), above-ground (jet by height above the terrain: the cloud's own heights, else "
                    "its class 2 or a terrain fitted in the background), class (ASPRS palette), intensity, "
                    "return (number)")
        ->capture_default_str();
    cmd->add_option("--point-size", args->point_size_px, "point size in pixels [1, 64] (at 100 m with --attenuate)")
        ->capture_default_str();
    cmd->add_flag("--attenuate", args->attenuate, "point size falls off with distance");
    cmd->add_flag("--no-edl", args->no_edl, "turn eye-dome lighting off");
    cmd->add_option("--rasterizer", args->rasterizer,
                    "how points are drawn: points (GL_POINTS), compute (two compute passes) or auto (compute on "
                    "discrete GPUs, points elsewhere)")
        ->capture_default_str();
    cmd->add_option("--frames", args->frames, "stop after N frames (with OpenXR: submitted frames); 0 = until closed")
        ->capture_default_str();
    cmd->add_option("--timeout", args->timeout_s,
                    "give up this many seconds after the start (start-up included), exit 1 (0 = never)")
        ->capture_default_str();
    cmd->add_option("--script", args->script,
                    "operator actions at frames: lines '<frame> space|escape|designate|confirm|reject|no_target|next', "
                    "'<frame> aim X Y Z', '<frame> grab_scale S' (docs/viewer.md)");
    cmd->add_option("--screenshot", args->screenshot, "write the mirror as PNG at the last frame");
    cmd->add_option("--log-json", args->log_json, "write a machine-readable run log (states, frames, poses, modes)");
    cmd->add_option("--width", args->width, "window width, pixels")->capture_default_str();
    cmd->add_option("--height", args->height, "window height, pixels")->capture_default_str();
    CLI::Option* upload_budget =
        cmd->add_option("--upload-budget", args->upload_budget, "points uploaded to the GPU per frame at most")
            ->capture_default_str();
    cmd->add_option("--upload-mb", args->upload_mb,
                    "MiB uploaded to the GPU per frame at most (instead of --upload-budget)");
    CLI::Option* point_budget =
        cmd->add_option("--point-budget", args->point_budget,
                        "points drawn per eye and frame at most (level of detail by screen size; 0 = unlimited; "
                        "default: by the GPU class, 3000000 on a software rasterizer)");
    cmd->add_option("--gpu-mb", args->gpu_mb,
                    "MiB of point buffers on the GPU at most (nodes not wanted now leave first)")
        ->capture_default_str();
    cmd->add_option("--adaptive-budget", args->adaptive_budget,
                    "on, off: lower the point budget while frames run late (default: on, off with --frames)");
    cmd->add_option("--measure-budget", args->measure_budget,
                    "on, off: choose the default point budget and rasterizer from the first frames' times, "
                    "remembered per GPU in the cache folder (default: on, off with --frames, --script or "
                    "--screenshot)");
    cmd->add_flag("--no-cull", args->no_cull, "draw cells outside the view frustum too (for comparisons)");
    cmd->add_option("--orbit-period", args->orbit_period_s, "seconds per turn of the automatic orbit")
        ->capture_default_str();
    const auto fixed_orbit = [args](const std::string&) { args->orbit_given = true; };
    cmd->add_option("--orbit-radius", args->orbit_radius_m,
                    "automatic orbit radius, metres (default: fitted to a cloud file's extent)")
        ->each(fixed_orbit)
        ->capture_default_str();
    cmd->add_option("--orbit-height", args->orbit_height_m,
                    "automatic orbit height above the cloud's centre, metres (default: fitted with the radius)")
        ->each(fixed_orbit)
        ->capture_default_str();
    cmd->add_option("--pick-angle", args->pick_angle_deg, "the pointer's angular radius, degrees (0, 10]")
        ->capture_default_str();
    cmd->add_option("--cut-radius", args->cut_radius_m, "cutting volume radius when switched on (V), metres")
        ->capture_default_str();
    cmd->add_option("--candidates", args->candidates,
                    "candidate detections (JSON, as `ladarvr detect` writes) to "
                    "confirm or reject");
    cmd->add_flag("--no-snap-turn", args->no_snap_turn, "headset, free mode: turn smoothly instead of 45 deg steps");
    cmd->add_flag("--no-vignette", args->no_vignette, "headset, free mode: no tunnel vignette while moving");
    cmd->add_flag("--no-headset-panel", args->no_headset_panel, "do not show the ImGui panel in the headset");
    cmd->add_option("--xres", args->orbit.xres, "generated cloud only: sensor pixels across")->capture_default_str();
    cmd->add_option("--yres", args->orbit.yres, "generated cloud only: sensor pixels down")->capture_default_str();
    cmd->add_option("--views", args->orbit.views, "generated cloud only: drone positions (NoV)")->capture_default_str();
    cmd->add_option("--index-above-mb", args->index.index_above_mb,
                    "a cloud file that is not COPC and would hold more than this many MiB in core (84 bytes a point, "
                    "from its header) is indexed into COPC first, into the cache folder, and read node by node")
        ->capture_default_str();
    cmd->add_option("--index-cache-mb", args->index.index_cache_mb,
                    "bound on the index cache folder ($XDG_CACHE_HOME/ladarvr, else ~/.cache/ladarvr), MiB; the "
                    "least recently used indexes are removed past it")
        ->capture_default_str();
    cmd->add_flag("--in-core", args->index.in_core,
                  "stream a cloud file that is not COPC and hold it whole, whatever its size (within --memory-mb)");
    cmd->add_option("--index-to", args->index.index_to,
                    "index the cloud file into this FILE.copc.laz (not the cache folder) and view that");
    cmd->add_flag("--cut", args->cut,
                  "the cutting volume on from the start: once a point is designated, only points within "
                  "--cut-radius of it are drawn (V toggles it)");
    cmd->callback([args, upload_budget, point_budget] {
        args->upload_budget_given = upload_budget->count() > 0;
        args->point_budget_given = point_budget->count() > 0;
        args->index.memory_mb = args->memory_mb;
        resolveClouds(*args);
        const int status = runView(*args);
        if (status != 0) throw CLI::RuntimeError(status);
    });
}

}  // namespace app
