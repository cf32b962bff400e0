// bench/src/formats.cpp: the cost of LAZ and COPC output against binary PCD, on the same
// points. The writers get the same chunks of the cloud one after the other (reading is
// not timed), so the ratios hold on a shared machine: binary PCD, LAZ with its chunks
// compressed on every core (as `generate` writes it), LAZ on the caller's thread alone
// (LASzip's own speed), and COPC within the memory bound `ladarvr index` has by default.
// Then whole `generate` runs of the same configuration to LAZ and to COPC, as a user runs
// them (the default memory bound, the cloud streamed through the spool), alternated.
// Goals: LAZ at most a quarter of the bytes at no more than 2x the write time of binary
// PCD; COPC at most 1.5x the time of LAZ.
#include "formats.hpp"

#include "common.hpp"

#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc_writer.hpp>
#include <sim/generator.hpp>

#include <cstdio>
#include <thread>
#include <sstream>
#include <system_error>
#include <vector>

namespace bench {

namespace {
constexpr int kCopcMemoryMiB = 1024;
}

FormatRuns benchFormatRuns(const core::Scene& scene, const sim::GenerateOptions& options,
                           const std::filesystem::path& dir) {
    namespace fs = std::filesystem;
    // Whole runs: LAZ, COPC, COPC, LAZ, so that drift within the hour falls on both sides.
    sim::GenerateOptions run_options = options;
    run_options.memory_budget_bytes = sim::GenerateOptions{}.memory_budget_bytes;
    std::vector<double> run_laz_total, run_laz_write, run_copc_total, run_copc_write;
    bool run_streamed = true;
    for (const io::CloudFormat format :
         {io::CloudFormat::Laz, io::CloudFormat::Copc, io::CloudFormat::Copc, io::CloudFormat::Laz}) {
        const bool is_copc = format == io::CloudFormat::Copc;
        const fs::path out = dir / (is_copc ? "run.copc.laz" : "run.laz");
        sim::GenerateStats st;
        sim::Generator(scene, run_options).run(out, format, &st);
        std::error_code ec;
        fs::remove(out, ec);
        run_streamed = run_streamed && st.streamed;
        (is_copc ? run_copc_total : run_laz_total).push_back(st.seconds.total);
        (is_copc ? run_copc_write : run_laz_write).push_back(st.seconds.write);
        std::fprintf(stderr, "bench formats: generate to %s: total %.2f s, write %.2f s\n", is_copc ? "COPC" : "LAZ",
                     st.seconds.total, st.seconds.write);
    }
    const Spread lt = spread(run_laz_total), ct = spread(run_copc_total), lw = spread(run_laz_write),
                 cw = spread(run_copc_write);
    const bool run_ok = ct.median <= 1.5 * lt.median;
    FormatRuns r;
    std::ostringstream g;
    g << "| `generate` output | total (s) | write stage (s) |\n|---|---|---|\n"
      << "| LAZ | " << fmtSpread("%.2f", lt) << " | " << fmtSpread("%.2f", lw) << " |\n"
      << "| COPC | " << fmtSpread("%.2f", ct) << " | " << fmtSpread("%.2f", cw) << " |\n";
    r.verdict = "Whole `generate` runs (" + std::string(run_streamed ? "streamed through the spool" : "NOT STREAMED") +
                ", memory bound " + std::to_string(run_options.memory_budget_bytes >> 20) + " MiB): COPC " +
                fmt("%.2f", ct.median / lt.median) + "x the time of LAZ (goal <= 1.5x: " + (run_ok ? "met" : "missed") +
                "); its write stage " + fmt("%.2f", cw.median / lw.median) + "x LAZ's";
    r.table = g.str();
    return r;
}

void benchFormats(const core::Scene& scene, const sim::GenerateOptions& options, const std::filesystem::path& dir,
                  const std::string& config, const std::string& md) {
    namespace fs = std::filesystem;
    const auto start = Clock::now();
    const fs::path source = dir / "formats_source.pcd";
    sim::Generator(scene, options).run(source, io::CloudFormat::PcdBinary);
    struct Remove {
        fs::path p;
        ~Remove() {
            std::error_code ec;
            fs::remove(p, ec);
        }
    } remove_source{source};
    // The whole cloud in memory first, so that no writer's background work overlaps
    // another's clock or the reading.
    io::CloudReader reader(source);
    std::vector<std::vector<core::CloudPoint>> chunks;
    std::size_t points = 0;
    for (;;) {
        std::vector<core::CloudPoint> chunk;
        if (!reader.nextChunk(chunk, std::size_t(1) << 20)) break;
        points += chunk.size();
        chunks.push_back(std::move(chunk));
    }
    const int threads = options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    io::LasOptions parallel, alone;
    parallel.threads = threads;
    alone.threads = 0;
    // One writer over the whole cloud: seconds from opening to the committed file, its size.
    const auto write = [&](io::CloudFormat format, const io::LasOptions& las, const fs::path& out,
                           std::uintmax_t& bytes, const io::CopcOptions* copc = nullptr) {
        const auto t0 = Clock::now();
        {
            io::CloudWriter w(out, format, reader.origin(), reader.fields(), las, copc);
            for (const auto& chunk : chunks) w.append(chunk);
            w.commit();
        }
        const double s = secondsSince(t0);
        bytes = fs::file_size(out);
        std::error_code ec;
        fs::remove(out, ec);
        return s;
    };
    // Binary PCD and parallel LAZ in turn, 3 rounds (medians); LAZ on one thread once.
    std::vector<double> pcd_runs, laz_runs;
    std::uintmax_t pcd_bytes = 0, laz_bytes = 0, laz1_bytes = 0;
    for (int round = 0; round < 3; ++round) {
        pcd_runs.push_back(write(io::CloudFormat::PcdBinary, {}, dir / "formats.pcd", pcd_bytes));
        laz_runs.push_back(write(io::CloudFormat::Laz, parallel, dir / "formats.laz", laz_bytes));
    }
    const double laz1_s = write(io::CloudFormat::Laz, alone, dir / "formats_1.laz", laz1_bytes);
    // COPC once (it takes longest), within `ladarvr index`'s default bound of 1 GiB.
    io::CopcOptions copc;
    copc.memory_bytes = std::uint64_t(kCopcMemoryMiB) << 20;
    std::uintmax_t copc_bytes = 0;
    const double copc_s = write(io::CloudFormat::Copc, parallel, dir / "formats.copc.laz", copc_bytes, &copc);
    const double pcd_s = median(pcd_runs), laz_s = median(laz_runs);
    const double pcd_mib = double(pcd_bytes) / 1048576.0, laz_mib = double(laz_bytes) / 1048576.0,
                 laz1_mib = double(laz1_bytes) / 1048576.0, copc_mib = double(copc_bytes) / 1048576.0;
    const bool same_file = laz_bytes == laz1_bytes;

    std::ostringstream t;
    t << "| format | write (s) | Mpoints/s | size (MiB) | bytes/point | size vs binary PCD | time vs binary PCD |\n"
      << "|---|---|---|---|---|---|---|\n";
    const auto row = [&](const char* name, double s, double mib) {
        t << "| " << name << " | " << fmt("%.2f", s) << " | " << fmt("%.2f", double(points) / s / 1e6) << " | "
          << fmt("%.1f", mib) << " | " << fmt("%.2f", mib * 1048576.0 / double(points)) << " | "
          << fmt("%.3fx", mib / pcd_mib) << " | " << fmt("%.2fx", s / pcd_s) << " |\n";
    };
    row("binary PCD (io::CloudWriter)", pcd_s, pcd_mib);
    const std::string laz_name = "LAZ, chunks compressed on " + std::to_string(threads) + " threads";
    row(laz_name.c_str(), laz_s, laz_mib);
    row("LAZ, on the caller's thread alone", laz1_s, laz1_mib);
    const std::string copc_name =
        "COPC, within " + std::to_string(kCopcMemoryMiB) + " MiB, on " + std::to_string(threads) + " threads";
    row(copc_name.c_str(), copc_s, copc_mib);
    const bool size_ok = laz_mib <= 0.25 * pcd_mib, time_ok = laz_s <= 2.0 * pcd_s, copc_ok = copc_s <= 1.5 * laz_s;
    const std::string verdict =
        std::string("LAZ: ") + fmt("%.3f", laz_mib / pcd_mib) +
        " of the bytes (goal <= 0.25: " + (size_ok ? "met" : "missed") + "), " + fmt("%.2f", laz_s / pcd_s) +
        "x the write time (goal <= 2x: " + (time_ok ? "met" : "missed") + "); " + fmt("%.2f", laz1_s / laz_s) +
        "x faster than on one thread" + (same_file ? "" : "; THE TWO LAZ FILES DIFFER IN SIZE") +
        ". COPC: " + fmt("%.2f", copc_s / laz_s) +
        "x the write time of LAZ (goal <= 1.5x: " + (copc_ok ? "met" : "missed") + "), " +
        fmt("%.3f", copc_mib / laz_mib) + "x its bytes";
    const FormatRuns runs = benchFormatRuns(scene, options, dir);
    std::printf("\n%s\n%s\n\n%s\n%s\n", t.str().c_str(), verdict.c_str(), runs.table.c_str(), runs.verdict.c_str());
    if (md.empty()) return;
    std::ostringstream s;
    s << "## Cloud formats (ladarvr bench generate)\n\n"
      << "Command: `./ladarvr bench generate` (or `--only formats`); " << utcNow() << "; " << cpuName() << "; "
      << fmt("%.0f", secondsSince(start)) << " s. The cloud of the " << config << " configuration (" << points
      << " points, fields x y z rgb label view range), read back chunk by chunk and written "
         "again by each writer: binary PCD as the "
         "generator writes it, and LAZ (LAS 1.4 point format 7, 1 mm scale, extra bytes range and label; "
         "chunks of "
      << io::lazChunkPoints()
      << " points compressed by LASzip on worker threads, "
         "the file LASzip writes alone, byte for byte), then the same LAZ on one thread, then COPC (`generate --out "
         "X.copc.laz`'s writer, past its memory bound spilling to scratch files and building the octree a part at a "
         "time). The cloud is read into memory first; each write is timed from opening the writer to the committed "
         "file; binary PCD and parallel LAZ in turn, 3 rounds, medians; LAZ on one thread and COPC once.\n\n"
      << t.str() << "\n"
      << verdict << ".\n\n"
      << "Then four whole `generate` runs of the same configuration (LAZ, COPC, COPC, LAZ), at the default "
         "memory bound, timed by the generator's own stages (BVH to write); medians [min..max] of two:\n\n"
      << runs.table << "\n"
      << runs.verdict << ".\n";
    replaceMarkdownSection(md, "## Cloud formats (ladarvr bench generate)", s.str());
}

}  // namespace bench
