// bench/src/ground_isprs_adaptive.cpp: see ground_isprs_adaptive.hpp.
#include "ground_isprs_adaptive.hpp"

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <sim/ground_adaptive.hpp>
#include <sim/ground_file.hpp>

#include <atomic>
#include <cstdio>
#include <mutex>
#include <sstream>
#include <thread>

namespace bench {
namespace {

struct GridPoint {
    double cell_m, slope, window_m, threshold_m, scalar;
};

struct Counts {
    double type1 = 0, type2 = 0, total = 0, kappa = 0;
};

Counts scoreOf(const std::vector<std::uint8_t>& found, const std::vector<std::uint8_t>& truth) {
    double gg = 0, go = 0, og = 0, oo = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
        if (truth[i])
            (found[i] ? gg : go) += 1;
        else
            (found[i] ? og : oo) += 1;
    }
    const double n = gg + go + og + oo;
    Counts s;
    s.type1 = gg + go > 0 ? 100.0 * go / (gg + go) : 0.0;
    s.type2 = og + oo > 0 ? 100.0 * og / (og + oo) : 0.0;
    s.total = n > 0 ? 100.0 * (go + og) / n : 0.0;
    const double po = n > 0 ? (gg + oo) / n : 1.0;
    const double pe = n > 0 ? ((gg + go) * (gg + og) + (og + oo) * (go + oo)) / (n * n) : 0.0;
    s.kappa = pe < 1.0 ? 100.0 * (po - pe) / (1.0 - pe) : 100.0;
    return s;
}

}  // namespace

void writeAdaptiveGrid(const std::vector<AdaptiveSample>& samples, const std::string& csv) {
    // Around `ladarvr ground`'s defaults (cell 1 m, slope 0.15, window 18 m, threshold 0.5 m,
    // scalar 1.25): the openings' slope and window on a grid, with the tolerance changed
    // one way at a time.
    std::vector<GridPoint> grid;
    const double tolerances[][2] = {{0.5, 1.25}, {0.3, 1.25}, {0.7, 1.25}, {0.5, 0.5}, {0.5, 2.0}};
    for (const double slope : {0.06, 0.1, 0.15, 0.22, 0.35})
        for (const double window : {8.0, 12.0, 18.0, 27.0})
            for (const auto& t : tolerances) grid.push_back({1.0, slope, window, t[0], t[1]});
    std::vector<std::string> lines(samples.size() * grid.size());
    std::atomic<std::size_t> next{0};
    std::mutex print;
    const auto work = [&] {
        for (;;) {
            const std::size_t job = next++;
            if (job >= lines.size()) return;
            const AdaptiveSample& s = samples[job / grid.size()];
            const GridPoint& g = grid[job % grid.size()];
            sim::GroundFileOptions o;
            o.smrf.cell_m = g.cell_m;
            o.smrf.slope = g.slope;
            o.smrf.window_m = g.window_m;
            o.smrf.threshold_m = g.threshold_m;
            o.smrf.scalar = g.scalar;
            const Counts c = scoreOf(sim::classifyGround(*s.points, o), *s.truth);
            std::ostringstream line;
            line << s.name << "," << g.cell_m << "," << g.slope << "," << g.window_m << "," << g.threshold_m << ","
                 << g.scalar << "," << c.type1 << "," << c.type2 << "," << c.total << "," << c.kappa << "\n";
            lines[job] = line.str();
            if (job % grid.size() == grid.size() - 1) {
                const std::lock_guard<std::mutex> lock(print);
                std::fprintf(stderr, "bench ground-isprs: grid: %s done\n", s.name.c_str());
            }
        }
    };
    std::thread other(work);
    work();
    other.join();
    std::string text = "sample,cell_m,slope,window_m,threshold_m,scalar,type1,type2,total,kappa\n";
    for (const std::string& l : lines) text += l;
    platform::writeFileAtomic(csv, text);
}

void writeAdaptiveTraits(const std::vector<AdaptiveSample>& samples, const std::string& csv) {
    std::string text = "sample";
    for (const std::string& name : sim::surveyTraitNames()) text += "," + name;
    text += "\n";
    for (const AdaptiveSample& s : samples) {
        std::ostringstream line;
        line << s.name;
        for (const double v : sim::traitValues(sim::measureSurvey(*s.points, sim::surveySmrfOptions())))
            line << "," << v;
        text += line.str() + "\n";
    }
    platform::writeFileAtomic(csv, text);
}

}  // namespace bench
