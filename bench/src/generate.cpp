// bench/src/generate.cpp: `ladarvr bench generate`: the generator's ray-casting
// throughput against plain loops over the same precomputed rays and the same BVH: one of
// rtcIntersect16 packets of 16 pixels of a row (the Embree limit for the generator's
// packets on this machine) and one of rtcIntersect1; and the time of every stage, on the
// paper's configuration (demo scene) and on one >= 100x larger that streams to disk.
// Warm-up, repeats interleaved with the baselines, medians with min..max; the section
// "## Generator (ladarvr bench generate)" of BENCHMARKS.md is rewritten with the tables,
// the command and the machine.
#include "common.hpp"
#include "formats.hpp"
#include "plain_loop.hpp"
#include "register.hpp"
#include "sensor.hpp"

#include <core/error.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>
#include <sim/generator.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <unistd.h>
#include <unordered_map>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

struct BenchGenerateCli {
    bool quick = false;
    int threads = 0;
    int repeats = 5;
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
    std::string tmp;
    std::string only;       // "sensors", "formats", "runs" or "large": those rows alone
    int large_repeats = 1;  // timed runs of the large configuration
};

// Peak resident set since the last resetPeakRss(), from /proc/self/status (VmHWM), MiB.
// Writing "5" to clear_refs resets VmHWM (Linux >= 4.0); if that is refused, the peak is
// that of the whole process so far (and said so).
bool resetPeakRss() {
    std::ofstream f("/proc/self/clear_refs");
    f << "5";
    f.flush();
    return bool(f);
}
double statusMiB(const char* key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key, 0) == 0) return std::stod(line.substr(line.find(':') + 1)) / 1024.0;  // kB
    return 0.0;
}

// Midpoint subdivision (each triangle into 4, shared edges keep shared midpoints, so the
// mesh stays watertight): the same surfaces with 4x the triangles.
core::Mesh subdivide(const core::Mesh& m) {
    core::Mesh out;
    out.name = m.name;
    out.role = m.role;
    out.vertices = m.vertices;
    std::unordered_map<std::uint64_t, unsigned> midpoints;
    const auto mid = [&](unsigned a, unsigned b) {
        const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
        auto [it, inserted] = midpoints.try_emplace(key, unsigned(out.vertices.size()));
        if (inserted) out.vertices.push_back(0.5f * (m.vertices[a] + m.vertices[b]));
        return it->second;
    };
    out.triangles.reserve(4 * m.triangles.size());
    for (const glm::uvec3& t : m.triangles) {
        const unsigned ab = mid(t.x, t.y), bc = mid(t.y, t.z), ca = mid(t.z, t.x);
        out.triangles.emplace_back(t.x, ab, ca);
        out.triangles.emplace_back(ab, t.y, bc);
        out.triangles.emplace_back(ca, bc, t.z);
        out.triangles.emplace_back(ab, bc, ca);
    }
    return out;
}

struct Result {
    std::string name;
    std::size_t triangles = 0;
    sim::OrbitOptions orbit;
    int threads = 1, repeats = 0;
    double prepare_s = 0;  // scene load (and subdivision)
    std::uint64_t rays = 0, points = 0, misses = 0;
    std::uint64_t rays_traced = 0;                         // rays the generator cast (the skips answer the rest)
    Spread bvh, cast, fuse, ransac, colour, write, total;  // seconds per stage
    // Throughputs in Mrays/s over all `rays`: the generator's cast stage (rtcIntersect16
    // packets), the plain rtcIntersect16 and rtcIntersect1 loops, and the cast stage with
    // packet_rays = false (n = 0: not run).
    Spread gen_mrays, plain16_mrays, plain1_mrays, single_mrays;
    bool streamed = false;
    bool in_output = false;
    bool packed_on_workers = false;
    double peak_rss_mib = 0, rss_before_mib = 0;
    bool peak_reset = false;
    double output_mib = 0;
    std::optional<double> precision, recall;
    // Per run: the total over that run's plain rtcIntersect16 loop, and whether the fuse
    // stage took no longer than the cast stage.
    std::vector<double> total_over_plain16;
    std::vector<bool> fuse_within_cast;
    bool warmed_up = false;
};

// A plain loop over every ray of every view (plain_loop.hpp): rtcIntersect16 packets of
// 16 pixels of a row, or rtcIntersect1. Rays are made per batch of views (not timed);
// only the intersect loops are timed.
double plainLoopAllViews(const sim::Generator& g, int threads, bool packets) {
    const sim::OrbitOptions& orbit = g.options().orbit;
    const std::size_t npix = std::size_t(orbit.xres) * std::size_t(orbit.yres);
    const std::size_t batch_views = std::max<std::size_t>(1, (std::size_t(4) << 20) / npix);
    std::vector<sim::Ray> rays, view_rays;
    std::vector<sim::Hit> hits;
    double seconds = 0.0;
    for (int first = 0; first < orbit.views; first += int(batch_views)) {
        const int last = std::min(orbit.views, first + int(batch_views));
        rays.clear();
        for (int v = first; v < last; ++v) {
            g.viewRays(v, view_rays);
            rays.insert(rays.end(), view_rays.begin(), view_rays.end());
        }
        seconds += packets ? plainPacketLoopSeconds(g.caster(), rays, hits, threads, std::size_t(orbit.xres))
                           : plainLoopSeconds(g.caster(), rays, hits, threads);
    }
    return seconds;
}

Result runConfig(const std::string& name, const core::Scene& scene, const sim::GenerateOptions& options, int repeats,
                 bool warm_up, bool single_too, const fs::path& out) {
    Result r;
    r.name = name;
    r.orbit = options.orbit;
    r.repeats = repeats;
    r.warmed_up = warm_up;
    std::vector<double> bvh, cast, fuse, ransac, colour, write, total, plain1, plain16, single;
    if (warm_up) {
        sim::Generator g(scene, options);
        g.run(out, io::CloudFormat::PcdBinary);
        fs::remove(out);
        const int threads =
            options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
        plainLoopAllViews(g, threads, true);
        plainLoopAllViews(g, threads, false);
    }
    for (int k = 0; k < repeats; ++k) {
        sim::GenerateStats st;
        sim::Generator g(scene, options);  // builds the BVH both the generator and the baselines use
        // The baselines on this run's BVH, same rays, the generator's thread count.
        const auto baselines = [&](int threads) {
            plain16.push_back(plainLoopAllViews(g, threads, true));
            plain1.push_back(plainLoopAllViews(g, threads, false));
        };
        // Interleaved: even runs time the generator first, odd runs the baselines first
        // (on the thread count the previous run reported), so neither side always runs
        // on a machine the other has just warmed or heated.
        const bool baselines_first = k % 2 == 1;
        if (baselines_first) baselines(r.threads);
        r.rss_before_mib = statusMiB("VmRSS:");
        r.peak_reset = resetPeakRss();
        g.run(out, io::CloudFormat::PcdBinary, &st);
        r.peak_rss_mib = std::max(r.peak_rss_mib, statusMiB("VmHWM:"));
        r.output_mib = double(fs::file_size(out)) / 1048576.0;
        fs::remove(out);
        if (!baselines_first) baselines(st.threads);
        bvh.push_back(st.seconds.bvh);
        cast.push_back(st.seconds.cast);
        fuse.push_back(st.seconds.fuse);
        ransac.push_back(st.seconds.ground);
        colour.push_back(st.seconds.colour);
        write.push_back(st.seconds.write);
        total.push_back(st.seconds.total);
        r.total_over_plain16.push_back(st.seconds.total / plain16.back());
        r.fuse_within_cast.push_back(st.seconds.fuse <= st.seconds.cast);
        r.triangles = st.triangles;
        r.threads = st.threads;
        r.rays = st.rays;
        r.rays_traced = st.rays_traced;
        r.points = st.points;
        r.misses = st.misses;
        r.streamed = st.streamed;
        r.in_output = st.in_output;
        r.packed_on_workers = st.packed_on_workers;
        r.precision = st.ground_precision;
        r.recall = st.ground_recall;
        if (single_too) {  // the generator tracing one ray at a time (rtcIntersect1)
            sim::GenerateOptions one = options;
            one.packet_rays = false;
            sim::GenerateStats st1;
            sim::Generator(scene, one).run(out, io::CloudFormat::PcdBinary, &st1);
            fs::remove(out);
            single.push_back(st1.seconds.cast);
        }
        std::fprintf(stderr,
                     "bench generate: %s run %d/%d: cast %.3f s (plain rtcIntersect16 loop %.3f s, rtcIntersect1 "
                     "loop %.3f s), total %.3f s\n",
                     name.c_str(), k + 1, repeats, st.seconds.cast, plain16.back(), plain1.back(), st.seconds.total);
    }
    r.bvh = spread(bvh);
    r.cast = spread(cast);
    r.fuse = spread(fuse);
    r.ransac = spread(ransac);
    r.colour = spread(colour);
    r.write = spread(write);
    r.total = spread(total);
    const auto mrays = [&](const std::vector<double>& seconds) {
        std::vector<double> v;
        for (double t : seconds) v.push_back(double(r.rays) / t / 1e6);
        return spread(v);
    };
    r.gen_mrays = mrays(cast);
    r.plain16_mrays = mrays(plain16);
    r.plain1_mrays = mrays(plain1);
    r.single_mrays = mrays(single);
    return r;
}

// The skips on one scene: the same run with and without skip_rays, interleaved,
// in memory (no file), medians. RANSAC is never run on a view whose band has < 3 points
// (sim::findGround; no switch), so its figure is the RANSAC time and how many views
// skipped it.
struct SkipRow {
    std::string name;
    std::uint64_t rays = 0, traced = 0, points = 0, views_without_ransac = 0;
    int views = 0;
    Spread cast_on, cast_off, ransac, total_on, total_off;  // seconds
    bool same = true;
};

SkipRow skipRow(const std::string& name, const core::Scene& scene, sim::GenerateOptions o, int repeats) {
    SkipRow r;
    r.name = name;
    r.views = o.orbit.views;
    std::vector<double> cast_on, cast_off, ransac, total_on, total_off;
    for (int k = 0; k <= repeats; ++k) {  // k = 0: warm-up
        sim::GenerateStats on, off;
        o.skip_rays = true;
        const core::PointCloud a = sim::generateCloud(scene, o, &on);
        o.skip_rays = false;
        const core::PointCloud b = sim::generateCloud(scene, o, &off);
        r.same = r.same && a.points.size() == b.points.size() &&
                 std::equal(a.points.begin(), a.points.end(), b.points.begin(), [](const auto& x, const auto& y) {
                     return x.position == y.position && x.rgb == y.rgb && x.view == y.view;
                 });
        r.rays = on.rays;
        r.traced = on.rays_traced;
        r.points = on.points;
        r.views_without_ransac = on.views_without_ransac;
        if (k == 0) continue;
        cast_on.push_back(on.seconds.cast);
        cast_off.push_back(off.seconds.cast);
        ransac.push_back(on.seconds.ground);
        total_on.push_back(on.seconds.total);
        total_off.push_back(off.seconds.total);
    }
    r.cast_on = spread(cast_on);
    r.cast_off = spread(cast_off);
    r.ransac = spread(ransac);
    r.total_on = spread(total_on);
    r.total_off = spread(total_off);
    std::fprintf(stderr, "bench generate: skip %s: %llu of %llu rays traced, cast %.3f s vs %.3f s\n", name.c_str(),
                 (unsigned long long)r.traced, (unsigned long long)r.rays, r.cast_on.median, r.cast_off.median);
    return r;
}

std::string skipTable(const std::vector<SkipRow>& rows) {
    std::ostringstream s;
    s << "| scene / roles | rays | rays traced (skip on) | points | cast skip off (s) | cast skip on (s) | "
         "cast ratio off/on | total off (s) | total on (s) | RANSAC (s) | views without RANSAC | same cloud |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const SkipRow& r : rows)
        s << "| " << r.name << " | " << r.rays << " | " << r.traced
          << fmt(" (%.1f %%)", 100.0 * double(r.traced) / double(r.rays)) << " | " << r.points << " | "
          << fmtSpread("%.3f", r.cast_off) << " | " << fmtSpread("%.3f", r.cast_on) << " | "
          << fmt("%.2fx", r.cast_on.median > 0 ? r.cast_off.median / r.cast_on.median : 0.0)
          << spreadNote(r.cast_off, r.cast_on) << " | " << fmtSpread("%.3f", r.total_off) << " | "
          << fmtSpread("%.3f", r.total_on) << " | " << fmtSpread("%.3f", r.ransac) << " | " << r.views_without_ransac
          << " of " << r.views << " | " << (r.same ? "yes" : "NO") << " |\n";
    return s.str();
}

std::string percent(const std::optional<double>& v) { return v ? fmt("%.2f %%", 100.0 * *v) : "n/a"; }

// "1.23x" for a / b of the medians, marked when the two ranges overlap.
std::string ratio(const Spread& a, const Spread& b) {
    return fmt("%.2fx", b.median > 0 ? a.median / b.median : 0.0) + spreadNote(a, b);
}

std::string castTable(const std::vector<Result>& results) {
    std::ostringstream s;
    s << "| configuration | triangles | rays | rays traced by the generator | threads | plain rtcIntersect16 loop "
         "(Mrays/s) | plain rtcIntersect1 loop (Mrays/s) | generator cast, rtcIntersect16 (Mrays/s) | generator / "
         "plain rtcIntersect16 | generator / plain rtcIntersect1 | generator cast, rtcIntersect1 (Mrays/s) | "
         "that / plain rtcIntersect1 |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Result& r : results) {
        s << "| " << r.name << " | " << r.triangles << " | " << r.rays << " | " << r.rays_traced
          << fmt(" (%.1f %%)", 100.0 * double(r.rays_traced) / double(r.rays)) << " | " << r.threads << " | "
          << fmtSpread("%.2f", r.plain16_mrays) << " | " << fmtSpread("%.2f", r.plain1_mrays) << " | "
          << fmtSpread("%.2f", r.gen_mrays) << " | " << ratio(r.gen_mrays, r.plain16_mrays) << " | "
          << ratio(r.gen_mrays, r.plain1_mrays) << " | "
          << (r.single_mrays.n > 0 ? fmtSpread("%.2f", r.single_mrays) + " | " + ratio(r.single_mrays, r.plain1_mrays)
                                   : std::string("- | -"))
          << " |\n";
    }
    return s.str();
}

std::string stageTable(const std::vector<Result>& results) {
    std::ostringstream s;
    s << "| configuration | BVH s | cast s | fuse s | RANSAC s | colour s | write s | total s | peak RSS MiB "
         "|\n|---|---|---|---|---|---|---|---|---|\n";
    for (const Result& r : results)
        s << "| " << r.name << " | " << fmtSpread("%.3f", r.bvh) << " | " << fmtSpread("%.3f", r.cast) << " | "
          << fmtSpread("%.3f", r.fuse) << " | " << fmtSpread("%.3f", r.ransac) << " | " << fmtSpread("%.3f", r.colour)
          << " | " << fmtSpread("%.3f", r.write) << " | " << fmtSpread("%.3f", r.total) << " | "
          << fmt("%.0f", r.peak_rss_mib) << " |\n";
    return s.str();
}

// The large configuration against its goals: the whole run at most 3x the plain
// rtcIntersect16 loop over the same rays, and fusing no longer than casting.
std::string largeGoals(const Result& r) {
    const double plain_s = r.plain16_mrays.median > 0 ? double(r.rays) / (r.plain16_mrays.median * 1e6) : 0.0;
    std::string s = "large configuration: total " + fmt("%.2f", r.total.median) +
                    " s = " + fmt("%.2f", plain_s > 0 ? r.total.median / plain_s : 0.0) +
                    "x the plain rtcIntersect16 loop's " + fmt("%.2f", plain_s) + " s (goal <= 3x); fuse " +
                    fmt("%.2f", r.fuse.median) + " s against cast " + fmt("%.2f", r.cast.median) +
                    " s (goal fuse <= cast)\n";
    if (r.total_over_plain16.size() > 1) {
        // Each run against its own plain loop, so that a slower hour falls on both sides.
        const Spread ratio = spread(r.total_over_plain16);
        const auto within = std::size_t(std::count(r.fuse_within_cast.begin(), r.fuse_within_cast.end(), true));
        const auto met = std::size_t(
            std::count_if(r.total_over_plain16.begin(), r.total_over_plain16.end(), [](double x) { return x <= 3.0; }));
        s += "per run: total over its plain loop " + fmtSpread("%.2f", ratio) + "x, <= 3x in " + std::to_string(met) +
             " of " + std::to_string(ratio.n) + " runs; fuse <= cast in " + std::to_string(within) + " of " +
             std::to_string(r.fuse_within_cast.size()) + " runs\n";
    }
    return s;
}

std::string notes(const std::vector<Result>& results) {
    std::ostringstream s;
    for (const Result& r : results) {
        s << "- " << r.name << ": " << r.orbit.xres << "x" << r.orbit.yres << " px x " << r.orbit.views << " views; "
          << r.points << " points, " << r.misses << " misses; ground precision " << percent(r.precision) << ", recall "
          << percent(r.recall) << "; "
          << (r.in_output  ? "streamed into the output and coloured there"
              : r.streamed ? "streamed through a spool file"
                           : "fused in memory")
          << (r.packed_on_workers ? " (records packed by the workers)" : "") << ", output " << fmt("%.0f", r.output_mib)
          << " MiB binary PCD; scene preparation " << fmt("%.2f", r.prepare_s)
          << " s (not in total); RSS before the run " << fmt("%.0f", r.rss_before_mib) << " MiB"
          << (r.peak_reset ? "" : " (peak not resettable: whole-process peak)") << "; medians of " << r.repeats
          << " run(s)" << (r.warmed_up ? " after a warm-up" : "") << ".\n";
    }
    return s.str();
}

// The >= 100x configuration's scene: the demo subdivided to just above 2 M triangles
// (500,000 with --quick), same surfaces.
core::Scene largeScene(const core::Scene& demo, bool quick) {
    core::Scene big = demo;
    const std::size_t want = quick ? 500000 : 2000000;
    // Whole levels while they stay under the goal, then meshes one by one, smallest
    // first, until it is reached, so the scene lands just above `want` triangles.
    while (big.triangleCount() * 4 <= want)
        for (auto& m : big.meshes) m = subdivide(m);
    std::vector<std::size_t> order(big.meshes.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return big.meshes[a].triangles.size() < big.meshes[b].triangles.size();
    });
    for (std::size_t i : order) {
        if (big.triangleCount() >= want) break;
        big.meshes[i] = subdivide(big.meshes[i]);
    }
    return big;
}

sim::GenerateOptions largeOptions(const BenchGenerateCli& cli) {
    sim::GenerateOptions large;
    large.threads = cli.threads;
    large.orbit.xres = large.orbit.yres = cli.quick ? 256 : 512;
    large.orbit.views = cli.quick ? 100 : 400;
    large.memory_budget_bytes = std::size_t(64) << 20;  // far below the fused cloud: it streams
    return large;
}

std::string largeName(const BenchGenerateCli& cli) {
    return cli.quick ? "quick large: demo subdivided, 256x256 x 100 views"
                     : "large: demo subdivided, 512x512 x 400 views";
}

void run(const BenchGenerateCli& cli) {
    if (cli.threads < 0 || cli.threads > 1024)
        throw core::Error("bench generate: --threads = " + std::to_string(cli.threads) + ": allowed [0, 1024]");
    if (cli.repeats < 1 || cli.repeats > 100)
        throw core::Error("bench generate: --repeats = " + std::to_string(cli.repeats) + ": allowed [1, 100]");
    if (cli.large_repeats < 1 || cli.large_repeats > 100)
        throw core::Error("bench generate: --large-repeats = " + std::to_string(cli.large_repeats) +
                          ": allowed [1, 100]");
    if (cli.only == "sensors") {
        sim::GenerateOptions paper;
        paper.threads = cli.threads;
        benchSensorModels(io::loadScene(io::demoScenePath()), paper, cli.quick, true,
                          cli.no_md ? std::string() : cli.md);
        return;
    }
    const fs::path dir = cli.tmp.empty() ? fs::temp_directory_path() / ("ladarvr_bench_" + std::to_string(::getpid()))
                                         : fs::path(cli.tmp);
    fs::create_directories(dir);
    if (cli.only == "runs") {
        const FormatRuns runs =
            benchFormatRuns(largeScene(io::loadScene(io::demoScenePath()), cli.quick), largeOptions(cli), dir);
        std::printf("%s\n%s\n", runs.table.c_str(), runs.verdict.c_str());
        std::error_code ec;
        fs::remove_all(dir, ec);
        return;
    }
    if (cli.only == "large") {
        const core::Scene big = largeScene(io::loadScene(io::demoScenePath()), cli.quick);
        const Result r =
            runConfig(largeName(cli), big, largeOptions(cli), cli.large_repeats, false, false, dir / "bench.pcd");
        std::printf("%s\n%s\n%s%s\n", castTable({r}).c_str(), stageTable({r}).c_str(), notes({r}).c_str(),
                    largeGoals(r).c_str());
        std::error_code ec;
        fs::remove_all(dir, ec);
        return;
    }
    if (cli.only == "formats") {
        benchFormats(largeScene(io::loadScene(io::demoScenePath()), cli.quick), largeOptions(cli), dir, largeName(cli),
                     cli.no_md ? "" : cli.md);
        std::error_code ec;
        fs::remove_all(dir, ec);
        return;
    }
    const fs::path out = dir / "bench.pcd";
    const auto start = Clock::now();
    std::vector<Result> results;

    // 1. The paper's configuration on the demo scene, fused in memory.
    auto t0 = Clock::now();
    const core::Scene demo = io::loadScene(io::demoScenePath());
    const double demo_load_s = secondsSince(t0);
    sim::GenerateOptions paper;
    paper.threads = cli.threads;
    results.push_back(
        runConfig("paper: demo scene, 128x128 x 100 views", demo, paper, cli.quick ? 2 : cli.repeats, true, true, out));
    results.back().prepare_s = demo_load_s;

    // Skips: the paper's orbit on the demo scene by roles; the metric's P1/P2
    // clouds use target,environment. Last: C 300 m off the scene, where no view sees it.
    std::vector<SkipRow> skips;
    {
        const int reps = cli.quick ? 3 : 7;
        sim::GenerateOptions o = paper;
        skips.push_back(skipRow("demo, all roles", demo, o, reps));
        o.roles = core::RoleMask::parse("target,environment", "bench");
        skips.push_back(skipRow("demo, target,environment", demo, o, reps));
        o.roles = core::RoleMask::parse("target", "bench");
        skips.push_back(skipRow("demo, target", demo, o, reps));
        o.roles = core::RoleMask::all();
        o.centre = sim::defaultCentre(demo) + glm::dvec3(300.0, 0.0, 0.0);
        skips.push_back(skipRow("demo, all roles, C 300 m off the scene", demo, o, reps));
    }
    const std::string skip_tbl = skipTable(skips);
    benchSensorModels(demo, paper, cli.quick, false, cli.no_md ? std::string() : cli.md);

    // 2. >= 100x larger: 512x512 x 400 views (64x the rays) on the demo scene subdivided to
    // >= 2 M triangles (same surfaces), streamed to disk (into the binary PCD itself).
    t0 = Clock::now();
    const core::Scene big = largeScene(demo, cli.quick);
    const double big_prepare_s = demo_load_s + secondsSince(t0);
    const sim::GenerateOptions large = largeOptions(cli);
    const std::string large_name = largeName(cli);
    results.push_back(runConfig(large_name, big, large, 1, false, false, out));
    results.back().prepare_s = big_prepare_s;
    benchFormats(big, large, dir, large_name, cli.no_md ? "" : cli.md);
    std::error_code ec;
    fs::remove_all(dir, ec);

    const std::string tbl = castTable(results) + "\n" + stageTable(results);
    std::printf("%s\n%s\n%s", tbl.c_str(), notes(results).c_str(), skip_tbl.c_str());
    const Result& p = results.front();
    std::printf(
        "paper configuration: cast %s the plain rtcIntersect16 loop (goal >= 0.95x), %s the plain "
        "rtcIntersect1 loop; whole run %.3f s (BVH + cast + fuse + RANSAC + colour + write; goal < 1 s) "
        "+ %.3f s scene load\n",
        ratio(p.gen_mrays, p.plain16_mrays).c_str(), ratio(p.gen_mrays, p.plain1_mrays).c_str(), p.total.median,
        p.prepare_s);

    if (!cli.no_md) {
        const std::string date = utcNow();
        std::ostringstream s;
        s << "## Generator (ladarvr bench generate)\n\n"
          << "Command: `./ladarvr bench generate" << (cli.quick ? " --quick" : "")
          << "`; machine: " << std::thread::hardware_concurrency() << " cores, " << cpuName() << "; " << date << "; "
          << fmt("%.0f", secondsSince(start)) << " s in all.\n\n"
          << "Ray casting: the generator's cast stage (rays made on the fly, traced as rtcIntersect16 "
             "packets of 16 consecutive pixels of a row, hits stored per pixel; and, in the last two columns, "
             "one ray at a time) against two plain loops over the same rays (precomputed), the same BVH and "
             "the same thread count: rtcIntersect16 packets of 16 consecutive pixels of a row (the limit for "
             "the generator's packets) and rtcIntersect1 per ray. The baselines run on each generator run's "
             "BVH, interleaved with it: right after it on even runs, right before it on odd runs. "
             "Throughputs count every pixel of every view; the generator casts only the rays its skips keep "
             "(column 'rays traced'), the plain loops cast them all. Ratios are of medians; '(within "
             "spread)' marks a ratio whose two measurements' min..max ranges overlap, i.e. one the run-to-run "
             "noise could explain. Every figure is 'median [min..max]' over the runs (the median alone for a "
             "single run). Stages: BVH = Embree build; fuse = per-view compaction and appending (to the output or "
             "the spool file when streamed); colour includes reading the points back; total = BVH + cast + fuse + "
             "RANSAC "
             "+ colour + write (scene loading excluded, given per row). Peak RSS = VmHWM, reset just "
             "before the run (so it includes the scene and its BVH). The machine's 2 cores were shared "
             "with other jobs: read ratios rather than lone times.\n\n"
          << tbl << "\n"
          << notes(results) << "\n"
          << "Skips, paper orbit (128x128 x 100 views), in memory, medians of " << (cli.quick ? 3 : 7)
          << " interleaved runs after a warm-up. Skip on: only the pixels whose rays "
             "can meet the bounds of the ray-cast meshes are traced (docs/generator.md); off: "
             "`--no-skip-rays`. RANSAC is never run on a view whose height band has < 3 points (no "
             "switch); its time is that of the skip-on run. Same cloud: positions, colours and views "
             "equal point by point. Figures are 'median [min..max]'; '(within spread)' marks a ratio "
             "whose two ranges overlap.\n\n"
          << skip_tbl << "\n";
        replaceMarkdownSection(cli.md, "## Generator (ladarvr bench generate)", s.str());
        std::fprintf(stderr, "bench generate: wrote the section to %s\n", cli.md.c_str());
    }
}

}  // namespace

void registerGenerate(CLI::App& parent) {
    auto state = std::make_shared<BenchGenerateCli>();
    CLI::App* c = parent.add_subcommand("generate",
                                        "generator throughput vs plain rtcIntersect16 and rtcIntersect1 "
                                        "loops, time per stage, paper config and a >= 100x larger "
                                        "streamed one");
    c->add_flag("--quick", state->quick, "smaller large configuration, 2 repeats (a smoke run)");
    c->add_option("--threads", state->threads, "threads for the generator and the plain loops, 0 = all")
        ->capture_default_str();
    c->add_option("--repeats", state->repeats, "timed runs of the paper configuration (medians)")
        ->capture_default_str();
    c->add_option("--large-repeats", state->large_repeats,
                  "timed runs of the large configuration with --only large (medians, and each run against its own "
                  "plain loop)")
        ->capture_default_str();
    c->add_option("--md", state->md, "markdown file whose generator section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print only, leave BENCHMARKS.md alone");
    c->add_option("--only", state->only,
                  "run only these rows: 'sensors' (the sensor models' table), 'formats' (the writers against "
                  "binary PCD on the large configuration, then whole runs to LAZ and COPC), 'runs' (those whole "
                  "runs alone, printed) or 'large' (the large configuration's stages and its plain loop, printed)")
        ->check(CLI::IsMember({"sensors", "formats", "runs", "large"}));
    c->add_option("--tmp", state->tmp, "scratch directory for the outputs (default: a temporary one)");
    c->callback([state] { run(*state); });
}

}  // namespace bench
