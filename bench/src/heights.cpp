// bench/src/heights.cpp: `ladarvr bench heights`: what the colour range without stray
// returns (core::HeightSpan) costs per point, on a real survey's heights in file order.
// Three loops over the same heights, in turn, each repeated: the running maximum alone
// (what the viewer's upload loop did before, the baseline), HeightSpan::add on every
// height (`info`, `ground --whiten`), and HeightSpan::addSampled with one in 8 inside the
// body (the viewer's uploads). Prints ns per point, median [min..max], each against the
// baseline, and what it comes to on a frame that uploads the viewer's default budget.
#include "common.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <core/height_span.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace bench {
namespace {

struct HeightsCli {
    std::string in;
    int repeats = 15, warmup = 3;
};

constexpr std::size_t kUploadPoints = 262144;  // the viewer's default upload budget per frame

void run(const HeightsCli& cli) {
    if (cli.repeats < 1 || cli.repeats > 1000)
        throw core::Error("bench heights: --repeats " + std::to_string(cli.repeats) + "; allowed [1, 1000]");
    if (cli.warmup < 0 || cli.warmup > 100)
        throw core::Error("bench heights: --warmup " + std::to_string(cli.warmup) + "; allowed [0, 100]");
    const std::string in = cli.in.empty() ? (sourceRoot() / "tests/data/real/FSite5_orig-utm.laz").string() : cli.in;
    io::CloudReader reader(in);
    const core::PointCloud cloud = io::readCloud(reader);
    std::vector<float> z;
    z.reserve(cloud.points.size());
    for (const core::CloudPoint& p : cloud.points) z.push_back(p.position.z);
    if (z.empty()) throw core::Error("bench heights: " + in + " holds no points; allowed a cloud with points");

    float sink = 0;  // each loop's result, so the compiler keeps the loop
    const std::function<void()> loops[] = {
        [&] {
            float top = -1e30f;
            for (const float v : z) top = std::max(top, v);
            sink += top;
        },
        [&] {
            core::HeightSpan s(core::kStrayGap_m);
            for (const float v : z) s.add(v);
            sink += float(s.span().hi);
        },
        [&] {
            core::HeightSpan s(core::kStrayGap_m);
            for (const float v : z) s.addSampled(v, 8);
            sink += float(s.span().hi);
        },
    };
    const char* names[] = {"running maximum only (baseline)", "HeightSpan::add, every point",
                           "HeightSpan::addSampled, 1 in 8 inside the body (the viewer)"};
    std::vector<std::vector<double>> ns(3);
    for (int r = 0; r < cli.warmup + cli.repeats; ++r)
        for (std::size_t k = 0; k < 3; ++k) {
            const auto t0 = Clock::now();
            loops[k]();
            if (r >= cli.warmup) ns[k].push_back(msSince(t0) * 1e6 / double(z.size()));
        }
    const Spread base = spread(ns[0]);
    std::printf("ladarvr bench heights: %s (%zu points), %s (%u cores), %s; warm-up %d, %d repeats\n\n", in.c_str(),
                z.size(), cpuName().c_str(), std::thread::hardware_concurrency(), utcNow().c_str(), cli.warmup,
                cli.repeats);
    std::printf("| loop | ns per point | against the baseline | ms per 262,144 points |\n|---|---:|---:|---:|\n");
    for (std::size_t k = 0; k < 3; ++k) {
        const Spread s = spread(ns[k]);
        std::printf("| %s | %s | %s | %s |\n", names[k], fmtSpread("%.2f", s).c_str(),
                    k == 0 ? "1.00x" : (fmt("%.1fx", s.median / base.median) + spreadNote(s, base)).c_str(),
                    fmt("%.2f", s.median * double(kUploadPoints) * 1e-6).c_str());
    }
    std::fprintf(stderr, "bench heights: checksum %g\n", double(sink));
}

}  // namespace

void registerHeights(CLI::App& parent) {
    auto state = std::make_shared<HeightsCli>();
    CLI::App* c = parent.add_subcommand(
        "heights",
        "the colour range without stray returns (core::HeightSpan): ns per point, every point and the "
        "viewer's sample, against a running maximum (prints only)");
    c->add_option("--in", state->in, "a cloud file (default: tests/data/real/FSite5_orig-utm.laz)");
    c->add_option("--repeats", state->repeats, "measured runs of each loop, [1, 1000]")->capture_default_str();
    c->add_option("--warmup", state->warmup, "unmeasured runs of each loop first, [0, 100]")->capture_default_str();
    c->callback([state] { run(*state); });
}

}  // namespace bench
