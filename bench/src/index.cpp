// bench/src/index.cpp: `ladarvr bench index`: how fast `ladarvr index` turns a binary PCD
// into COPC (io/copc_writer.hpp), its peak memory, and its output's size, against writing
// the same points as plain LAZ in the same run (the baseline: the same reader, the same
// records, chunks compressed on the same threads, no octree).
//
// A synthetic binary PCD of --points points (a terrain with buildings and a dense cluster,
// seeded) is written once; each repeat then runs in a child process (fork) that reads it
// and writes COPC, or plain LAZ, as `ladarvr index` does, so that the child's peak RSS is
// that of one conversion; COPC is written within --memory-mb as the command does. Reports points per second (median [min..max] over --repeats, after
// one warm-up of each), the children's peak RSS, and COPC bytes / LAZ bytes. Rewrites the
// section "## Index (ladarvr bench index)" of BENCHMARKS.md.
#include "common.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc_writer.hpp>
#include <sim/memory_budget.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

struct BenchIndexCli {
    double points = 1e7;
    int repeats = 3;
    int threads = 0;            // 0 = the cores
    double memory_mb = 1024.0;  // as `ladarvr index --memory-mb`
    bool quick = false;
    std::string tmp;
    std::string input;  // a cloud to index instead of the synthetic one
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
};

struct Run {
    double seconds = 0;
    double rss_mib = 0;
};

// The synthetic cloud, written in pieces so that it never sits whole in memory.
void writeInput(const fs::path& path, std::size_t n) {
    core::CloudFields fields;  // x y z rgb label view range: what the generator writes
    io::CloudWriter w(path, io::CloudFormat::PcdBinary, glm::dvec3(500000.0, 4000000.0, 100.0), fields);
    std::mt19937_64 rng(20);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float side_m = float(std::sqrt(double(n) / 25.0));  // about 25 points per m^2
    std::vector<core::CloudPoint> piece;
    for (std::size_t i = 0; i < n;) {
        piece.clear();
        for (; i < n && piece.size() < (1u << 20); ++i) {
            core::CloudPoint p;
            const float x = u(rng) * side_m, y = u(rng) * side_m;
            const bool building = std::fmod(x, 50.0f) < 12.0f && std::fmod(y, 60.0f) < 15.0f;
            p.position = {x, y, building ? 8.0f + u(rng) * 0.05f : 0.02f * std::sin(x * 0.01f) * 100.0f};
            if (i % 50 == 0) p.position = {side_m * 0.5f + u(rng) * 2.0f, side_m * 0.5f + u(rng) * 2.0f, u(rng) * 3.0f};
            p.rgb = core::packRgb(std::uint8_t(x), std::uint8_t(y), std::uint8_t(p.position.z * 10.0f));
            p.label = building ? core::Role::Environment : core::Role::Ground;
            p.view = std::uint16_t(i % 100);
            p.range_m = 300.0f + u(rng);
            piece.push_back(p);
        }
        w.append(piece);
    }
    w.commit();
}

// What `ladarvr index` does, into `format`: COPC within `budget` bytes, the reader's two chunks
// included, as the command plans it.
void convert(const fs::path& in, const fs::path& out, io::CloudFormat format, int threads, std::uint64_t budget) {
    io::CloudReader reader(in);
    io::LasOptions las;
    las.threads = threads - 1;
    io::CopcOptions copc;
    copc.memory_bytes = budget - 2 * io::CloudReader::kChunkPoints * sizeof(core::CloudPoint);
    io::CloudWriter writer(out, format, reader.origin(), reader.fields(), las,
                           format == io::CloudFormat::Copc ? &copc : nullptr);
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) { writer.append(chunk); });
    writer.commit();
}

// One conversion in a child process: its wall time and peak RSS.
Run measure(const fs::path& in, const fs::path& out, io::CloudFormat format, int threads, std::uint64_t budget) {
    std::fflush(nullptr);
    const auto t0 = Clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) throw core::Error("bench index: fork failed");
    if (pid == 0) {
        int status = 0;
        try {
            convert(in, out, format, threads, budget);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "bench index: %s\n", e.what());
            status = 1;
        }
        std::fflush(nullptr);
        ::_exit(status);
    }
    int status = 0;
    struct rusage usage{};
    if (::wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw core::Error("bench index: the conversion to " + out.string() + " failed");
    return {secondsSince(t0), double(usage.ru_maxrss) / 1024.0};
}

void run(BenchIndexCli& cli) {
    if (cli.quick) {
        cli.points = 200000;
        cli.repeats = 1;
    }
    if (!(cli.points >= 1 && cli.points <= 4e9)) throw core::Error("bench index: --points: allowed [1, 4e9]");
    if (!cli.input.empty() && !fs::is_regular_file(cli.input))
        throw core::Error("bench index: --input " + cli.input + ": allowed a cloud file (PCD, PLY, LAS, LAZ, COPC)");
    if (cli.repeats < 1) throw core::Error("bench index: --repeats: allowed >= 1");
    std::size_t n = std::size_t(cli.points);
    const int threads = cli.threads > 0 ? cli.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    const std::uint64_t budget = sim::memoryBudgetBytes(cli.memory_mb, "bench index");
    const std::uint64_t least =
        io::copcMinimumBytes(threads - 1) + 2 * io::CloudReader::kChunkPoints * sizeof(core::CloudPoint);
    if (budget < least)
        throw core::Error("bench index: --memory-mb " + core::shownNumber(cli.memory_mb) + " is below the " +
                          std::to_string((least >> 20) + 1) + " MiB indexing needs with " + std::to_string(threads) +
                          " threads");
    const fs::path dir = (cli.tmp.empty() ? fs::temp_directory_path() : fs::path(cli.tmp)) /
                         ("ladarvr-bench-index-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{dir};
    const fs::path copc = dir / "out.copc.laz", laz = dir / "out.laz";
    fs::path in = dir / "in.pcd";
    if (cli.input.empty()) {
        std::fprintf(stderr, "bench index: writing %zu points to %s\n", n, in.string().c_str());
        writeInput(in, n);
    } else {
        in = cli.input;
        n = io::CloudReader(in).declaredPoints();
    }
    std::vector<double> copc_rate, laz_rate;
    double copc_rss = 0, laz_rss = 0;
    const int runs = cli.quick ? 1 : cli.repeats + 1;
    for (int r = 0; r < runs; ++r) {  // r = 0: the warm-up (measured in a quick run)
        const Run c = measure(in, copc, io::CloudFormat::Copc, threads, budget);
        const Run l = measure(in, laz, io::CloudFormat::Laz, threads, budget);
        std::fprintf(stderr, "bench index: %s copc %.2f s (%.0f MiB), laz %.2f s (%.0f MiB)\n",
                     r == 0 && !cli.quick ? "warm-up" : ("repeat " + std::to_string(r)).c_str(), c.seconds, c.rss_mib,
                     l.seconds, l.rss_mib);
        if (r == 0 && !cli.quick) continue;
        copc_rate.push_back(double(n) / c.seconds);
        laz_rate.push_back(double(n) / l.seconds);
        copc_rss = std::max(copc_rss, c.rss_mib);
        laz_rss = std::max(laz_rss, l.rss_mib);
    }
    const double copc_bytes = double(fs::file_size(copc)), laz_bytes = double(fs::file_size(laz));
    const Spread cs = spread(copc_rate), ls = spread(laz_rate);
    std::ostringstream s;
    s << "## Index (ladarvr bench index)\n\n"
      << "`./ladarvr bench index "
      << (cli.input.empty() ? "--points " + std::to_string(n) : "--input " + fs::path(cli.input).filename().string())
      << " --repeats " << cli.repeats << "` on " << cpuName() << ", " << threads << " threads, --memory-mb "
      << core::shownNumber(cli.memory_mb) << ", " << utcNow() << ". "
      << (cli.input.empty() ? "A binary PCD of synthetic terrain (uniformly random points and attributes, the worst "
                              "order for LAZ)"
                            : "The given cloud (" + std::to_string(n) + " points)")
      << " to COPC (what `ladarvr index` does, within the memory bound) against "
      << "the same points to plain LAZ in the same run; each conversion in its own process.\n\n"
      << "| output | M points/s | peak RSS MiB | bytes |\n|---|---:|---:|---:|\n"
      << "| COPC | " << fmtSpread("%.2f", {cs.min / 1e6, cs.median / 1e6, cs.max / 1e6, cs.n}) << " | "
      << fmt("%.0f", copc_rss) << " | " << fmt("%.0f", copc_bytes) << " |\n"
      << "| plain LAZ (baseline) | " << fmtSpread("%.2f", {ls.min / 1e6, ls.median / 1e6, ls.max / 1e6, ls.n}) << " | "
      << fmt("%.0f", laz_rss) << " | " << fmt("%.0f", laz_bytes) << " |\n\n"
      << "COPC / LAZ: time " << fmt("%.2f", ls.median / cs.median) << "x" << spreadNote(cs, ls) << ", bytes "
      << fmt("%.3f", copc_bytes / laz_bytes) << "x.\n";
    std::printf("%s", s.str().c_str());
    if (!cli.no_md && !cli.quick) replaceMarkdownSection(cli.md, "## Index (ladarvr bench index)", s.str());
}

}  // namespace

void registerIndex(CLI::App& parent) {
    auto state = std::make_shared<BenchIndexCli>();
    CLI::App* c = parent.add_subcommand(
        "index", "points per second, peak memory and size of a binary PCD to COPC, against plain LAZ in the same run");
    c->add_option("--points", state->points, "points of the synthetic cloud")->capture_default_str();
    c->add_option("--repeats", state->repeats, "measured runs of each, after one warm-up")->capture_default_str();
    c->add_option("--threads", state->threads, "threads, 0 = the cores")->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb, "the COPC writer's memory bound, as `ladarvr index --memory-mb`")
        ->capture_default_str();
    c->add_flag("--quick", state->quick, "a smoke run: 200000 points, one run, BENCHMARKS.md left alone");
    c->add_option("--input", state->input,
                  "index this cloud instead of the synthetic one (any format `ladarvr index` reads); --points is "
                  "then its count");
    c->add_option("--tmp", state->tmp, "folder for the input and outputs (default: the system's temporary folder)");
    c->add_option("--md", state->md, "markdown file whose index section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print only, leave BENCHMARKS.md alone");
    c->callback([state] { run(*state); });
}

}  // namespace bench
