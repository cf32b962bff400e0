// bench/src/view.cpp: `ladarvr bench view`: frame times of the viewer (CPU submit, GPU
// through GL timer queries, whole frame) for the paper's cloud (1,638,400 points: the demo
// scene generated with the paper's parameters) and a 20 M point cloud (the same cloud
// replicated with seeded jitter), in the mirror, XR and offscreen stereo paths.
#include "common.hpp"
#include "register.hpp"
#include "view_measure.hpp"
#include "view_ooc.hpp"
#include "view_pick.hpp"

#include <core/error.hpp>
#include <io/scene_file.hpp>
#include <sim/generator.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <ctime>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace bench {

namespace {
struct BenchViewArgs {
    std::vector<std::size_t> points = {1638400, 20000000};
    int frames = 10, warmup = 3;
    std::string paths = "mirror,xr,egl,skip,pick";
    std::string eye = "1440x1600";
    std::string display = "auto";
    std::size_t point_budget = 3000000;
    std::vector<std::string> rasterizers = {"points"};
    OocBenchOptions ooc;  // --paths ooc
    std::string subgroup = "on";
    bool no_md = false;
};

/// Without a display, reruns this benchmark under tests/viewer/headless_env.sh (a private
/// Xvfb and Monado's simulated HMD), so the mirror and XR paths are measured too.
/// Returns false when it did not (a display exists, --display none, or no script).
bool rerunHeadless(const BenchViewArgs& a) {
    if (a.display != "auto" || std::getenv("DISPLAY")) return false;
    const std::filesystem::path script = sourceRoot() / "tests" / "viewer" / "headless_env.sh";
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec || !std::filesystem::exists(script)) return false;
    std::string ooc_args;
    if (a.paths.find("ooc") != std::string::npos) {
        std::string sizes;
        for (std::size_t n : a.ooc.points) sizes += (sizes.empty() ? "" : ",") + std::to_string(n);
        ooc_args = " --ooc-points " + sizes + " --head-paths " + shellQuote(a.ooc.head_paths) + " --cache-mb " +
                   std::to_string(a.ooc.cache_mb) + " --gpu-mb " + std::to_string(a.ooc.gpu_mb) + " --in-core-max " +
                   std::to_string(a.ooc.in_core_max_points) +
                   (a.ooc.dir.empty() ? std::string() : " --ooc-dir " + shellQuote(a.ooc.dir)) +
                   (a.ooc.synthetic ? " --ooc-synthetic" : "") + " --subgroup " + a.subgroup +
                   (a.no_md ? " --no-md" : "");
    }
    std::string points, rasterizers;
    for (std::size_t n : a.points) points += (points.empty() ? "" : ",") + std::to_string(n);
    for (const std::string& r : a.rasterizers) rasterizers += (rasterizers.empty() ? "" : ",") + r;
    const std::string command = shellQuote(script.string()) + " --monado-stay --timeout 3000 -- " +
                                shellQuote(exe.string()) + " view --display none --points " + points + " --frames " +
                                std::to_string(a.frames) + " --warmup " + std::to_string(a.warmup) + " --paths " +
                                shellQuote(a.paths) + " --eye " + shellQuote(a.eye) + " --point-budget " +
                                std::to_string(a.point_budget) + " --rasterizer " + shellQuote(rasterizers) + ooc_args;
    std::fprintf(stderr, "bench view: no DISPLAY: running under %s (Xvfb + Monado)\n", script.c_str());
    std::fflush(stdout);
    const int status = std::system(command.c_str());
    if (status != 0) throw core::Error("bench view: the headless run failed (" + command + ")");
    return true;
}

/// `base` replicated (with seeded jitter of up to 0.2 m) until it holds `n` points.
core::PointCloud grow(const core::PointCloud& base, std::size_t n) {
    core::PointCloud out;
    out.origin = base.origin;
    out.fields = base.fields;
    out.points.reserve(n);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
    for (std::size_t i = 0; out.points.size() < n; ++i) {
        core::CloudPoint p = base.points[i % base.points.size()];
        if (i >= base.points.size()) p.position += glm::vec3(jitter(rng), jitter(rng), jitter(rng) * 0.25f);
        out.points.push_back(p);
    }
    return out;
}

void run(const BenchViewArgs& a) {
    if (a.display != "auto" && a.display != "none")
        throw core::Error("bench view: --display '" + a.display + "' is not one of auto, none");
    ViewBenchOptions o;
    o.frames = a.frames;
    o.warmup_frames = a.warmup;
    o.mirror = a.paths.find("mirror") != std::string::npos;
    o.xr = a.paths.find("xr") != std::string::npos;
    o.egl = a.paths.find("egl") != std::string::npos;
    o.skip = a.paths.find("skip") != std::string::npos;
    o.tools = a.paths.find("tools") != std::string::npos;
    o.point_budget = a.point_budget;
    const bool pick = a.paths.find("pick") != std::string::npos;
    // "skip" and "pick" alone need no display: EGL only, or no GL at all.
    const bool display_needed = o.mirror || o.xr || o.tools;
    if (std::sscanf(a.eye.c_str(), "%dx%d", &o.eye_width, &o.eye_height) != 2)
        throw core::Error("bench view: --eye '" + a.eye + "': expected WIDTHxHEIGHT, e.g. 1440x1600");
    o.rasterizers.clear();
    for (const std::string& r : a.rasterizers) o.rasterizers.push_back(viewer::parseRasterizer(r));
    if (display_needed && rerunHeadless(a)) return;
    if (a.paths.find("ooc") != std::string::npos) {
        OocBenchOptions ooc = a.ooc;
        ooc.point_budget = a.point_budget;
        ooc.eye_width = o.eye_width;
        ooc.eye_height = o.eye_height;
        ooc.md = a.no_md ? "" : "BENCHMARKS.md";
        if (a.rasterizers.size() != 1)
            throw core::Error("bench view: --paths ooc measures one rasterizer: give --rasterizer points or compute");
        ooc.rasterizer = a.rasterizers.front();
        ooc.subgroup = a.subgroup == "on";
        runOocBench(ooc, stdout);
        if (!(o.mirror || o.xr || o.egl || o.skip || o.tools || a.paths.find("pick") != std::string::npos)) return;
    }

    std::fprintf(stderr, "bench view: generating the demo cloud (paper parameters)\n");
    const core::Scene scene = io::loadScene(io::demoScenePath());
    const core::PointCloud demo = sim::generateCloud(scene, sim::GenerateOptions{});

    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
    std::printf("ladarvr bench view (%s): warm-up %d, median of %d frames; eye-dome lighting on\n", date, a.warmup,
                a.frames);
    if (o.mirror || o.xr || o.egl || o.tools) {
        std::printf(
            "| path | points | size | CPU submit ms | GPU ms | frame ms | frames | baseline GPU ms | "
            "ratio | note |\n");
        std::printf("|---|---:|---|---:|---:|---:|---:|---:|---:|---|\n");
    }
    std::string gl;
    std::vector<ViewBenchResult> skip_rows;
    for (std::size_t n : a.points) {
        if (!(o.mirror || o.xr || o.egl || o.skip || o.tools)) break;
        const core::PointCloud cloud = n == demo.points.size() ? demo : grow(demo, n);
        for (const auto& r : measureViewer(cloud, o)) {
            if (!r.gl.empty()) gl = r.gl;
            if (r.path == "skip-egl") {
                skip_rows.push_back(r);
                continue;
            }
            if (r.frames == 0) {
                std::printf("| %s | %zu | - | - | - | - | 0 | - | - | %s |\n", r.path.c_str(), r.points,
                            r.note.c_str());
            } else {
                char baseline[64] = "-", ratio[32] = "-";
                if (r.baseline_gpu_ms_median > 0) {
                    std::snprintf(baseline, sizeof baseline, "%.2f", r.baseline_gpu_ms_median);
                    std::snprintf(ratio, sizeof ratio, "%.2fx", r.gpu_ms_median / r.baseline_gpu_ms_median);
                }
                std::printf("| %s | %zu | %dx%d | %.2f | %.2f | %.2f | %d | %s | %s | %s |\n", r.path.c_str(), r.points,
                            r.width, r.height, r.cpu_ms_median, r.gpu_ms_median, r.frame_ms_median, r.frames, baseline,
                            ratio, r.note.c_str());
            }
            std::fflush(stdout);
        }
    }
    if (!skip_rows.empty()) {
        std::printf(
            "\nSkip what a frame does not need (offscreen stereo, both eyes; 'nothing skipped' is the "
            "in-run baseline of each view):\n");
        std::printf(
            "| points | size | configuration | points drawn (2 eyes) | CPU submit ms | GPU ms | frame ms | "
            "frames | frame ratio |\n");
        std::printf("|---:|---|---|---:|---:|---:|---:|---:|---:|\n");
        double base = 0.0;
        for (const auto& r : skip_rows) {
            if (r.note.find("nothing skipped") != std::string::npos) base = r.frame_ms_median;
            if (r.frames == 0) {
                std::printf("| %zu | - | %s | - | - | - | - | 0 | - |\n", r.points, r.note.c_str());
                continue;
            }
            std::printf("| %zu | %dx%d | %s | %zu | %.2f | %.2f | %.2f | %d | %.2fx |\n", r.points, r.width, r.height,
                        r.note.c_str(), r.points_drawn, r.cpu_ms_median, r.gpu_ms_median, r.frame_ms_median, r.frames,
                        base > 0 ? r.frame_ms_median / base : 0.0);
        }
        // Each configuration's compute row against its points row (same cloud, same run).
        const std::string points_tag = ", points", compute_tag = ", compute";
        for (const auto& c : skip_rows) {
            if (c.frames == 0 || !c.note.ends_with(compute_tag)) continue;
            const std::string name = c.note.substr(0, c.note.size() - compute_tag.size());
            for (const auto& p : skip_rows)
                if (p.points == c.points && p.frames > 0 && p.note == name + points_tag && p.gpu_ms_median > 0)
                    std::printf("- %zu points, %s: compute / points GPU ms %.2fx, frame ms %.2fx\n", c.points,
                                name.c_str(), c.gpu_ms_median / p.gpu_ms_median,
                                p.frame_ms_median > 0 ? c.frame_ms_median / p.frame_ms_median : 0.0);
        }
    }
    if (pick) {
        std::printf(
            "\nThe pointer's pick (nearest point within 0.5 deg of a ray from the automatic orbit's eye to a "
            "random point of the cloud; k-d tree, viewer/pick_index.hpp) against a scan of every point:\n");
        printPickingHeader(stdout);
        for (std::size_t n : a.points) measurePicking(n == demo.points.size() ? demo : grow(demo, n), 1000, stdout);
    }
    if (o.mirror || o.xr || o.egl || o.skip || o.tools) std::printf("GL: %s\n", gl.c_str());
    if (o.egl)
        std::printf(
            "baseline: render::PointSplatRenderer (the metric's 2 px splats, no eye-dome lighting) drawing the "
            "same two eyes, interleaved frame by frame; ratio = viewer GPU ms / baseline GPU ms\n");
}
}  // namespace

void registerView(CLI::App& parent) {
    auto args = std::make_shared<BenchViewArgs>();
    CLI::App* cmd = parent.add_subcommand("view",
                                          "viewer frame times (CPU, GPU timer queries) for 1.6 M and 20 M "
                                          "points in the mirror, XR and offscreen stereo paths");
    cmd->add_option("--points", args->points, "cloud sizes to measure (comma separated)")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--frames", args->frames, "measured frames per configuration")->capture_default_str();
    cmd->add_option("--warmup", args->warmup, "warm-up frames (after the upload)")->capture_default_str();
    cmd->add_option("--paths", args->paths,
                    "any of mirror, xr, egl, skip, pick, tools, ooc (comma separated; skip: culling and LOD budget "
                    "before/after, offscreen stereo; pick: the pointer's pick time; tools: the XR frame with and "
                    "without the pointer, cutting volume and headset panel; ooc: COPC files viewed out of core "
                    "along head paths against the in-core path, and the node selection at 10^5 nodes)")
        ->capture_default_str();
    cmd->add_option("--ooc-points", args->ooc.points, "ooc: cloud sizes, generated as COPC (comma separated)")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--head-paths", args->ooc.head_paths, "ooc: any of orbit, fly-in, turn (comma separated)")
        ->capture_default_str();
    cmd->add_option("--cache-mb", args->ooc.cache_mb, "ooc: the COPC source's RAM cache, as view --cache-mb")
        ->capture_default_str();
    cmd->add_option("--gpu-mb", args->ooc.gpu_mb, "ooc: the renderer's GPU arena, as view --gpu-mb")
        ->capture_default_str();
    cmd->add_option("--in-core-max", args->ooc.in_core_max_points,
                    "ooc: the in-core baseline only for clouds of at most this many points")
        ->capture_default_str();
    cmd->add_flag("--ooc-synthetic", args->ooc.synthetic,
                  "ooc: synthetic surveys written to COPC node by node, not the generator's clouds (sizes whose "
                  "scratch files would not fit the disk)");
    cmd->add_option("--ooc-dir", args->ooc.dir,
                    "ooc: folder where the COPC files are made and kept, reused by later runs (default: a "
                    "temporary folder, removed)");
    cmd->add_option("--subgroup", args->subgroup, "ooc, compute: the subgroup reduction where the GPU has it, on|off")
        ->check(CLI::IsMember({"on", "off"}))
        ->capture_default_str();
    cmd->add_flag("--no-md", args->no_md, "ooc: print only, leave BENCHMARKS.md alone");
    cmd->add_option("--frame-log", args->ooc.frame_log,
                    "ooc: existing folder that receives each run's second-lap frames as CSV (GPU and pass ms, "
                    "points drawn per eye), to place the slow frames along the head path")
        ->check(CLI::ExistingDirectory);
    cmd->add_option("--point-budget", args->point_budget, "skip rows: points per eye with the LOD budget")
        ->capture_default_str();
    cmd->add_option("--rasterizer", args->rasterizers,
                    "egl and skip rows once per rasterizer, any of points, compute (comma separated); ooc: one")
        ->delimiter(',')
        ->capture_default_str();
    cmd->add_option("--eye", args->eye, "eye size of the offscreen stereo path, WxH")->capture_default_str();
    cmd->add_option("--display", args->display,
                    "auto: without DISPLAY, rerun under tests/viewer/headless_env.sh "
                    "(Xvfb + Monado's simulated HMD); none: run as is")
        ->capture_default_str();
    cmd->callback([args] { run(*args); });
}

}  // namespace bench
