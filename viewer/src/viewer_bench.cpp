// viewer/src/viewer_bench.cpp: `ladarvr bench view` measurements (a program, not a test).
// - mirror / xr: the real frame loop (runViewer) with a GL timer query per frame, medians
//   taken from its run log after the whole cloud is on the GPU;
// - stereo-egl: the same per-eye drawing (points + eye-dome lighting + indicator) into two
//   offscreen eye images at HMD size through a headless EGL context: the stereo-equivalent
//   that runs on any GPU without a display or a runtime (e.g. NVIDIA through EGL).
#include <viewer/viewer.hpp>

#include "point_renderer.hpp"

#include <engine/error.hpp>
#include <render/egl_context.hpp>
#include <render/gl.hpp>
#include <render/point_splat.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <memory>
#include <numbers>
#include <exception>
#include <vector>

namespace viewer {

namespace {
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

ViewBenchResult measureLoop(const engine::PointCloud& cloud, const ViewBenchOptions& bench, bool xr) {
    ViewBenchResult r;
    r.path = xr ? "xr" : "mirror";
    r.points = cloud.points.size();
    ViewerOptions o;
    o.use_xr = xr;
    o.quiet = true;
    o.vsync = false;
    o.gpu_timing = true;
    o.upload_points_per_frame = std::max<std::size_t>(cloud.points.size(), 1024);   // all in frame 1
    o.frames = 1 + bench.warmup_frames + bench.frames;
    o.timeout_s = 1200.0;
    o.modes.orbit_period_s = 60.0;
    CloudFeed feed;
    feed.feedCloud(cloud, 1u << 20);
    std::string log_text;
    try {
        runViewer(o, feed, log_text);
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
    std::vector<double> cpu, gpu, frame;
    for (const auto& f : log["frames"]) {
        if (f.value("frame", 0L) <= 1 + bench.warmup_frames) continue;
        if (f.value("points_uploaded", std::size_t{0}) < cloud.points.size()) continue;
        cpu.push_back(f.value("cpu_ms", 0.0));
        gpu.push_back(f.value("gpu_ms", 0.0));
        frame.push_back(f.value("frame_ms", 0.0));
    }
    r.frames = static_cast<int>(cpu.size());
    r.cpu_ms_median = median(cpu);
    r.gpu_ms_median = median(gpu);
    r.frame_ms_median = median(frame);
    return r;
}

ViewBenchResult measureStereoEgl(const engine::PointCloud& cloud, const ViewBenchOptions& bench) {
    ViewBenchResult r;
    r.path = "stereo-egl";
    r.points = cloud.points.size();
    r.width = bench.eye_width;
    r.height = bench.eye_height;
    std::unique_ptr<render::EglContext> context;
    try {
        context = std::make_unique<render::EglContext>();
    } catch (const std::exception& e) {
        r.note = std::string("skipped: ") + e.what();
        return r;
    }
    r.gl = render::glDescription();
    r.note = "offscreen, 2 eyes, automatic orbit, IPD 64 mm";
    {
        PointRenderer renderer;
        CloudFeed feed;
        feed.feedCloud(cloud, 1u << 20);
        renderer.stream(feed, cloud.points.size());
        ModeOptions modes_options;
        ModeController modes(modes_options, renderer.bounds().centre());
        std::array<EyeTarget, 2> targets;
        std::array<GLuint, 2> images{}, fbos{};
        glCreateTextures(GL_TEXTURE_2D, 2, images.data());
        glCreateFramebuffers(2, fbos.data());
        for (int i = 0; i < 2; ++i) {
            targets[i].ensure(r.width, r.height);
            glTextureStorage2D(images[i], 1, GL_RGBA8, r.width, r.height);   // the "swapchain image"
            glNamedFramebufferTexture(fbos[i], GL_COLOR_ATTACHMENT0, images[i], 0);
        }
        GLuint query = 0;
        glCreateQueries(GL_TIME_ELAPSED, 1, &query);
        ViewStyle style;
        // The baseline: the metric's splat renderer on the same points, eyes and targets.
        render::PointSplatRenderer baseline;
        baseline.setCloud(cloud);
        render::SplatStyle splat;
        splat.point_size_px = style.point_size_px;
        splat.use_point_colours = true;
        std::vector<double> cpu, gpu, frame, base_gpu;
        const int total = bench.warmup_frames + bench.frames;
        for (int f = 0; f < 2 * total; ++f) {
            const bool ours = f % 2 == 0;   // interleaved, so both see the same machine load
            const Clock::time_point t0 = Clock::now();
            if (ours) modes.update(1.0 / 90.0, {}, RigPose{});
            const RigPose rig = modes.rig();
            glBeginQuery(GL_TIME_ELAPSED, query);
            for (int i = 0; i < 2; ++i) {
                RigPose eye = rig;
                eye.position = rig.apply(glm::dvec3(i == 0 ? -0.032 : 0.032, 0.0, 0.0));
                EyeDraw draw;
                draw.view = viewFromPose(eye);
                draw.projection = projectionFromFov(-0.95, 0.95, 1.0, -1.0, draw.near_m, draw.far_m);
                if (ours) {
                    renderer.drawEye(targets[i], draw, style, modes.mode(), fbos[i], 0, 0, r.width, r.height);
                } else {
                    glBindFramebuffer(GL_FRAMEBUFFER, targets[i].fbo);
                    glViewport(0, 0, r.width, r.height);
                    glEnable(GL_DEPTH_TEST);
                    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                    baseline.draw(draw.view, draw.projection, splat);
                }
            }
            glEndQuery(GL_TIME_ELAPSED);
            const double submit_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            GLuint64 ns = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
            glFinish();
            const double frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            if (f / 2 < bench.warmup_frames) continue;
            if (!ours) {
                base_gpu.push_back(double(ns) * 1e-6);
                continue;
            }
            cpu.push_back(submit_ms);
            gpu.push_back(double(ns) * 1e-6);
            frame.push_back(frame_ms);
        }
        glDeleteQueries(1, &query);
        glDeleteFramebuffers(2, fbos.data());
        glDeleteTextures(2, images.data());
        for (auto& t : targets) t.destroy();
        r.frames = static_cast<int>(cpu.size());
        r.cpu_ms_median = median(cpu);
        r.gpu_ms_median = median(gpu);
        r.frame_ms_median = median(frame);
        r.baseline_gpu_ms_median = median(base_gpu);
    }
    return r;
}

/// Issue 5 rows: the same eyes drawn with nothing skipped, with frustum culling, and with
/// culling + the point budget; the orbit view and the same rig turned 180 degrees (looking
/// away from the cloud's centre). All configurations interleaved frame by frame.
std::vector<ViewBenchResult> measureSkip(const engine::PointCloud& cloud, const ViewBenchOptions& bench) {
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
    std::vector<ViewBenchResult> rows(configs.size());
    for (std::size_t c = 0; c < configs.size(); ++c) {
        rows[c].path = "skip-egl";
        rows[c].points = cloud.points.size();
        rows[c].width = bench.eye_width;
        rows[c].height = bench.eye_height;
        rows[c].note = configs[c].name;
        if (configs[c].budget) rows[c].note += " " + std::to_string(configs[c].budget);
    }
    std::unique_ptr<render::EglContext> context;
    try {
        context = std::make_unique<render::EglContext>();
    } catch (const std::exception& e) {
        for (auto& r : rows) r.note = std::string("skipped: ") + e.what();
        return rows;
    }
    const std::string gl = render::glDescription();
    {
        // The LOD order's CPU cost per streamed chunk (the viewer's 262,144 point chunks).
        {
            const std::size_t chunk = 262144;
            std::vector<double> ms;
            for (std::size_t i = 0; i + chunk <= cloud.points.size() && ms.size() < 8; i += chunk) {
                std::vector<engine::CloudPoint> part(cloud.points.begin() + static_cast<std::ptrdiff_t>(i),
                                                     cloud.points.begin() + static_cast<std::ptrdiff_t>(i + chunk));
                const Clock::time_point t0 = Clock::now();
                const auto cells = buildLodOrder(part);
                ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
            }
            std::fprintf(stderr, "bench view: LOD order of a 262144 point chunk: median %.2f ms (%zu chunks)\n",
                         median(ms), ms.size());
        }
        PointRenderer renderer;
        CloudFeed feed;
        feed.feedCloud(cloud, 1u << 20);
        renderer.stream(feed, cloud.points.size());
        ModeOptions modes_options;
        ModeController modes(modes_options, renderer.bounds().centre());
        modes.update(1.0 / 90.0, {}, RigPose{});
        {
            std::array<EyeDraw, 2> draws;
            for (auto& d : draws) {   // the orbit view: every cell visible, the budget binding at 20 M
                d.view = viewFromPose(modes.rig());
                d.projection = projectionFromFov(-0.95, 0.95, 1.0, -1.0, d.near_m, d.far_m);
            }
            const Clock::time_point t0 = Clock::now();
            for (int k = 0; k < 20; ++k) renderer.planFrame(draws, bench.point_budget, true);
            std::fprintf(stderr, "bench view: planFrame over %zu cells: %.3f ms\n", renderer.cellCount(),
                         std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / 20.0);
        }
        std::array<EyeTarget, 2> targets;
        std::array<GLuint, 2> images{}, fbos{};
        glCreateTextures(GL_TEXTURE_2D, 2, images.data());
        glCreateFramebuffers(2, fbos.data());
        for (int i = 0; i < 2; ++i) {
            targets[i].ensure(bench.eye_width, bench.eye_height);
            glTextureStorage2D(images[i], 1, GL_RGBA8, bench.eye_width, bench.eye_height);
            glNamedFramebufferTexture(fbos[i], GL_COLOR_ATTACHMENT0, images[i], 0);
        }
        GLuint query = 0;
        glCreateQueries(GL_TIME_ELAPSED, 1, &query);
        const ViewStyle style;
        std::vector<std::vector<double>> cpu(configs.size()), gpu(configs.size()), frame(configs.size());
        for (int f = 0; f < bench.warmup_frames + bench.frames; ++f) {
            for (std::size_t c = 0; c < configs.size(); ++c) {
                RigPose rig = modes.rig();   // a fixed orbit pose: every configuration sees the same
                if (configs[c].away)
                    rig.rotation = glm::dmat3(glm::rotate(glm::dmat4(1.0), std::numbers::pi, glm::dvec3(0, 0, 1))) *
                                   rig.rotation;
                const Clock::time_point t0 = Clock::now();
                std::array<EyeDraw, 2> draws;
                for (int i = 0; i < 2; ++i) {
                    RigPose eye = rig;
                    eye.position = rig.apply(glm::dvec3(i == 0 ? -0.032 : 0.032, 0.0, 0.0));
                    draws[i].view = viewFromPose(eye);
                    draws[i].projection = projectionFromFov(-0.95, 0.95, 1.0, -1.0, draws[i].near_m, draws[i].far_m);
                }
                renderer.planFrame(draws, configs[c].budget, configs[c].cull);
                glBeginQuery(GL_TIME_ELAPSED, query);
                std::size_t drawn = 0;
                for (int i = 0; i < 2; ++i)
                    drawn += renderer.drawEye(targets[i], draws[i], style, modes.mode(), fbos[i], 0, 0,
                                              bench.eye_width, bench.eye_height).points_drawn;
                glEndQuery(GL_TIME_ELAPSED);
                const double submit_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                GLuint64 ns = 0;
                glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
                glFinish();
                const double frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                rows[c].points_drawn = drawn;
                if (f < bench.warmup_frames) continue;
                cpu[c].push_back(submit_ms);
                gpu[c].push_back(double(ns) * 1e-6);
                frame[c].push_back(frame_ms);
            }
        }
        glDeleteQueries(1, &query);
        glDeleteFramebuffers(2, fbos.data());
        glDeleteTextures(2, images.data());
        for (auto& t : targets) t.destroy();
        for (std::size_t c = 0; c < configs.size(); ++c) {
            rows[c].gl = gl;
            rows[c].frames = static_cast<int>(cpu[c].size());
            rows[c].cpu_ms_median = median(cpu[c]);
            rows[c].gpu_ms_median = median(gpu[c]);
            rows[c].frame_ms_median = median(frame[c]);
        }
    }
    return rows;
}
}  // namespace

std::vector<ViewBenchResult> benchmarkViewer(const engine::PointCloud& cloud, const ViewBenchOptions& options) {
    if (options.frames < 1 || options.warmup_frames < 0)
        throw engine::Error("bench view: --frames must be >= 1 and --warmup >= 0");
    if (options.eye_width < 16 || options.eye_height < 16 || options.eye_width > 8192 || options.eye_height > 8192)
        throw engine::Error("bench view: --eye size must be 16..8192 pixels each");
    std::vector<ViewBenchResult> results;
    if (options.mirror) results.push_back(measureLoop(cloud, options, false));
    if (options.xr) results.push_back(measureLoop(cloud, options, true));
    if (options.egl) results.push_back(measureStereoEgl(cloud, options));
    if (options.skip)
        for (auto& r : measureSkip(cloud, options)) results.push_back(std::move(r));
    return results;
}

}  // namespace viewer
