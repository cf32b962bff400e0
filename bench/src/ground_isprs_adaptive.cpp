// bench/src/ground_isprs_adaptive.cpp: see ground_isprs_adaptive.hpp.
#include "ground_isprs_adaptive.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>
#include <platform/atomic_file.hpp>
#include <sim/ground_adaptive.hpp>
#include <sim/ground_file.hpp>

#include <algorithm>
#include <atomic>
#include <iomanip>
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

double meanOver(const std::vector<std::vector<double>>& errors, const std::vector<std::size_t>& rows, std::size_t set) {
    double sum = 0;
    for (const std::size_t k : rows) sum += errors[k][set];
    return rows.empty() ? 0.0 : sum / double(rows.size());
}

std::string describeSet(const GridPoint& g) {
    std::ostringstream s;
    s << "slope " << g.slope << ", window " << g.window_m << " m, threshold " << g.threshold_m << " m, scalar "
      << g.scalar;
    return s.str();
}

void printMean(const char* what, const std::vector<AdaptiveSample>& samples, const std::vector<Counts>& chosen) {
    Counts mean;
    std::ostringstream per;
    for (std::size_t k = 0; k < chosen.size(); ++k) {
        mean.type1 += chosen[k].type1 / double(chosen.size());
        mean.type2 += chosen[k].type2 / double(chosen.size());
        mean.total += chosen[k].total / double(chosen.size());
        mean.kappa += chosen[k].kappa / double(chosen.size());
        per << " " << samples[k].name << " " << std::fixed << std::setprecision(2) << chosen[k].total;
    }
    std::printf("%s: mean type I %.2f, type II %.2f, total %.2f %%, kappa %.1f %% (%s)\n", what, mean.type1, mean.type2,
                mean.total, mean.kappa, per.str().c_str() + 1);
}

void summarise(const std::vector<AdaptiveSample>& samples, const std::vector<GridPoint>& grid,
               const std::vector<std::vector<Counts>>& counts);

}  // namespace

std::size_t SelectionRule::choose(const std::vector<double>& traits) const {
    if (trait < 0) return base;
    const double v = traits[std::size_t(trait)];
    return (above ? v > threshold : v <= threshold) ? alternative : base;
}

SelectionRule fitSelectionRule(const std::vector<std::vector<double>>& errors,
                               const std::vector<std::vector<double>>& traits, const std::vector<std::size_t>& train,
                               std::size_t base) {
    SelectionRule best;
    best.base = best.alternative = base;
    double best_error = meanOver(errors, train, base);
    if (train.empty()) return best;
    const std::size_t sets = errors[train[0]].size(), columns = traits[train[0]].size();
    for (std::size_t f = 0; f < columns; ++f) {
        std::vector<double> values;
        for (const std::size_t k : train) values.push_back(traits[k][f]);
        std::sort(values.begin(), values.end());
        values.erase(std::unique(values.begin(), values.end()), values.end());
        for (std::size_t v = 0; v + 1 < values.size(); ++v)
            for (const bool above : {true, false}) {
                SelectionRule r;
                r.trait = int(f);
                r.threshold = (values[v] + values[v + 1]) / 2.0;
                r.above = above;
                r.base = base;
                std::vector<std::size_t> picked, kept;
                for (const std::size_t k : train)
                    ((above ? traits[k][f] > r.threshold : traits[k][f] <= r.threshold) ? picked : kept).push_back(k);
                if (picked.size() < 2) continue;
                std::size_t alternative = base;
                double picked_error = meanOver(errors, picked, base);
                for (std::size_t g = 0; g < sets; ++g)
                    if (const double e = meanOver(errors, picked, g); e < picked_error)
                        picked_error = e, alternative = g;
                const double error =
                    (picked_error * double(picked.size()) + meanOver(errors, kept, base) * double(kept.size())) /
                    double(train.size());
                if (error < best_error - 1e-9) {
                    r.alternative = alternative;
                    best = r;
                    best_error = error;
                }
            }
    }
    return best;
}

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
    std::vector<std::vector<Counts>> counts(samples.size(), std::vector<Counts>(grid.size()));
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
            counts[job / grid.size()][job % grid.size()] = c;
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
    summarise(samples, grid, counts);
}

namespace {

// The oracle, the best one set, and the rule fitted leave-one-site-out.
void summarise(const std::vector<AdaptiveSample>& samples, const std::vector<GridPoint>& grid,
               const std::vector<std::vector<Counts>>& counts) {
    const sim::SmrfOptions d = sim::surveySmrfOptions();
    std::size_t base = 0;
    for (std::size_t g = 0; g < grid.size(); ++g)
        if (grid[g].slope == d.slope && grid[g].window_m == d.window_m && grid[g].threshold_m == d.threshold_m &&
            grid[g].scalar == d.scalar && grid[g].cell_m == d.cell_m)
            base = g;
    std::vector<std::vector<double>> errors(samples.size()), traits;
    for (std::size_t k = 0; k < samples.size(); ++k) {
        for (const Counts& c : counts[k]) errors[k].push_back(c.total);
        traits.push_back(sim::traitValues(sim::measureSurvey(*samples[k].points, d)));
    }
    std::vector<Counts> oracle, defaults, loso(samples.size());
    for (std::size_t k = 0; k < samples.size(); ++k) {
        const auto best = std::min_element(errors[k].begin(), errors[k].end()) - errors[k].begin();
        oracle.push_back(counts[k][std::size_t(best)]);
        defaults.push_back(counts[k][base]);
        std::printf("%s: best of the grid %s (%.2f %%; `ladarvr ground`'s %.2f %%)\n", samples[k].name.c_str(),
                    describeSet(grid[std::size_t(best)]).c_str(), oracle.back().total, defaults.back().total);
    }
    printMean("`ladarvr ground`'s options", samples, defaults);
    printMean("each sample's best of the grid (the oracle: it sees the reference)", samples, oracle);
    // Leave-one-site-out: the site is the sample's first digit.
    std::vector<char> sites;
    for (const AdaptiveSample& a : samples)
        if (std::find(sites.begin(), sites.end(), a.name[4]) == sites.end()) sites.push_back(a.name[4]);
    for (const char site : sites) {
        std::vector<std::size_t> train;
        for (std::size_t k = 0; k < samples.size(); ++k)
            if (samples[k].name[4] != site) train.push_back(k);
        const SelectionRule r = fitSelectionRule(errors, traits, train, base);
        for (std::size_t k = 0; k < samples.size(); ++k)
            if (samples[k].name[4] == site) loso[k] = counts[k][r.choose(traits[k])];
        if (r.trait < 0)
            std::printf("site %c left out: the rule keeps `ladarvr ground`'s options\n", site);
        else
            std::printf("site %c left out: %s where %s %s %.3g\n", site, describeSet(grid[r.alternative]).c_str(),
                        sim::surveyTraitNames()[std::size_t(r.trait)].c_str(), r.above ? ">" : "<=", r.threshold);
    }
    printMean("options chosen by the traits' rule, leave-one-site-out", samples, loso);
}

}  // namespace

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
