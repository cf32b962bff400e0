// bench/src/generate.cpp: `ladarvr bench generate`: the generator's ray-casting
// throughput against a plain rtcIntersect1 loop over the same rays and the same BVH (the
// Embree limit on this machine), and the time of every stage, on the paper's
// configuration (demo scene) and on one >= 100x larger that streams to disk.
// Warm-up, repeats, medians; the section "## Generator (ladarvr bench generate)" of
// BENCHMARKS.md is rewritten with the table, the command and the machine.
#include "common.hpp"
#include "plain_loop.hpp"
#include "register.hpp"

#include <engine/atomic_file.hpp>
#include <engine/error.hpp>
#include <engine/scene.hpp>
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
engine::Mesh subdivide(const engine::Mesh& m) {
    engine::Mesh out;
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
    double prepare_s = 0;                     // scene load (and subdivision)
    std::uint64_t rays = 0, points = 0, misses = 0;
    double bvh = 0, cast = 0, fuse = 0, ransac = 0, colour = 0, write = 0, total = 0;  // medians
    double plain_cast = 0;                    // median of the plain rtcIntersect1 loop
    double single_cast = 0;                   // median cast stage with packet_rays = false (0: not run)
    bool streamed = false;
    double peak_rss_mib = 0, rss_before_mib = 0;
    bool peak_reset = false;
    double output_mib = 0;
    std::optional<double> precision, recall;
};

// The plain loop over every ray of every view (plain_loop.hpp). Rays are made per batch
// of views (not timed); only the intersect loops are timed.
double plainLoopAllViews(const sim::Generator& g, int threads) {
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
        seconds += plainLoopSeconds(g.caster(), rays, hits, threads);
    }
    return seconds;
}

Result runConfig(const std::string& name, const engine::Scene& scene, const sim::GenerateOptions& options,
                 int repeats, bool warm_up, bool single_too, const fs::path& out) {
    Result r;
    r.name = name;
    r.orbit = options.orbit;
    r.repeats = repeats;
    std::vector<double> bvh, cast, fuse, ransac, colour, write, total, plain, single;
    if (warm_up) {
        sim::Generator g(scene, options);
        g.run(out, engine::CloudFormat::PcdBinary);
        fs::remove(out);
        plainLoopAllViews(g, options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency())));
    }
    for (int k = 0; k < repeats; ++k) {
        r.rss_before_mib = statusMiB("VmRSS:");
        r.peak_reset = resetPeakRss();
        sim::GenerateStats st;
        sim::Generator g(scene, options);
        g.run(out, engine::CloudFormat::PcdBinary, &st);
        r.peak_rss_mib = std::max(r.peak_rss_mib, statusMiB("VmHWM:"));
        r.output_mib = double(fs::file_size(out)) / 1048576.0;
        fs::remove(out);
        bvh.push_back(st.seconds.bvh);
        cast.push_back(st.seconds.cast);
        fuse.push_back(st.seconds.fuse);
        ransac.push_back(st.seconds.ransac);
        colour.push_back(st.seconds.colour);
        write.push_back(st.seconds.write);
        total.push_back(st.seconds.total);
        r.triangles = st.triangles;
        r.threads = st.threads;
        r.rays = st.rays;
        r.points = st.points;
        r.misses = st.misses;
        r.streamed = st.streamed;
        r.precision = st.ground_precision;
        r.recall = st.ground_recall;
        // The baseline right after, on the same BVH, same rays, same thread count.
        plain.push_back(plainLoopAllViews(g, st.threads));
        if (single_too) {  // the generator tracing one ray at a time (rtcIntersect1)
            sim::GenerateOptions one = options;
            one.packet_rays = false;
            sim::GenerateStats st1;
            sim::Generator(scene, one).run(out, engine::CloudFormat::PcdBinary, &st1);
            fs::remove(out);
            single.push_back(st1.seconds.cast);
        }
        std::fprintf(stderr, "bench generate: %s run %d/%d: cast %.3f s (plain loop %.3f s), total %.3f s\n",
                     name.c_str(), k + 1, repeats, st.seconds.cast, plain.back(), st.seconds.total);
    }
    r.bvh = median(bvh);
    r.cast = median(cast);
    r.fuse = median(fuse);
    r.ransac = median(ransac);
    r.colour = median(colour);
    r.write = median(write);
    r.total = median(total);
    r.plain_cast = median(plain);
    r.single_cast = median(single);
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
    double cast_on = 0, cast_off = 0, ransac = 0, total_on = 0, total_off = 0;
    bool same = true;
};

SkipRow skipRow(const std::string& name, const engine::Scene& scene, sim::GenerateOptions o, int repeats) {
    SkipRow r;
    r.name = name;
    r.views = o.orbit.views;
    std::vector<double> cast_on, cast_off, ransac, total_on, total_off;
    for (int k = 0; k <= repeats; ++k) {  // k = 0: warm-up
        sim::GenerateStats on, off;
        o.skip_rays = true;
        const engine::PointCloud a = sim::generateCloud(scene, o, &on);
        o.skip_rays = false;
        const engine::PointCloud b = sim::generateCloud(scene, o, &off);
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
        ransac.push_back(on.seconds.ransac);
        total_on.push_back(on.seconds.total);
        total_off.push_back(off.seconds.total);
    }
    r.cast_on = median(cast_on);
    r.cast_off = median(cast_off);
    r.ransac = median(ransac);
    r.total_on = median(total_on);
    r.total_off = median(total_off);
    std::fprintf(stderr, "bench generate: skip %s: %llu of %llu rays traced, cast %.3f s vs %.3f s\n", name.c_str(),
                 (unsigned long long)r.traced, (unsigned long long)r.rays, r.cast_on, r.cast_off);
    return r;
}

std::string skipTable(const std::vector<SkipRow>& rows) {
    std::ostringstream s;
    s << "| scene / roles | rays | rays traced (skip on) | points | cast skip off (s) | cast skip on (s) | "
         "cast ratio off/on | total off (s) | total on (s) | RANSAC (s) | views without RANSAC | same cloud |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const SkipRow& r : rows)
        s << "| " << r.name << " | " << r.rays << " | " << r.traced << fmt(" (%.1f %%)", 100.0 * double(r.traced) / double(r.rays))
          << " | " << r.points << " | " << fmt("%.3f", r.cast_off) << " | " << fmt("%.3f", r.cast_on) << " | "
          << fmt("%.2fx", r.cast_on > 0 ? r.cast_off / r.cast_on : 0.0) << " | " << fmt("%.3f", r.total_off) << " | "
          << fmt("%.3f", r.total_on) << " | " << fmt("%.3f", r.ransac) << " | " << r.views_without_ransac << " of "
          << r.views << " | " << (r.same ? "yes" : "NO") << " |\n";
    return s.str();
}

std::string percent(const std::optional<double>& v) { return v ? fmt("%.2f %%", 100.0 * *v) : "n/a"; }

std::string table(const std::vector<Result>& results) {
    std::ostringstream s;
    s << "| configuration | triangles | rays | threads | plain rtcIntersect1 loop (Mrays/s) | generator cast, "
         "rtcIntersect16 (Mrays/s) | ratio | generator cast, rtcIntersect1 (Mrays/s) | BVH s | cast s | fuse s | "
         "RANSAC s | colour s | write s | total s | peak RSS MiB "
         "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Result& r : results) {
        const double plain_mrays = double(r.rays) / r.plain_cast / 1e6;
        const double gen_mrays = double(r.rays) / r.cast / 1e6;
        s << "| " << r.name << " | " << r.triangles << " | " << r.rays << " | " << r.threads << " | "
          << fmt("%.2f", plain_mrays) << " | " << fmt("%.2f", gen_mrays) << " | "
          << fmt("%.2fx", gen_mrays / plain_mrays) << " | "
          << (r.single_cast > 0 ? fmt("%.2f", double(r.rays) / r.single_cast / 1e6) + fmt(" (%.2fx)", plain_mrays > 0 ? (double(r.rays) / r.single_cast / 1e6) / plain_mrays : 0.0) : std::string("-"))
          << " | " << fmt("%.3f", r.bvh) << " | "
          << fmt("%.3f", r.cast) << " | " << fmt("%.3f", r.fuse) << " | " << fmt("%.3f", r.ransac) << " | "
          << fmt("%.3f", r.colour) << " | " << fmt("%.3f", r.write) << " | " << fmt("%.3f", r.total) << " | "
          << fmt("%.0f", r.peak_rss_mib) << " |\n";
    }
    return s.str();
}

std::string notes(const std::vector<Result>& results) {
    std::ostringstream s;
    for (const Result& r : results) {
        s << "- " << r.name << ": " << r.orbit.xres << "x" << r.orbit.yres << " px x " << r.orbit.views
          << " views; " << r.points << " points, " << r.misses << " misses; ground precision "
          << percent(r.precision) << ", recall " << percent(r.recall) << "; "
          << (r.streamed ? "streamed through a spool file" : "fused in memory") << ", output "
          << fmt("%.0f", r.output_mib) << " MiB binary PCD; scene preparation " << fmt("%.2f", r.prepare_s)
          << " s (not in total); RSS before the run " << fmt("%.0f", r.rss_before_mib) << " MiB"
          << (r.peak_reset ? "" : " (peak not resettable: whole-process peak)") << "; medians of "
          << r.repeats << " run(s)" << (r.repeats > 1 ? " after a warm-up" : "") << ".\n";
    }
    return s.str();
}

void run(const BenchGenerateCli& cli) {
    if (cli.threads < 0 || cli.threads > 1024)
        throw engine::Error("bench generate: --threads = " + std::to_string(cli.threads) + ": allowed [0, 1024]");
    if (cli.repeats < 1 || cli.repeats > 100)
        throw engine::Error("bench generate: --repeats = " + std::to_string(cli.repeats) + ": allowed [1, 100]");
    const fs::path dir = cli.tmp.empty() ? fs::temp_directory_path() / ("ladarvr_bench_" + std::to_string(::getpid()))
                                         : fs::path(cli.tmp);
    fs::create_directories(dir);
    const fs::path out = dir / "bench.pcd";
    const auto start = Clock::now();
    std::vector<Result> results;

    // 1. The paper's configuration on the demo scene, fused in memory.
    auto t0 = Clock::now();
    const engine::Scene demo = engine::loadScene(engine::demoScenePath());
    const double demo_load_s = secondsSince(t0);
    sim::GenerateOptions paper;
    paper.threads = cli.threads;
    results.push_back(runConfig("paper: demo scene, 128x128 x 100 views", demo, paper,
                                cli.quick ? 2 : cli.repeats, true, true, out));
    results.back().prepare_s = demo_load_s;

    // Skips: the paper's orbit on the demo scene by roles; the metric's P1/P2
    // clouds use target,environment. Last: C 300 m off the scene, where no view sees it.
    std::vector<SkipRow> skips;
    {
        const int reps = cli.quick ? 3 : 7;
        sim::GenerateOptions o = paper;
        skips.push_back(skipRow("demo, all roles", demo, o, reps));
        o.roles = engine::RoleMask::parse("target,environment", "bench");
        skips.push_back(skipRow("demo, target,environment", demo, o, reps));
        o.roles = engine::RoleMask::parse("target", "bench");
        skips.push_back(skipRow("demo, target", demo, o, reps));
        o.roles = engine::RoleMask::all();
        o.centre = sim::defaultCentre(demo) + glm::dvec3(300.0, 0.0, 0.0);
        skips.push_back(skipRow("demo, all roles, C 300 m off the scene", demo, o, reps));
    }
    const std::string skip_tbl = skipTable(skips);

    // 2. >= 100x larger: 512x512 x 400 views (64x the rays) on the demo scene subdivided to
    // >= 2 M triangles (same surfaces), streamed to disk through the spool file.
    t0 = Clock::now();
    engine::Scene big = demo;
    const std::size_t want = cli.quick ? 500000 : 2000000;
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
    const double big_prepare_s = demo_load_s + secondsSince(t0);
    sim::GenerateOptions large;
    large.threads = cli.threads;
    large.orbit.xres = large.orbit.yres = cli.quick ? 256 : 512;
    large.orbit.views = cli.quick ? 100 : 400;
    large.memory_budget_bytes = std::size_t(64) << 20;  // far below the fused cloud: it streams
    const std::string large_name = cli.quick ? "quick large: demo subdivided, 256x256 x 100 views"
                                             : "large: demo subdivided, 512x512 x 400 views";
    results.push_back(runConfig(large_name, big, large, 1, false, false, out));
    results.back().prepare_s = big_prepare_s;
    std::error_code ec;
    fs::remove_all(dir, ec);

    const std::string tbl = table(results);
    std::printf("%s\n%s\n%s", tbl.c_str(), notes(results).c_str(), skip_tbl.c_str());
    const Result& p = results.front();
    std::printf("paper configuration: cast %.2fx the plain rtcIntersect1 loop (goal >= 0.9x); whole run %.3f s "
                "(BVH + cast + fuse + RANSAC + colour + write; goal < 1 s) + %.3f s scene load\n",
                (double(p.rays) / p.cast) / (double(p.rays) / p.plain_cast), p.total, p.prepare_s);

    if (!cli.no_md) {
        const std::string date = utcNow();
        std::ostringstream s;
        s << "## Generator (ladarvr bench generate)\n\n"
          << "Command: `./ladarvr bench generate" << (cli.quick ? " --quick" : "") << "`; machine: "
          << std::thread::hardware_concurrency() << " cores, " << cpuName() << "; " << date << "; "
          << fmt("%.0f", secondsSince(start)) << " s in all.\n\n"
          << "Ray casting: the generator's cast stage (rays made on the fly, traced as rtcIntersect16 "
             "packets of 16 pixels, hits stored per pixel; and, in the rtcIntersect1 column, one ray at a "
             "time) against a plain loop of rtcIntersect1 over the same rays (precomputed), same BVH, same "
             "thread count, run right after each generator run; ratio = generator / plain throughput. "
             "Stages: BVH = Embree build; fuse = per-view compaction and appending (to the spool file "
             "when streamed); colour includes reading the spool back; total = BVH + cast + fuse + RANSAC "
             "+ colour + write (scene loading excluded, given per row). Peak RSS = VmHWM, reset just "
             "before the run (so it includes the scene and its BVH). The machine's 2 cores were shared "
             "with other jobs: read ratios rather than lone times.\n\n"
          << tbl << "\n" << notes(results) << "\n"
          << "Skips, paper orbit (128x128 x 100 views), in memory, medians of "
          << (cli.quick ? 3 : 7) << " interleaved runs after a warm-up. Skip on: only the pixels whose rays "
             "can meet the bounds of the ray-cast meshes are traced (docs/generator.md); off: "
             "`--no-skip-rays`. RANSAC is never run on a view whose height band has < 3 points (no "
             "switch); its time is that of the skip-on run. Same cloud: positions, colours and views "
             "equal point by point.\n\n"
          << skip_tbl << "\n";
        replaceMarkdownSection(cli.md, "## Generator (ladarvr bench generate)", s.str());
        std::fprintf(stderr, "bench generate: wrote the section to %s\n", cli.md.c_str());
    }
}

}  // namespace

void registerGenerate(CLI::App& parent) {
    auto state = std::make_shared<BenchGenerateCli>();
    CLI::App* c = parent.add_subcommand("generate", "generator throughput vs a plain rtcIntersect1 loop, time per "
                                                   "stage, paper config and a >= 100x larger streamed one");
    c->add_flag("--quick", state->quick, "smaller large configuration, 2 repeats (a smoke run)");
    c->add_option("--threads", state->threads, "threads for both the generator and the plain loop, 0 = all")
        ->capture_default_str();
    c->add_option("--repeats", state->repeats, "timed runs of the paper configuration (medians)")
        ->capture_default_str();
    c->add_option("--md", state->md, "markdown file whose generator section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print only, leave BENCHMARKS.md alone");
    c->add_option("--tmp", state->tmp, "scratch directory for the outputs (default: a temporary one)");
    c->callback([state] { run(*state); });
}

}  // namespace bench
