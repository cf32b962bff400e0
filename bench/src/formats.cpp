// bench/src/formats.cpp: the cost of LAZ output against binary PCD, on the same points.
// The writers get the same chunks of the cloud one after the other (reading is not
// timed), so the ratios hold on a shared machine: binary PCD, LAZ with its chunks
// compressed on every core (as `generate` writes it), and LAZ on the caller's thread
// alone (LASzip's own speed). Goal: LAZ at most a quarter of the bytes at no more than
// 2x the write time of binary PCD.
#include "formats.hpp"

#include "common.hpp"

#include <engine/cloud_io.hpp>
#include <engine/cloud_reader.hpp>

#include <cstdio>
#include <thread>
#include <sstream>
#include <system_error>
#include <vector>

namespace bench {

void benchFormats(const engine::Scene& scene, const sim::GenerateOptions& options,
                  const std::filesystem::path& dir, const std::string& config, const std::string& md) {
    namespace fs = std::filesystem;
    const auto start = Clock::now();
    const fs::path source = dir / "formats_source.pcd";
    sim::Generator(scene, options).run(source, engine::CloudFormat::PcdBinary);
    struct Remove {
        fs::path p;
        ~Remove() {
            std::error_code ec;
            fs::remove(p, ec);
        }
    } remove_source{source};
    engine::CloudReader reader(source);
    const fs::path pcd_out = dir / "formats.pcd", laz_out = dir / "formats.laz", laz1_out = dir / "formats_1.laz";
    const int threads = options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
    engine::LasOptions parallel, alone;
    parallel.threads = threads;
    parallel.memory_bytes = std::uint64_t(threads + 1) * engine::lazChunkBytes();
    alone.threads = 0;
    double pcd_s = 0.0, laz_s = 0.0, laz1_s = 0.0;
    std::size_t points = 0;
    {
        auto t = Clock::now();
        engine::CloudWriter pcd_w(pcd_out, engine::CloudFormat::PcdBinary, reader.origin(), reader.fields());
        pcd_s += secondsSince(t);
        t = Clock::now();
        engine::CloudWriter laz_w(laz_out, engine::CloudFormat::Laz, reader.origin(), reader.fields(), parallel);
        laz_s += secondsSince(t);
        t = Clock::now();
        engine::CloudWriter laz1_w(laz1_out, engine::CloudFormat::Laz, reader.origin(), reader.fields(), alone);
        laz1_s += secondsSince(t);
        std::vector<engine::CloudPoint> chunk;
        const auto timed = [&](engine::CloudWriter& w, double& s) {
            const auto t0 = Clock::now();
            w.append(chunk);
            s += secondsSince(t0);
        };
        for (;;) {
            chunk.clear();
            if (!reader.nextChunk(chunk, std::size_t(1) << 20)) break;
            points += chunk.size();
            timed(pcd_w, pcd_s);
            timed(laz_w, laz_s);
            timed(laz1_w, laz1_s);
        }
        const auto committed = [&](engine::CloudWriter& w, double& s) {
            const auto t0 = Clock::now();
            w.commit();
            s += secondsSince(t0);
        };
        committed(pcd_w, pcd_s);
        committed(laz_w, laz_s);
        committed(laz1_w, laz1_s);
    }
    const double pcd_mib = double(fs::file_size(pcd_out)) / 1048576.0;
    const double laz_mib = double(fs::file_size(laz_out)) / 1048576.0;
    const double laz1_mib = double(fs::file_size(laz1_out)) / 1048576.0;
    const bool same_file = fs::file_size(laz_out) == fs::file_size(laz1_out);
    std::error_code ec;
    fs::remove(pcd_out, ec);
    fs::remove(laz_out, ec);
    fs::remove(laz1_out, ec);

    std::ostringstream t;
    t << "| format | write (s) | Mpoints/s | size (MiB) | bytes/point | size vs binary PCD | time vs binary PCD |\n"
      << "|---|---|---|---|---|---|---|\n";
    const auto row = [&](const char* name, double s, double mib) {
        t << "| " << name << " | " << fmt("%.2f", s) << " | " << fmt("%.2f", double(points) / s / 1e6) << " | "
          << fmt("%.1f", mib) << " | " << fmt("%.2f", mib * 1048576.0 / double(points)) << " | "
          << fmt("%.3fx", mib / pcd_mib) << " | " << fmt("%.2fx", s / pcd_s) << " |\n";
    };
    row("binary PCD (engine::CloudWriter)", pcd_s, pcd_mib);
    const std::string laz_name = "LAZ, chunks compressed on " + std::to_string(threads) + " threads";
    row(laz_name.c_str(), laz_s, laz_mib);
    row("LAZ, on the caller's thread alone", laz1_s, laz1_mib);
    const bool size_ok = laz_mib <= 0.25 * pcd_mib, time_ok = laz_s <= 2.0 * pcd_s;
    const std::string verdict = std::string("LAZ: ") + fmt("%.3f", laz_mib / pcd_mib) + " of the bytes (goal <= 0.25: " +
                                (size_ok ? "met" : "missed") + "), " + fmt("%.2f", laz_s / pcd_s) +
                                "x the write time (goal <= 2x: " + (time_ok ? "met" : "missed") + "); " +
                                fmt("%.2f", laz1_s / laz_s) + "x faster than on one thread" +
                                (same_file ? "" : "; THE TWO LAZ FILES DIFFER IN SIZE");
    std::printf("\n%s\n%s\n", t.str().c_str(), verdict.c_str());
    if (md.empty()) return;
    std::ostringstream s;
    s << "## Cloud formats (ladarvr bench generate)\n\n"
      << "Command: `./ladarvr bench generate`; " << utcNow() << "; " << cpuName() << "; "
      << fmt("%.0f", secondsSince(start)) << " s. The cloud of the " << config << " configuration ("
      << points << " points, fields x y z rgb label view range), read back chunk by chunk and written "
         "again by both writers in turn, each timed on its own (reading excluded): binary PCD as the "
         "generator writes it, and LAZ (LAS 1.4 point format 7, 1 mm scale, extra bytes range and label; "
         "chunks of " << engine::lazChunkPoints() << " points compressed by LASzip on worker threads, "
         "the file LASzip writes alone, byte for byte), then the same LAZ on one thread. One run each.\n\n"
      << t.str() << "\n" << verdict << ".\n";
    replaceMarkdownSection(md, "## Cloud formats (ladarvr bench generate)", s.str());
}

}  // namespace bench
