// bench/src/corpus.cpp: `ladarvr bench corpus`: items per second of `ladarvr corpus` on the
// demo scene at the paper's configuration (128x128 px x 100 views), without and with the
// metric, with --jobs 1..K; what determinism costs (planning each item from (seed, i) and
// hashing its files, against the item's time); and a projection for 10,000 items at the
// 100x configuration (100 times the paper's rays: 1280x1280 px x 100 views) on N nodes,
// from a fit of item time against rays measured at 1x and 4x. Rewrites the section
// "## Corpus (ladarvr bench corpus)" of BENCHMARKS.md.
#include "common.hpp"
#include "register.hpp"

#include <corpus/plan.hpp>
#include <corpus/run.hpp>
#include <corpus/spec.hpp>

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>
#include <platform/sha256.hpp>
#include <sim/generator.hpp>

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

struct BenchCorpusCli {
    int items = 6;
    int max_jobs = 0;  // 0 = the cores
    int node_cores = 32;
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
    std::string tmp;
};

struct Measure {
    std::string label;
    int jobs = 1, threads = 0, items = 0;
    double rays = 0;
    double wall_s = 0;
    Spread item_s;  // seconds per item as the manifest records them
    double itemsPerSecond() const { return wall_s > 0 ? items / wall_s : 0; }
};

std::string writeSpec(const fs::path& dir, const std::string& name, int count, int resolution, bool metric) {
    const fs::path scene = io::demoScenePath();
    nlohmann::json spec{{"scene", fs::absolute(scene).string()},
                        {"count", count},
                        {"seed", 2016},
                        {"vary",
                         {{"target_yaw_deg", {{"min", 0}, {"max", 360}}},
                          {"target_offset_m", {{"min", 0}, {"max", 20}}},
                          {"centre_offset_m", {{"min", 0}, {"max", 15}}},
                          {"resolution", resolution}}},
                        {"metric", metric}};
    const fs::path file = dir / (name + ".json");
    platform::writeFileAtomic(file, spec.dump(2));
    return file.string();
}

Measure measure(const fs::path& tmp, const std::string& label, const std::string& spec, int jobs, int threads,
                double rays) {
    const fs::path out = tmp / ("run-" + std::to_string(::getpid()) + "-" + label);
    fs::remove_all(out);
    corpus::RunOptions o;
    o.spec = spec;
    o.out = out;
    o.jobs = jobs;
    o.threads = threads;
    const auto t0 = Clock::now();
    const corpus::RunSummary s = corpus::runCorpus(o);
    Measure m;
    m.wall_s = secondsSince(t0);
    m.label = label;
    m.jobs = jobs;
    m.threads = threads;
    m.items = int(s.built);
    m.rays = rays;
    if (!s.failed.empty()) throw core::Error("bench corpus: " + s.failed.front());
    std::vector<double> per_item;
    platform::InputSet read;  // what the benchmark read; it writes nothing in the corpus
    for (const std::string& line : corpus::readManifest(out, read))
        per_item.push_back(nlohmann::json::parse(line)["seconds"].get<double>());
    m.item_s = spread(per_item);
    fs::remove_all(out);
    std::fprintf(stderr, "bench corpus: %-40s %d items in %.2f s: %.3f items/s\n", label.c_str(), m.items, m.wall_s,
                 m.itemsPerSecond());
    return m;
}

/// The in-run baseline: what `ladarvr generate` does for the same items (load the concrete
/// scene, generate in memory, write the cloud), without planning, folders, hashing or
/// manifest.
Spread plainItems(const corpus::Planner& planner, int items, const fs::path& tmp) {
    std::vector<double> seconds;
    for (int i = 0; i < items; ++i) {
        const corpus::ItemPlan p = planner.plan(std::size_t(i));
        const auto t0 = Clock::now();
        const core::Scene scene = io::loadSceneJson(p.sceneText({}), tmp / "plain.json");
        sim::GenerateOptions o = p.options;
        o.threads = 0;
        const core::PointCloud cloud = sim::generateCloud(scene, o);
        io::writeCloud(tmp / "plain.pcd", cloud, io::CloudFormat::PcdBinary);
        seconds.push_back(secondsSince(t0));
    }
    fs::remove(tmp / "plain.pcd");
    return spread(seconds);
}

std::string loadAverage() {
    std::ifstream in("/proc/loadavg");
    double one = 0;
    in >> one;
    return in ? fmt("%.1f", one) : std::string("unknown");
}

std::string hours(double seconds) {
    if (seconds < 3600) return fmt("%.0f min", seconds / 60);
    return fmt("%.1f h", seconds / 3600);
}

void run(const BenchCorpusCli& cli) {
    const auto start = Clock::now();
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    const int max_jobs = cli.max_jobs > 0 ? cli.max_jobs : cores;
    if (cli.items < 2 || cli.items > 1000) throw core::Error("bench corpus: --items: allowed [2, 1000]");
    const fs::path tmp = cli.tmp.empty()
                             ? fs::temp_directory_path() / ("ladarvr-bench-corpus-" + std::to_string(::getpid()))
                             : fs::path(cli.tmp);
    fs::create_directories(tmp);
    struct Remove {
        fs::path p;
        ~Remove() {
            std::error_code ec;
            fs::remove_all(p, ec);
        }
    } remove{cli.tmp.empty() ? tmp : fs::path()};

    const double paper_rays = 128.0 * 128.0 * 100.0;
    const std::string paper = writeSpec(tmp, "paper", cli.items, 128, false);
    const std::string paper_metric = writeSpec(tmp, "paper_metric", cli.items, 128, true);
    const std::string x4 = writeSpec(tmp, "x4", cli.items, 256, false);

    measure(tmp, "warm-up", writeSpec(tmp, "warm", 1, 128, true), 1, 0, paper_rays);
    const corpus::Spec spec = corpus::loadSpec(paper);
    const corpus::Planner planner(spec);
    std::vector<Measure> rows;
    // The baseline right before and after the first corpus row (the machine's load drifts).
    std::vector<double> plain_s;
    const auto addPlain = [&] {
        const Spread p = plainItems(planner, cli.items, tmp);
        plain_s.push_back(p.median);
    };
    addPlain();
    for (int jobs = 1; jobs <= max_jobs; jobs *= 2)
        rows.push_back(measure(tmp, "paper, no metric, --jobs " + std::to_string(jobs), paper, jobs, 0, paper_rays));
    addPlain();
    const Spread plain = spread(plain_s);
    std::fprintf(stderr, "bench corpus: plain generate of the same items: %s s per item\n",
                 fmtSpread("%.3f", plain).c_str());
    rows.push_back(measure(tmp, "paper, metric, --jobs 1", paper_metric, 1, 0, paper_rays));
    if (max_jobs > 1)
        rows.push_back(
            measure(tmp, "paper, metric, --jobs " + std::to_string(max_jobs), paper_metric, max_jobs, 0, paper_rays));
    rows.push_back(measure(tmp, "4x (256x256 px), no metric, --jobs 1", x4, 1, 0, 4 * paper_rays));

    // Determinism: planning each item from (seed, i) alone, and hashing its files.
    std::vector<double> plan_ms;
    for (int rep = 0; rep < 5; ++rep)
        for (std::size_t i = 0; i < spec.count; ++i) {
            const auto t0 = Clock::now();
            const corpus::ItemPlan p = planner.plan(i);
            plan_ms.push_back(msSince(t0));
        }
    const std::string cloud_like(std::size_t(36) << 20, 'x');  // a paper-size binary PCD: 36 MiB
    std::vector<double> hash_ms;
    for (int rep = 0; rep < 3; ++rep) {
        const auto t0 = Clock::now();
        (void)platform::sha256Hex(cloud_like);
        hash_ms.push_back(msSince(t0));
    }
    const Spread plan = spread(plan_ms), hash = spread(hash_ms);
    const double item_ms = rows.front().item_s.median * 1000.0;

    // Projection: item time = a + b * rays, from the 1x and 4x rows (jobs 1, no metric).
    const Measure& one = rows.front();
    const Measure& four = rows.back();
    const double b = (four.item_s.median - one.item_s.median) / (four.rays - one.rays);
    const double a = one.item_s.median - b * one.rays;
    const double t100 = a + b * 100.0 * paper_rays;
    const auto with_metric =
        std::find_if(rows.begin(), rows.end(), [](const Measure& m) { return m.label == "paper, metric, --jobs 1"; });
    const double metric_extra = with_metric->item_s.median - one.item_s.median;
    const double t100_metric = t100 + metric_extra * 100.0;  // its three generator runs scale with rays
    // --jobs scaling: items/s at the largest --jobs over --jobs 1 (no metric).
    double jobs_speedup = 1.0;
    int jobs_best = 1;
    for (const Measure& m : rows)
        if (m.label.find("no metric") != std::string::npos && m.rays == paper_rays && m.jobs > jobs_best) {
            jobs_best = m.jobs;
            jobs_speedup = m.itemsPerSecond() / rows.front().itemsPerSecond();
        }

    std::ostringstream s;
    s << "Command: `./ladarvr bench corpus --items " << cli.items << "`; machine: " << cores << " cores, " << cpuName()
      << "; " << utcNow() << "; " << fmt("%.0f", secondsSince(start)) << " s in all; load average " << loadAverage()
      << " at the end. The cores were shared with other jobs: read ratios rather than lone times.\n\n"
      << "Items of `ladarvr corpus` over the demo scene (the target's yaw, a target offset of 0-20 m and a centre "
      << "offset of 0-15 m vary), each run into a fresh folder: wall time of the whole run (SPEC, base scene, items, "
      << "manifest) and the seconds per item the manifest records (median [min..max]). Generator threads per item: "
         "the cores divided by --jobs. Metric: `ladarvr metric`'s defaults (100 views, 512x512 px, exact "
         "reference).\n\n"
      << "| configuration | rays per item | items | wall s | items/s | s per item |\n|---|---|---|---|---|---|\n";
    for (const Measure& m : rows)
        s << "| " << m.label << " | " << fmt("%.0f", m.rays) << " | " << m.items << " | " << fmt("%.2f", m.wall_s)
          << " | " << fmt("%.3f", m.itemsPerSecond()) << " | " << fmtSpread("%.3f", m.item_s) << " |\n";
    s << "\nIn-run baseline: the same paper items made as `ladarvr generate` makes a cloud (load the concrete scene, "
      << "generate, write; no planning, item folder, hashing or manifest), measured before and after the --jobs "
      << "rows without the metric: " << fmtSpread("%.3f", plain) << " s each (medians of the two passes). A corpus "
      << "item (--jobs 1) costs " << fmt("%.2f", rows.front().item_s.median / plain.median) << "x that"
      << spreadNote(rows.front().item_s, plain) << ".\n";
    s << "\nDeterminism: planning an item from (seed, i) alone (its own random streams, the target's and C's "
      << "placement with vertical rays on the ground) takes " << fmtSpread("%.3f", plan) << " ms, "
      << fmt("%.2f", 100.0 * plan.median / item_ms) << " % of a paper item (" << fmt("%.0f", item_ms)
      << " ms); SHA-256 of a paper-size cloud (36 MiB) " << fmtSpread("%.0f", hash) << " ms, "
      << fmt("%.0f", 36.0 / (hash.median / 1000.0)) << " MiB/s. The generator's cloud does not depend on its thread "
      << "count, so no run is serialised for the sake of determinism.\n\n"
      << "Projection, 10,000 items at the 100x configuration (1280x1280 px x 100 views, 163.8 M rays per item): a "
      << "straight line through the 1x and 4x rows gives " << fmt("%.1f", t100) << " s per item on one of these "
      << "nodes with all its cores (" << fmt("%.1f", t100_metric) << " s with the metric, counting its three "
      << "generator runs as scaling with the rays too: an upper bound). --jobs " << jobs_best << " made "
      << fmt("%.2f", jobs_speedup) << "x the items/s of --jobs 1 here (the generator already keeps the cores busy). "
      << "The figures assume nodes like this one (" << cores << " cores, one item at a time) and, in the last "
      << "columns, " << cli.node_cores << "-core nodes running " << cli.node_cores / cores << " such items at once "
      << "with linear scaling (an assumption: this machine has " << cores << " cores):\n\n"
      << "| nodes | " << cores << "-core nodes | with metric | " << cli.node_cores << "-core nodes | with metric |\n"
      << "|---|---|---|---|---|\n";
    for (int nodes : {1, 10, 50, 100, 500}) {
        const double per_node = 1.0, wide = double(cli.node_cores / cores);
        s << "| " << nodes << " | " << hours(1e4 * t100 / (nodes * per_node)) << " | "
          << hours(1e4 * t100_metric / (nodes * per_node)) << " | " << hours(1e4 * t100 / (nodes * wide)) << " | "
          << hours(1e4 * t100_metric / (nodes * wide)) << " |\n";
    }
    s << "\nAt " << fmt("%.0f", t100) << " s per item, a 5-15 minute array task holds " << fmt("%.0f", 300.0 / t100)
      << "-" << fmt("%.0f", 900.0 / t100) << " items per node slot: for 10,000 items, "
      << "--array=0-" << int(std::ceil(1e4 / std::max(1.0, std::floor(600.0 / t100)))) - 1
      << " (about 10 minutes each; docs/corpus.md).\n";
    std::printf("%s", s.str().c_str());
    if (!cli.no_md) {
        replaceMarkdownSection(cli.md, "## Corpus (ladarvr bench corpus)",
                               "## Corpus (ladarvr bench corpus)\n\n" + s.str() + "\n");
        std::fprintf(stderr, "bench corpus: wrote the section to %s\n", cli.md.c_str());
    }
}

}  // namespace

void registerCorpus(CLI::App& parent) {
    auto state = std::make_shared<BenchCorpusCli>();
    CLI::App* c = parent.add_subcommand("corpus",
                                        "items/s of `ladarvr corpus` at the paper configuration with and "
                                        "without the metric, --jobs scaling, cost of determinism, "
                                        "projection for 10,000 items at 100x on N nodes");
    c->add_option("--items", state->items, "items per measured run, [2, 1000]")->capture_default_str();
    c->add_option("--max-jobs", state->max_jobs, "largest --jobs measured (doubling from 1); 0 = the cores")
        ->capture_default_str();
    c->add_option("--node-cores", state->node_cores, "cores of the cluster nodes in the projection")
        ->capture_default_str();
    c->add_option("--md", state->md, "markdown file whose corpus section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print only, leave BENCHMARKS.md alone");
    c->add_option("--tmp", state->tmp, "scratch folder (default: a new one under the system temp dir, removed)");
    c->callback([state] { run(*state); });
}

}  // namespace bench
