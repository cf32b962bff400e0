// bench/src/view_measure.cpp: `ladarvr bench view` measurements (a program, not a test).
// - mirror / xr: the real frame loop (viewer::runViewer) with a GL timer query per frame,
//   medians taken from its run log after the whole cloud is on the GPU;
// - stereo-egl: the same per-eye drawing (points + eye-dome lighting + indicator) into two
//   offscreen eye images at HMD size (viewer::OffscreenStereo) through a headless EGL
//   context: the stereo-equivalent that runs on any GPU without a display or a runtime;
// - skip-egl: the same eyes with nothing skipped, frustum culling, and culling + the point
//   budget, for the orbit view and a view turned away from the cloud.
#include "view_measure.hpp"

#include "common.hpp"

#include <core/error.hpp>
#include <render/egl_context.hpp>
#include <render/gl.hpp>
#include <render/point_splat.hpp>
#include <viewer/lod.hpp>
#include <viewer/offscreen_stereo.hpp>
#include <viewer/viewer.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <exception>
#include <memory>
#include <numbers>
#include <vector>

namespace bench {

namespace {
/// Medians over samples; 0 when there are none (a path that measured nothing).
double medianOr0(const std::vector<double>& v) { return v.empty() ? 0.0 : median(v); }

/// A colour (RGBA8) + depth (32F) framebuffer for the baseline renderer, the same kind of
/// target the viewer draws an eye into before its eye-dome lighting resolve.
struct BaselineTarget {
    GLuint fbo = 0, colour = 0, depth = 0;
    BaselineTarget(int w, int h) {
        glCreateTextures(GL_TEXTURE_2D, 1, &colour);
        glTextureStorage2D(colour, 1, GL_RGBA8, w, h);
        glCreateTextures(GL_TEXTURE_2D, 1, &depth);
        glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT32F, w, h);
        glCreateFramebuffers(1, &fbo);
        glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, colour, 0);
        glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depth, 0);
    }
    ~BaselineTarget() {
        glDeleteFramebuffers(1, &fbo);
        glDeleteTextures(1, &colour);
        glDeleteTextures(1, &depth);
    }
    BaselineTarget(const BaselineTarget&) = delete;
    BaselineTarget& operator=(const BaselineTarget&) = delete;
};

/// One GL timer query around the GPU work of `draw`: CPU submit ms, GPU ms, whole frame ms
/// (until glFinish returns).
struct FrameTimes {
    double submit_ms = 0.0, gpu_ms = 0.0, frame_ms = 0.0;
};
template <class Draw>
FrameTimes timeFrame(GLuint query, Clock::time_point t0, Draw&& draw) {
    glBeginQuery(GL_TIME_ELAPSED, query);
    draw();
    glEndQuery(GL_TIME_ELAPSED);
    FrameTimes t;
    t.submit_ms = msSince(t0);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    glFinish();
    t.frame_ms = msSince(t0);
    t.gpu_ms = double(ns) * 1e-6;
    return t;
}

viewer::StereoOptions stereoOptions(const ViewBenchOptions& bench) {
    viewer::StereoOptions o;
    o.eye_width_px = bench.eye_width;
    o.eye_height_px = bench.eye_height;
    return o;
}

/// Samples of one configuration: CPU submit, GPU and whole-frame milliseconds.
struct Samples {
    std::vector<double> cpu, gpu, frame;
    void add(const FrameTimes& t) {
        cpu.push_back(t.submit_ms);
        gpu.push_back(t.gpu_ms);
        frame.push_back(t.frame_ms);
    }
    void store(ViewBenchResult& r) const {
        r.frames = static_cast<int>(cpu.size());
        r.cpu_ms_median = medianOr0(cpu);
        r.gpu_ms_median = medianOr0(gpu);
        r.frame_ms_median = medianOr0(frame);
    }
};

/// `tools`: 0 the plain loop; 1 the XR loop without the operator's tools (no panel in the
/// headset); 2 with the pointer aimed at the cloud's centre, a designation and the panel
/// in the headset; 3 the same with the cutting volume on (which hides most points, so it
/// saves more than it costs). These rows count only frames once the pick index is built
/// (on a worker thread after the upload, competing for the CPU) and, with the pointer,
/// once it has a hit.
ViewBenchResult measureLoop(const core::PointCloud& cloud, const ViewBenchOptions& bench, bool xr, int tools = 0) {
    ViewBenchResult r;
    r.path = tools == 1 ? "xr-no-tools" : tools == 2 ? "xr-tools" : tools == 3 ? "xr-tools-cut" : xr ? "xr" : "mirror";
    r.points = cloud.points.size();
    viewer::ViewerOptions o;
    o.use_xr = xr;
    o.quiet = true;
    o.vsync = false;
    o.gpu_timing = true;
    o.upload_points_per_frame = std::max<std::size_t>(cloud.points.size(), 1024);  // all in frame 1
    o.frames = 1 + bench.warmup_frames + bench.frames;
    o.timeout_s = 1200.0;
    o.modes.orbit_period_s = 60.0;
    if (tools > 0) {
        o.headset_panel = tools >= 2;
        o.frames += 60;  // room for the pick index to be built before the measured frames
    }
    if (tools >= 2) {
        const glm::dvec3 centre = cloud.bounds().centre() + cloud.origin;
        viewer::ScriptEvent aim;
        aim.frame = 0;
        aim.key = viewer::ScriptEvent::Key::Aim;
        for (int i = 0; i < 3; ++i) aim.point[i] = centre[i];
        viewer::ScriptEvent designate;
        designate.frame = 1;
        designate.key = viewer::ScriptEvent::Key::Designate;
        o.script = {aim, designate};
        o.cut_enabled = tools == 3;
    }
    viewer::CloudFeed feed;
    feed.feedCloud(cloud, 1u << 20);
    std::string log_text;
    try {
        viewer::runViewer(o, feed, log_text);
    } catch (const std::exception& e) {
        r.note = std::string("skipped: ") + e.what();
        return r;
    }
    const auto log = nlohmann::json::parse(log_text);
    r.gl = log.value("gl", "");
    if (xr && log.value("frames_submitted", 0L) == 0) {
        r.note = "skipped: no OpenXR session (" + log.value("fallback", std::string("?")) + ")";
        return r;
    }
    if (xr) {
        const auto size = log.value("xr_eye_size", nlohmann::json::array({0, 0}));
        r.width = size[0];
        r.height = size[1];
        r.note = log.value("xr_system", std::string("")) + ", mirror both eyes";
    } else {
        r.width = o.window_width;
        r.height = o.window_height;
        r.note = "desktop window, one view";
    }
    if (tools == 2) r.note += ", pointer + designation + headset panel";
    if (tools == 3) r.note += ", pointer + designation + headset panel + cutting volume (15 m)";
    if (tools == 1) r.note += ", no tools, no headset panel";
    Samples samples;
    int ready_frames = 0;
    for (const auto& f : log["frames"]) {
        if (f.value("frame", 0L) <= 1 + bench.warmup_frames) continue;
        if (f.value("points_uploaded", std::size_t{0}) < cloud.points.size()) continue;
        if (tools > 0) {  // once the index is built (its thread competes for the CPU), then warm-up again
            const bool hit = f.contains("pointer") && f["pointer"].contains("hit") && !f["pointer"]["hit"].is_null();
            if (!f.value("pick_ready", false) || (tools >= 2 && !hit)) continue;
            if (++ready_frames <= bench.warmup_frames || int(samples.cpu.size()) >= bench.frames) continue;
        }
        samples.add({f.value("cpu_ms", 0.0), f.value("gpu_ms", 0.0), f.value("frame_ms", 0.0)});
    }
    samples.store(r);
    return r;
}

/// A headless GL context, or the reason there is none (in `note`).
std::unique_ptr<render::EglContext> eglContext(std::string& note) {
    try {
        return std::make_unique<render::EglContext>();
    } catch (const std::exception& e) {
        note = std::string("skipped: ") + e.what();
        return nullptr;
    }
}

ViewBenchResult measureStereoEgl(const core::PointCloud& cloud, const ViewBenchOptions& bench,
                                 viewer::Rasterizer rasterizer) {
    ViewBenchResult r;
    r.path = "stereo-egl";
    r.points = cloud.points.size();
    r.width = bench.eye_width;
    r.height = bench.eye_height;
    const std::unique_ptr<render::EglContext> context = eglContext(r.note);
    if (!context) return r;
    r.gl = render::glDescription();
    r.note =
        std::string("offscreen, 2 eyes, automatic orbit, IPD 64 mm, rasterizer ") + viewer::rasterizerName(rasterizer);
    {
        viewer::OffscreenStereo stereo(stereoOptions(bench));
        stereo.upload(cloud);
        viewer::ModeController modes(viewer::ModeOptions{}, stereo.bounds().centre());
        viewer::ViewStyle style;
        style.rasterizer = rasterizer;
        // The baseline: the metric's splat renderer on the same points and eyes.
        render::PointSplatRenderer baseline;
        baseline.setCloud(cloud);
        render::SplatStyle splat;
        splat.point_size_px = style.point_size_px;
        splat.use_point_colours = true;
        BaselineTarget baseline_target(r.width, r.height);
        GLuint query = 0;
        glCreateQueries(GL_TIME_ELAPSED, 1, &query);
        Samples ours;
        std::vector<double> base_gpu;
        const int total = bench.warmup_frames + bench.frames;
        for (int f = 0; f < 2 * total; ++f) {
            const bool viewer_frame = f % 2 == 0;  // interleaved, so both see the same machine load
            const Clock::time_point t0 = Clock::now();
            if (viewer_frame) modes.update(1.0 / 90.0, {}, viewer::RigPose{});
            const viewer::RigPose head = modes.rig();
            const FrameTimes t = timeFrame(query, t0, [&] {
                if (viewer_frame) {
                    stereo.draw(head, style, modes.mode());
                    return;
                }
                for (int i = 0; i < 2; ++i) {
                    glBindFramebuffer(GL_FRAMEBUFFER, baseline_target.fbo);
                    glViewport(0, 0, r.width, r.height);
                    glEnable(GL_DEPTH_TEST);
                    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                    baseline.draw(stereo.eyeView(head, i), stereo.projection(), splat);
                }
            });
            if (f / 2 < bench.warmup_frames) continue;
            if (viewer_frame)
                ours.add(t);
            else
                base_gpu.push_back(t.gpu_ms);
        }
        glDeleteQueries(1, &query);
        ours.store(r);
        r.baseline_gpu_ms_median = medianOr0(base_gpu);
    }
    return r;
}

/// The same eyes drawn with nothing skipped, with frustum culling, and with culling + the
/// point budget; the orbit view and the same rig turned 180 degrees (looking away from the
/// cloud's centre). All configurations interleaved frame by frame.
std::vector<ViewBenchResult> measureSkip(const core::PointCloud& cloud, const ViewBenchOptions& bench) {
    struct Config {
        const char* name;
        bool away, cull;
        std::size_t budget;
    };
    const std::vector<Config> configs = {
        {"orbit view, nothing skipped", false, false, 0},
        {"orbit view, frustum culling", false, true, 0},
        {"orbit view, culling + point budget", false, true, bench.point_budget},
        {"view away from the cloud, nothing skipped", true, false, 0},
        {"view away from the cloud, frustum culling", true, true, 0},
        {"view away from the cloud, culling + point budget", true, true, bench.point_budget},
    };
    // Row k: configuration k % configs, rasterizer k / configs.
    const std::size_t rasterizers = bench.rasterizers.size();
    std::vector<ViewBenchResult> rows(configs.size() * rasterizers);
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const std::size_t c = k % configs.size();
        rows[k].path = "skip-egl";
        rows[k].points = cloud.points.size();
        rows[k].width = bench.eye_width;
        rows[k].height = bench.eye_height;
        rows[k].note = configs[c].name;
        if (configs[c].budget) rows[k].note += " " + std::to_string(configs[c].budget);
        if (rasterizers > 1)
            rows[k].note += std::string(", ") + viewer::rasterizerName(bench.rasterizers[k / configs.size()]);
    }
    std::string why;
    const std::unique_ptr<render::EglContext> context = eglContext(why);
    if (!context) {
        for (auto& r : rows) r.note = why;
        return rows;
    }
    const std::string gl = render::glDescription();
    {
        // The LOD order's CPU cost per streamed chunk (the viewer's 262,144 point chunks).
        {
            const std::size_t chunk = 262144;
            std::vector<double> ms;
            for (std::size_t i = 0; i + chunk <= cloud.points.size() && ms.size() < 8; i += chunk) {
                std::vector<core::CloudPoint> part(cloud.points.begin() + static_cast<std::ptrdiff_t>(i),
                                                   cloud.points.begin() + static_cast<std::ptrdiff_t>(i + chunk));
                const Clock::time_point t0 = Clock::now();
                const auto cells = viewer::buildLodOrder(part);
                ms.push_back(msSince(t0));
            }
            std::fprintf(stderr, "bench view: LOD order of a 262144 point chunk: median %.2f ms (%zu chunks)\n",
                         medianOr0(ms), ms.size());
        }
        viewer::OffscreenStereo stereo(stereoOptions(bench));
        stereo.upload(cloud);
        viewer::ModeController modes(viewer::ModeOptions{}, stereo.bounds().centre());
        modes.update(1.0 / 90.0, {}, viewer::RigPose{});
        {
            // The orbit view's plan: every cell visible, the budget binding for large clouds.
            const Clock::time_point t0 = Clock::now();
            for (int k = 0; k < 20; ++k) stereo.plan(modes.rig(), bench.point_budget, true);
            std::fprintf(stderr, "bench view: planFrame over %zu cells: %.3f ms\n", stereo.cellCount(),
                         msSince(t0) / 20.0);
        }
        GLuint query = 0;
        glCreateQueries(GL_TIME_ELAPSED, 1, &query);
        std::vector<Samples> samples(rows.size());
        for (int f = 0; f < bench.warmup_frames + bench.frames; ++f) {
            for (std::size_t k = 0; k < rows.size(); ++k) {
                const std::size_t c = k % configs.size();
                viewer::ViewStyle style;
                style.rasterizer = bench.rasterizers[k / configs.size()];
                viewer::RigPose head = modes.rig();  // a fixed orbit pose: every configuration sees the same
                if (configs[c].away)
                    head.rotation =
                        glm::dmat3(glm::rotate(glm::dmat4(1.0), std::numbers::pi, glm::dvec3(0, 0, 1))) * head.rotation;
                const Clock::time_point t0 = Clock::now();
                stereo.plan(head, configs[c].budget, configs[c].cull);
                std::size_t drawn = 0;
                const FrameTimes t = timeFrame(query, t0, [&] { drawn = stereo.draw(head, style, modes.mode()); });
                rows[k].points_drawn = drawn;
                if (f >= bench.warmup_frames) samples[k].add(t);
            }
        }
        glDeleteQueries(1, &query);
        for (std::size_t k = 0; k < rows.size(); ++k) {
            rows[k].gl = gl;
            samples[k].store(rows[k]);
        }
    }
    return rows;
}
}  // namespace

std::vector<ViewBenchResult> measureViewer(const core::PointCloud& cloud, const ViewBenchOptions& options) {
    if (options.frames < 1 || options.warmup_frames < 0)
        throw core::Error("bench view: --frames must be >= 1 and --warmup >= 0");
    if (options.eye_width < 16 || options.eye_height < 16 || options.eye_width > 8192 || options.eye_height > 8192)
        throw core::Error("bench view: --eye size must be 16..8192 pixels each");
    std::vector<ViewBenchResult> results;
    if (options.mirror) results.push_back(measureLoop(cloud, options, false));
    if (options.xr) results.push_back(measureLoop(cloud, options, true));
    if (options.tools) {
        results.push_back(measureLoop(cloud, options, true, 1));
        results.push_back(measureLoop(cloud, options, true, 2));
        results.push_back(measureLoop(cloud, options, true, 3));
    }
    if (options.rasterizers.empty())
        throw core::Error("bench view: --rasterizer needs at least one of points, compute");
    if (options.egl)
        for (const viewer::Rasterizer r : options.rasterizers) results.push_back(measureStereoEgl(cloud, options, r));
    if (options.skip)
        for (auto& r : measureSkip(cloud, options)) results.push_back(std::move(r));
    return results;
}

}  // namespace bench
