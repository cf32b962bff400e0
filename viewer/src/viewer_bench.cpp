// viewer/src/viewer_bench.cpp: `ladarvr bench view` measurements (a program, not a test).
// Runs the real viewer loop with GL timer queries on a cloud that is entirely uploaded
// during warm-up, and takes medians of the per-frame figures from its run log.
#include <viewer/viewer.hpp>

#include <engine/error.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <vector>

namespace viewer {

namespace {
double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

ViewBenchResult measure(const engine::PointCloud& cloud, const ViewBenchOptions& bench, bool xr) {
    ViewerOptions o;
    o.use_xr = xr;
    o.quiet = true;
    o.vsync = false;
    o.gpu_timing = true;
    o.style.eye_dome = true;
    o.upload_points_per_frame = std::max<std::size_t>(cloud.points.size(), 1024);   // all in frame 1
    o.frames = 1 + bench.warmup_frames + bench.frames;
    o.timeout_s = 600.0;
    CloudFeed feed;
    feed.feedCloud(cloud, 1u << 20);
    std::string log_text;
    runViewer(o, feed, log_text);
    const auto log = nlohmann::json::parse(log_text);

    ViewBenchResult r;
    r.path = xr ? "xr" : "mirror";
    r.points = cloud.points.size();
    r.gl = log.value("gl", "");
    const bool xr_ran = log.value("frames_submitted", 0L) > 0;
    if (xr && !xr_ran) {
        r.note = "no OpenXR session: " + log.value("fallback", std::string("?"));
        return r;
    }
    if (xr) {
        const auto size = log.value("xr_eye_size", nlohmann::json::array({0, 0}));
        r.width = size[0];
        r.height = size[1];
    } else {
        r.width = o.window_width;
        r.height = o.window_height;
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
}  // namespace

std::vector<ViewBenchResult> benchmarkViewer(const engine::PointCloud& cloud, const ViewBenchOptions& options) {
    if (options.frames < 1 || options.warmup_frames < 0)
        throw engine::Error("bench view: frames must be >= 1 and warm-up >= 0");
    std::vector<ViewBenchResult> results;
    results.push_back(measure(cloud, options, false));
    if (options.xr) results.push_back(measure(cloud, options, true));
    return results;
}

}  // namespace viewer
