// bench/src/view_pick.cpp: pick times of the viewer's pointer over a k-d tree, and the
// scan it replaces.
#include "view_pick.hpp"

#include <render/orbit_camera.hpp>
#include <viewer/pick_index.hpp>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <numbers>
#include <random>
#include <vector>

namespace bench {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
/// This thread's CPU time, ms: a pick's own cost, without the time the scheduler gave
/// other processes while it ran (a shared machine preempts a 0.1 ms call now and then).
double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}
double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * double(v.size() - 1) + 0.5))];
}
}  // namespace

void printPickingHeader(std::FILE* out) {
    std::fprintf(out,
                 "| points | index build s | rays | hits | pick ms median | p99 | max | CPU ms p99 | CPU ms max | "
                 "sphere queries median | scan ms median (every point) | speed-up |\n");
    std::fprintf(out, "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
}

void measurePicking(const core::PointCloud& cloud, int rays, std::FILE* out) {
    const auto t_build = Clock::now();
    const viewer::PickIndex index(cloud.points);
    const double build_s = msSince(t_build) / 1000.0;
    const core::Bounds bounds = cloud.bounds();
    const render::OrbitCameraOptions orbit;  // the viewer's automatic mode: 60 m out, 40 m up
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
    std::uniform_int_distribution<std::size_t> pick_point(0, cloud.points.size() - 1);
    std::vector<double> times, cpu_times, queries, scans;
    int hits = 0;
    for (int i = 0; i < rays; ++i) {
        const render::CameraPose eye = render::orbitPose(orbit, bounds.centre(), angle(rng));
        const glm::dvec3 target(cloud.points[pick_point(rng)].position);
        const double c0 = threadCpuMs();
        const auto t0 = Clock::now();
        const auto hit = index.pick(eye.eye, target - eye.eye);
        times.push_back(msSince(t0));
        cpu_times.push_back(threadCpuMs() - c0);
        queries.push_back(double(index.lastQueries()));
        if (hit) ++hits;
        if (i < 5) {  // the scan is what a frame would pay without the index
            const auto t1 = Clock::now();
            const auto scan = index.pickByScan(eye.eye, target - eye.eye);
            scans.push_back(msSince(t1));
            if (bool(scan) != bool(hit) || (scan && scan->index != hit->index && scan->distance_m != hit->distance_m))
                std::fprintf(stderr, "bench view: pick and scan disagree on ray %d\n", i);
        }
    }
    const double median = quantile(times, 0.5), scan = quantile(scans, 0.5);
    std::fprintf(out, "| %zu | %.2f | %d | %d | %.4f | %.4f | %.4f | %.4f | %.4f | %.0f | %.1f | %.0fx |\n",
                 cloud.points.size(), build_s, rays, hits, median, quantile(times, 0.99), quantile(times, 1.0),
                 quantile(cpu_times, 0.99), quantile(cpu_times, 1.0), quantile(queries, 0.5), scan,
                 median > 0 ? scan / median : 0.0);
    std::fflush(out);
}

}  // namespace bench
