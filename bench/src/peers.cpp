// bench/src/peers.cpp: `ladarvr bench peers`: our code side by side with peer
// libraries in one run, on the same scene and the same data:
//   1. ray casting: the generator's cast stage (rtcIntersect16 packets) and a plain
//      rtcIntersect1 loop (sim::RayCaster::intersect) against Open3D's RaycastingScene
//      (scripts/peer_open3d.py) on the same triangles and the same 1.64 M rays, with the
//      hit agreement;
//   2. binary PCD write and read of the paper's 1.64 M-point cloud against PCL's
//      savePCDFileBinary / loadPCDFile (same fields), and each reading the other's file;
//   3. ground whitening (paper §III-C, iterative RANSAC per view, and our SMRF and CSF
//      on the whole cloud) against PCL's progressive morphological filter: precision, recall
//      and time on the demo, hilly and slopes scenes, against the generator's
//      ground-truth labels.
// A program, not a test: warm-up, repeats, medians, ratios; the section
// "## Peers (ladarvr bench peers)" of BENCHMARKS.md is rewritten.
#include "peers_pcl.hpp"
#include "common.hpp"
#include "plain_loop.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>
#include <sim/generator.hpp>
#include <sim/raycaster.hpp>

#include <nlohmann/json.hpp>

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
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

struct BenchPeersCli {
    bool quick = false;
    int threads = 0;
    int repeats = 5;
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
    std::string python = "python3";
    std::string open3d_script;  // default: <source>/scripts/peer_open3d.py
    std::string tmp;
    int pmf_stride = 0;  // 0: from the point budget below
    bool no_sensors = false;
};

struct RayResult {
    std::uint64_t rays = 0;
    std::size_t triangles = 0;
    double generator_cast_s = 0, plain_s = 0, open3d_s = 0;
    std::string open3d_version;
    double same_hit_fraction = 0;
    std::uint64_t both_hit = 0, differ_1mm = 0;
    double dt_median_m = 0, dt_p99_m = 0, dt_max_m = 0;
};

RayResult rayCasting(const core::Scene& scene, const sim::GenerateOptions& options, const BenchPeersCli& cli,
                     int threads, const fs::path& dir) {
    RayResult r;
    sim::Generator g(scene, options);
    // All rays of the orbit, in output order.
    std::vector<sim::Ray> rays, view_rays;
    for (int v = 0; v < options.orbit.views; ++v) {
        g.viewRays(v, view_rays);
        rays.insert(rays.end(), view_rays.begin(), view_rays.end());
    }
    r.rays = rays.size();
    r.triangles = g.caster().triangleCount();

    // Ours: the generator's cast stage (fresh generator per run: its BVH is built in the
    // constructor, outside the cast stage) and the plain loop on the same BVH.
    const int repeats = cli.quick ? 3 : cli.repeats;
    std::vector<double> gen, plain;
    std::vector<sim::Hit> hits;
    plainLoopSeconds(g.caster(), rays, hits, threads);  // warm-up
    for (int k = 0; k < repeats + 1; ++k) {
        sim::GenerateStats st;
        sim::GenerateOptions o = options;
        o.white = true;  // no RANSAC: only the cast stage is compared
        sim::Generator(scene, o).run(&st);
        if (k > 0) gen.push_back(st.seconds.cast);  // the first is the warm-up
        plain.push_back(plainLoopSeconds(g.caster(), rays, hits, threads));
    }
    r.generator_cast_s = median(gen);
    r.plain_s = median(plain);

    // Open3D: dump the same triangles (the meshes the generator casts, merged) and rays.
    const fs::path dump = dir / "rays.bin", out_hits = dir / "open3d_hits.bin";
    {
        std::vector<float> vertices;
        std::vector<std::uint32_t> indices;
        for (const core::Mesh& m : scene.meshes) {
            if (!options.roles.has(m.role)) continue;
            const std::uint32_t base = std::uint32_t(vertices.size() / 3);
            for (const glm::vec3& v : m.vertices) vertices.insert(vertices.end(), {v.x, v.y, v.z});
            for (const glm::uvec3& t : m.triangles) indices.insert(indices.end(), {base + t.x, base + t.y, base + t.z});
        }
        std::ofstream f(dump, std::ios::binary);
        const std::uint64_t counts[3] = {vertices.size() / 3, indices.size() / 3, rays.size()};
        f.write("LVRAYS01", 8);
        f.write(reinterpret_cast<const char*>(counts), sizeof counts);
        f.write(reinterpret_cast<const char*>(vertices.data()), std::streamsize(vertices.size() * 4));
        f.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(indices.size() * 4));
        std::vector<float> buf;
        buf.reserve(rays.size() * 6);
        for (const sim::Ray& ray : rays)
            buf.insert(buf.end(),
                       {ray.origin.x, ray.origin.y, ray.origin.z, ray.direction.x, ray.direction.y, ray.direction.z});
        f.write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size() * 4));
        if (!f) throw core::Error("bench peers: cannot write the ray dump " + dump.string());
    }
    const fs::path script =
        cli.open3d_script.empty() ? sourceRoot() / "scripts" / "peer_open3d.py" : fs::path(cli.open3d_script);
    const std::string cmd = cli.python + " '" + script.string() + "' '" + dump.string() + "' '" + out_hits.string() +
                            "' --repeats " + std::to_string(repeats) + " --threads " + std::to_string(threads);
    std::string output;
    if (FILE* p = ::popen(cmd.c_str(), "r")) {
        char buf[4096];
        while (std::fgets(buf, sizeof buf, p)) output += buf;
        if (::pclose(p) != 0)
            throw core::Error("bench peers: '" + cmd +
                              "' failed (is python3-open3d installed? it is in "
                              "BENCH_PACKAGES of ./ladarvr): " +
                              output);
    } else {
        throw core::Error("bench peers: cannot run '" + cmd + "'");
    }
    const auto line = output.rfind('{');
    if (line == std::string::npos) throw core::Error("bench peers: no JSON from " + script.string() + ": " + output);
    const nlohmann::json j = nlohmann::json::parse(output.substr(line));
    r.open3d_s = j.at("median_s").get<double>();
    r.open3d_version = j.at("open3d").get<std::string>();

    // Agreement of the plain loop's hits with Open3D's t_hit (inf = miss).
    std::vector<float> t3(rays.size());
    {
        std::ifstream f(out_hits, std::ios::binary);
        f.read(reinterpret_cast<char*>(t3.data()), std::streamsize(t3.size() * 4));
        if (!f) throw core::Error("bench peers: " + out_hits.string() + " is short");
    }
    std::uint64_t same = 0;
    std::vector<double> dt;
    dt.reserve(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const bool a = hits[i].hit(), b = std::isfinite(t3[i]);
        same += a == b;
        if (a && b) {
            const double d = std::abs(double(hits[i].t) - double(t3[i]));
            dt.push_back(d);
            r.differ_1mm += d > 1e-3;
        }
    }
    r.same_hit_fraction = double(same) / double(rays.size());
    r.both_hit = dt.size();
    r.dt_median_m = median(dt);
    r.dt_p99_m = quantile(dt, 0.99);
    r.dt_max_m = dt.empty() ? 0.0 : *std::max_element(dt.begin(), dt.end());
    fs::remove(dump);
    fs::remove(out_hits);
    return r;
}

struct IoResult {
    std::size_t points = 0;
    double ours_write_s = 0, ours_read_s = 0, pcl_write_s = 0, pcl_read_s = 0;
    double file_mib = 0;
    bool pcl_reads_ours = false, ours_reads_pcl = false, pcl_round_trip = false;
};

IoResult pcdIo(const core::PointCloud& cloud, int repeats, const fs::path& dir) {
    IoResult r;
    r.points = cloud.points.size();
    const fs::path ours = dir / "ours.pcd", theirs = dir / "pcl.pcd";
    std::vector<double> ow, orr, pw, pr;
    for (int k = 0; k < repeats + 1; ++k) {  // k = 0 is the warm-up
        fs::remove(ours);
        auto t0 = Clock::now();
        io::writeCloud(ours, cloud, io::CloudFormat::PcdBinary);
        const double w = secondsSince(t0);
        t0 = Clock::now();
        const core::PointCloud back = io::readCloud(ours);
        const double rd = secondsSince(t0);
        if (back.points.size() != cloud.points.size())
            throw core::Error("bench peers: our reader read " + std::to_string(back.points.size()) + " points");
        const peers::PclIo p = peers::pclWriteRead(cloud, theirs);
        if (k > 0) {
            ow.push_back(w);
            orr.push_back(rd);
            pw.push_back(p.write_s);
            pr.push_back(p.read_s);
        }
        r.pcl_round_trip = p.same_points;
    }
    r.ours_write_s = median(ow);
    r.ours_read_s = median(orr);
    r.pcl_write_s = median(pw);
    r.pcl_read_s = median(pr);
    r.file_mib = double(fs::file_size(ours)) / 1048576.0;
    // Each reads the other's file.
    std::size_t n = 0;
    r.pcl_reads_ours = peers::pclReadsOurs(ours, cloud, &n);
    const core::PointCloud from_pcl = io::readCloud(theirs);
    r.ours_reads_pcl = from_pcl.points.size() == cloud.points.size();
    for (std::size_t i = 0; r.ours_reads_pcl && i < cloud.points.size(); ++i) {
        const auto &a = from_pcl.points[i], &b = cloud.points[i];
        r.ours_reads_pcl = a.position == b.position && a.rgb == b.rgb && a.label == b.label && a.view == b.view &&
                           a.range_m == b.range_m;
    }
    fs::remove(ours);
    fs::remove(theirs);
    return r;
}

// One ground method's figures from a generate run's stats.
struct MethodFigures {
    double s = 0, precision = 0, recall = 0, kept = 0, environment_kept = 0;
};

MethodFigures figures(const sim::GenerateStats& st) {
    return {st.seconds.ground, st.ground_precision.value_or(std::nan("")), st.ground_recall.value_or(std::nan("")),
            st.target_kept.value_or(std::nan("")), st.environment_kept.value_or(std::nan(""))};
}

struct GroundResult {
    std::string scene;
    std::size_t points = 0, pmf_points = 0;
    int pmf_stride = 1;
    MethodFigures ransac, smrf, csf;  // in the order of kGroundMethods
    double pmf_s = 0, pmf_precision = 0, pmf_recall = 0;
    int threads = 1;
};

constexpr std::pair<sim::GroundMethod, const char*> kGroundMethods[] = {
    {sim::GroundMethod::Ransac, "RANSAC"}, {sim::GroundMethod::Smrf, "SMRF"}, {sim::GroundMethod::Csf, "CSF"}};

GroundResult ground(const std::string& name, const core::Scene& scene, const sim::GenerateOptions& options,
                    std::size_t pmf_budget, int stride_option) {
    GroundResult r;
    r.scene = name;
    sim::GenerateStats st;
    const core::PointCloud cloud = sim::generateCloud(scene, options, &st);
    r.points = cloud.points.size();
    r.threads = st.threads;
    r.ransac = figures(st);
    {
        sim::GenerateOptions other = options;
        sim::GenerateStats ss;
        other.ground.method = sim::GroundMethod::Smrf;
        sim::generateCloud(scene, other, &ss);
        r.smrf = figures(ss);
        other.ground.method = sim::GroundMethod::Csf;
        sim::generateCloud(scene, other, &ss);
        r.csf = figures(ss);
    }
    // PMF's morphological opening searches a box per point per window: on 1.6 M points
    // at ~130 points/m^2 that is beyond reach, so it gets every k-th point (airborne Lidar
    // density, a few points per m^2) and is scored on those points.
    r.pmf_stride = stride_option > 0
                       ? stride_option
                       : int(std::max<std::size_t>(1, (cloud.points.size() + pmf_budget - 1) / pmf_budget));
    std::vector<glm::vec3> pts;
    std::vector<std::uint8_t> truth;
    for (std::size_t i = 0; i < cloud.points.size(); i += std::size_t(r.pmf_stride)) {
        pts.push_back(cloud.points[i].position);
        truth.push_back(cloud.points[i].label == core::Role::Ground);
    }
    r.pmf_points = pts.size();
    const auto flags = peers::pclGroundPmf(pts, peers::PmfOptions{}, &r.pmf_s);
    std::size_t found = 0, tp = 0, gt = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        found += flags[i];
        gt += truth[i];
        tp += flags[i] && truth[i];
    }
    r.pmf_precision = found ? double(tp) / double(found) : std::nan("");
    r.pmf_recall = gt ? double(tp) / double(gt) : std::nan("");
    return r;
}

std::string pct(double v) { return std::isnan(v) ? "n/a" : fmt("%.2f %%", 100.0 * v); }

// One scene under one sensor preset, one ground method.
struct SensorGroundRow {
    std::string scene, sensor, method;
    MethodFigures f;
    double ransac_s = 0;  // RANSAC's ground stage on the same scene and sensor
};

// Every scene of `grounds` under every sensor preset, with each ground method; the ideal
// sensor's rows are those runs themselves.
std::vector<SensorGroundRow> groundUnderSensors(const std::vector<std::pair<std::string, core::Scene>>& scenes,
                                                const std::vector<GroundResult>& grounds,
                                                const sim::GenerateOptions& paper) {
    std::vector<SensorGroundRow> rows;
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        const auto& [name, scene] = scenes[i];
        for (const std::string_view preset : sim::sensorPresetNames()) {
            const sim::SensorOptions sensor = sim::sensorPreset(preset);
            const MethodFigures* ideal[] = {&grounds[i].ransac, &grounds[i].smrf, &grounds[i].csf};
            double ransac_s = 0;
            for (std::size_t m = 0; m < std::size(kGroundMethods); ++m) {
                MethodFigures f;
                if (sim::isIdeal(sensor)) {
                    f = *ideal[m];
                } else {
                    std::fprintf(stderr, "bench peers: ground under sensors: %s, %.*s, %s\n", name.c_str(),
                                 int(preset.size()), preset.data(), kGroundMethods[m].second);
                    sim::GenerateOptions o = paper;
                    o.sensor = sensor;
                    o.ground.method = kGroundMethods[m].first;
                    sim::GenerateStats st;
                    sim::generateCloud(scene, o, &st);
                    f = figures(st);
                }
                if (m == 0) ransac_s = f.s;
                rows.push_back({name, std::string(preset), kGroundMethods[m].second, f, ransac_s});
            }
        }
    }
    return rows;
}

void run(const BenchPeersCli& cli) {
    if (cli.threads < 0 || cli.threads > 1024)
        throw core::Error("bench peers: --threads = " + std::to_string(cli.threads) + ": allowed [0, 1024]");
    if (cli.repeats < 1 || cli.repeats > 100)
        throw core::Error("bench peers: --repeats = " + std::to_string(cli.repeats) + ": allowed [1, 100]");
    if (cli.pmf_stride < 0)
        throw core::Error("bench peers: --pmf-stride = " + std::to_string(cli.pmf_stride) + ": allowed >= 0");
    const int threads = cli.threads > 0 ? cli.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    const fs::path dir = cli.tmp.empty() ? fs::temp_directory_path() / ("ladarvr_peers_" + std::to_string(::getpid()))
                                         : fs::path(cli.tmp);
    fs::create_directories(dir);
    const auto start = Clock::now();

    const core::Scene demo = io::loadScene(io::demoScenePath());
    sim::GenerateOptions paper;  // the paper's configuration: 128 x 128 px x 100 views
    paper.threads = threads;

    std::fprintf(stderr, "bench peers: 1/3 ray casting vs Open3D (demo scene, %d threads)\n", threads);
    const RayResult rays = rayCasting(demo, paper, cli, threads, dir);
    const double gen_mr = double(rays.rays) / rays.generator_cast_s / 1e6;
    const double plain_mr = double(rays.rays) / rays.plain_s / 1e6;
    const double o3d_mr = double(rays.rays) / rays.open3d_s / 1e6;
    std::printf(
        "ray casting, %llu rays, %zu triangles, %d threads: generator %.2f Mrays/s, plain rtcIntersect1 "
        "%.2f Mrays/s, Open3D %s %.2f Mrays/s; plain/Open3D %.2fx, generator/Open3D %.2fx; same hit/miss "
        "%.4f %%, |dt| median %.2g m, p99 %.2g m, max %.2g m\n",
        (unsigned long long)rays.rays, rays.triangles, threads, gen_mr, plain_mr, rays.open3d_version.c_str(), o3d_mr,
        plain_mr / o3d_mr, gen_mr / o3d_mr, 100.0 * rays.same_hit_fraction, rays.dt_median_m, rays.dt_p99_m,
        rays.dt_max_m);

    std::fprintf(stderr, "bench peers: 2/3 binary PCD write/read vs PCL (paper cloud)\n");
    const core::PointCloud cloud = sim::generateCloud(demo, paper);
    const IoResult io = pcdIo(cloud, cli.quick ? 2 : cli.repeats, dir);
    std::printf(
        "PCD binary, %zu points (%.1f MiB): write ours %.3f s, PCL %.3f s (PCL/ours %.2fx); read ours %.3f s, "
        "PCL %.3f s (PCL/ours %.2fx); PCL reads ours: %s; we read PCL's: %s\n",
        io.points, io.file_mib, io.ours_write_s, io.pcl_write_s, io.pcl_write_s / io.ours_write_s, io.ours_read_s,
        io.pcl_read_s, io.pcl_read_s / io.ours_read_s, io.pcl_reads_ours ? "identical" : "NO",
        io.ours_reads_pcl ? "identical" : "NO");

    std::fprintf(stderr,
                 "bench peers: 3/3 ground: iterative RANSAC, SMRF and CSF vs PCL progressive morphological "
                 "filter\n");
    std::vector<GroundResult> grounds;
    const std::size_t pmf_budget = cli.quick ? 25000 : 60000;
    grounds.push_back(ground("demo", demo, paper, pmf_budget, cli.pmf_stride));
    const fs::path hilly_path = sourceRoot() / "assets" / "hilly" / "scene.json";
    const core::Scene hilly = io::loadScene(hilly_path);
    grounds.push_back(ground("hilly", hilly, paper, pmf_budget, cli.pmf_stride));
    const core::Scene slopes = io::loadScene(sourceRoot() / "assets" / "slopes" / "scene.json");
    grounds.push_back(ground("slopes", slopes, paper, pmf_budget, cli.pmf_stride));
    const core::Scene forest = io::loadScene(sourceRoot() / "assets" / "forest" / "scene.json");
    grounds.push_back(ground("forest", forest, paper, pmf_budget, cli.pmf_stride));
    std::vector<SensorGroundRow> sensor_rows;
    if (!cli.no_sensors) {
        std::fprintf(stderr, "bench peers: ground under the sensor presets (4 scenes x %zu presets x 3 methods)\n",
                     sim::sensorPresetCount());
        sensor_rows = groundUnderSensors({{"demo", demo}, {"hilly", hilly}, {"slopes", slopes}, {"forest", forest}},
                                         grounds, paper);
    }
    for (const SensorGroundRow& r : sensor_rows)
        std::printf(
            "ground %s, sensor %s, %s: precision %s recall %s target kept %s environment kept %s in %.3f s "
            "(%.2fx RANSAC's)\n",
            r.scene.c_str(), r.sensor.c_str(), r.method.c_str(), pct(r.f.precision).c_str(), pct(r.f.recall).c_str(),
            pct(r.f.kept).c_str(), pct(r.f.environment_kept).c_str(), r.f.s, r.f.s / r.ransac_s);
    for (const GroundResult& g : grounds)
        std::printf(
            "ground %s: RANSAC (per view, %d threads) precision %s recall %s target kept %s in %.3f s on %zu "
            "points; SMRF precision %s recall %s target kept %s in %.3f s; CSF precision %s recall %s target kept %s "
            "in %.3f s; PMF precision %s recall %s in %.3f s on %zu points (every %d-th)\n",
            g.scene.c_str(), g.threads, pct(g.ransac.precision).c_str(), pct(g.ransac.recall).c_str(),
            pct(g.ransac.kept).c_str(), g.ransac.s, g.points, pct(g.smrf.precision).c_str(), pct(g.smrf.recall).c_str(),
            pct(g.smrf.kept).c_str(), g.smrf.s, pct(g.csf.precision).c_str(), pct(g.csf.recall).c_str(),
            pct(g.csf.kept).c_str(), g.csf.s, pct(g.pmf_precision).c_str(), pct(g.pmf_recall).c_str(), g.pmf_s,
            g.pmf_points, g.pmf_stride);
    std::error_code ec;
    fs::remove_all(dir, ec);
    const double total_s = secondsSince(start);

    const std::string date = utcNow();
    std::ostringstream s;
    s << "## Peers (ladarvr bench peers)\n\n"
      << "Command: `./ladarvr bench peers" << (cli.quick ? " --quick" : "")
      << "`; machine: " << std::thread::hardware_concurrency() << " cores, " << cpuName() << "; " << date << "; "
      << fmt("%.0f", total_s) << " s in all. One run, same scene (assets/demo, paper configuration: "
      << "128 x 128 px x 100 views), same data for both sides; medians of " << (cli.quick ? 3 : cli.repeats)
      << " runs after a warm-up.\n\n"
      << "**Ray casting** (" << rays.rays << " rays, " << rays.triangles << " triangles, " << threads
      << " threads on every side; rays and triangles dumped to a binary file and cast by "
      << "`scripts/peer_open3d.py`, Open3D " << rays.open3d_version << " `RaycastingScene.cast_rays`):\n\n"
      << "| caster | Mrays/s | vs Open3D |\n|---|---|---|\n"
      << "| generator cast stage (rtcIntersect16 packets, hits stored) | " << fmt("%.2f", gen_mr) << " | "
      << fmt("%.2fx", gen_mr / o3d_mr) << " |\n"
      << "| plain rtcIntersect1 loop (`sim::RayCaster::intersect`) | " << fmt("%.2f", plain_mr) << " | "
      << fmt("%.2fx", plain_mr / o3d_mr) << " |\n"
      << "| Open3D RaycastingScene | " << fmt("%.2f", o3d_mr) << " | 1 |\n\n"
      << "Hit agreement (plain loop vs Open3D): " << fmt("%.4f %%", 100.0 * rays.same_hit_fraction)
      << " of rays agree on hit/miss; over the " << rays.both_hit << " rays both hit, |t difference| median "
      << fmt("%.2g", rays.dt_median_m) << " m, 99th percentile " << fmt("%.2g", rays.dt_p99_m) << " m, max "
      << fmt("%.3g", rays.dt_max_m) << " m; " << rays.differ_1mm << " differ by more than 1 mm (Open3D's "
      << "RaycastingScene is itself built on Embree: the same watertight first hits are expected; the speed "
      << "difference is the call path, not the traversal).\n\n"
      << "**Binary PCD** (the paper's cloud, " << io.points << " points, fields x y z rgb label view range, "
      << fmt("%.1f", io.file_mib) << " MiB; PCL with a point type of the same fields; a new file each time, "
      << "written to the page cache without fsync and read back from it by both):\n\n"
      << "| | ours | PCL | PCL / ours |\n|---|---|---|---|\n"
      << "| write (`io::writeCloud` vs `pcl::io::savePCDFileBinary`) | " << fmt("%.3f s", io.ours_write_s) << " | "
      << fmt("%.3f s", io.pcl_write_s) << " | " << fmt("%.2fx", io.pcl_write_s / io.ours_write_s) << " |\n"
      << "| read (`io::readCloud` vs `pcl::io::loadPCDFile`) | " << fmt("%.3f s", io.ours_read_s) << " | "
      << fmt("%.3f s", io.pcl_read_s) << " | " << fmt("%.2fx", io.pcl_read_s / io.ours_read_s) << " |\n\n"
      << "Interoperability in the same run: PCL reads our file "
      << (io.pcl_reads_ours ? "field for field" : "NOT identically") << ", we read PCL's "
      << (io.ours_reads_pcl ? "field for field" : "NOT identically") << ".\n\n"
      << "**Ground whitening** against the generator's ground-truth labels (paper configuration). Ours: paper "
      << "§III-C iterative RANSAC on each view (16,384 points), all views, " << grounds.front().threads
      << " threads (`--ground ransac`); SMRF (Pingel et al. 2013, PDAL's defaults: cell 1 m, slope 0.15, "
      << "window 18 m, threshold 0.5 m, scalar 1.25) and CSF (Zhang et al. 2016, the paper's defaults: cloth "
      << "1 m, rigidness 3, threshold 0.5 m, time step 0.65, at most 500 iterations) on the whole fused cloud "
      << "(`--ground smrf`, `--ground csf`), each ground stage timed as a whole (gridding, fit, classification). PCL's "
         "`ProgressiveMorphologicalFilter` "
      << "(windows 3-17 m, slope 1, initial distance 0.5 m, max distance 3 m, cell 1 m; one thread) on the "
      << "fused cloud thinned to every k-th point, because its per-point box searches cannot take 1.6 M "
      << "points at ~130 points/m^2; its precision and recall are over those points. Target kept: the share of "
         "the target's points more than 0.5 m above the scene's true terrain left coloured. Points/s compares "
         "throughputs, not equal work.\n\n"
      << "| scene | method | precision | recall | target kept | s (points) | points/s |\n"
         "|---|---|---|---|---|---|---|\n";
    for (const GroundResult& g : grounds) {
        s << "| " << g.scene << " | RANSAC | " << pct(g.ransac.precision) << " | " << pct(g.ransac.recall) << " | "
          << pct(g.ransac.kept) << " | " << fmt("%.3f", g.ransac.s) << " (" << g.points << ") | "
          << fmt("%.3g", double(g.points) / g.ransac.s) << " |\n";
        s << "| " << g.scene << " | SMRF | " << pct(g.smrf.precision) << " | " << pct(g.smrf.recall) << " | "
          << pct(g.smrf.kept) << " | " << fmt("%.3f", g.smrf.s) << " (" << g.points << ") | "
          << fmt("%.3g", double(g.points) / g.smrf.s) << " |\n";
        s << "| " << g.scene << " | CSF | " << pct(g.csf.precision) << " | " << pct(g.csf.recall) << " | "
          << pct(g.csf.kept) << " | " << fmt("%.3f", g.csf.s) << " (" << g.points << ") | "
          << fmt("%.3g", double(g.points) / g.csf.s) << " |\n";
        s << "| " << g.scene << " | PCL PMF | " << pct(g.pmf_precision) << " | " << pct(g.pmf_recall) << " | n/a | "
          << fmt("%.3f", g.pmf_s) << " (" << g.pmf_points << ", every " << g.pmf_stride << "th) | "
          << fmt("%.3g", double(g.pmf_points) / g.pmf_s) << " |\n";
    }
    s << "\n";
    if (!sensor_rows.empty()) {
        s << "**Ground under the sensor presets** (same run; each row one `generate` of the paper configuration "
             "with `--sensor` and `--ground` as named, the same seed; docs/sensor.md describes the presets). Target "
             "kept and environment kept: the share of the target's, and of the buildings' and trees' points more "
             "than 0.5 m above the true terrain (judged where each ray hit) left coloured. Ground s: the ground "
             "stage as a whole; the last column divides it by RANSAC's on the same scene and sensor.\n\n"
          << "| scene | sensor | method | precision | recall | target kept | environment kept | ground s | vs "
             "RANSAC |\n|---|---|---|---|---|---|---|---|---|\n";
        for (const SensorGroundRow& r : sensor_rows)
            s << "| " << r.scene << " | " << r.sensor << " | " << r.method << " | " << pct(r.f.precision) << " | "
              << pct(r.f.recall) << " | " << pct(r.f.kept) << " | " << pct(r.f.environment_kept) << " | "
              << fmt("%.3f", r.f.s) << " | " << fmt("%.2fx", r.f.s / r.ransac_s) << " |\n";
        s << "\n";
    }
    if (!cli.no_md) {
        replaceMarkdownSection(cli.md, "## Peers (ladarvr bench peers)", s.str());
        std::fprintf(stderr, "bench peers: wrote the section to %s (%.0f s)\n", cli.md.c_str(), total_s);
    } else {
        std::fputs(s.str().c_str(), stdout);
    }
}

}  // namespace

void registerPeers(CLI::App& parent) {
    auto state = std::make_shared<BenchPeersCli>();
    CLI::App* c =
        parent.add_subcommand("peers",
                              "side by side with peer libraries: ray casting vs Open3D, binary "
                              "PCD I/O vs PCL, ground whitening (RANSAC, SMRF, CSF) vs PCL's morphological filter");
    c->add_flag("--quick", state->quick, "3 repeats, a smaller PMF sample (a smoke run)");
    c->add_option("--threads", state->threads, "threads for every caster, 0 = all")->capture_default_str();
    c->add_option("--repeats", state->repeats, "timed runs (medians)")->capture_default_str();
    c->add_option("--md", state->md, "markdown file whose peers section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print the section, leave the file alone");
    c->add_option("--python", state->python, "python interpreter with open3d")->capture_default_str();
    c->add_option("--open3d-script", state->open3d_script, "default: <source>/scripts/peer_open3d.py");
    c->add_option("--pmf-stride", state->pmf_stride, "give PMF every k-th point (0: ~60,000 points)");
    c->add_option("--tmp", state->tmp, "scratch directory (default: a temporary one)");
    c->add_flag("--no-sensors", state->no_sensors,
                "leave out the ground figures under the sensor presets (each scene x preset x method)");
    c->callback([state] { run(*state); });
}

}  // namespace bench
