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

double meanOver(const std::vector<std::vector<double>>& errors, const std::vector<std::size_t>& rows, std::size_t set) {
    double sum = 0;
    for (const std::size_t k : rows) sum += errors[k][set];
    return rows.empty() ? 0.0 : sum / double(rows.size());
}

std::string fmtNumber(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
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

// Tile sizes of the per-region choice, metres.
const std::vector<double> kTiles_m = {100.0, 50.0};

std::size_t summarise(const std::vector<AdaptiveSample>& samples, const std::vector<GridPoint>& grid,
                      const std::vector<std::vector<Counts>>& counts);
void summariseTiles(const std::vector<AdaptiveSample>& samples, const std::vector<GridPoint>& grid,
                    const std::vector<Tiles>& tiles, const std::vector<std::vector<std::vector<Confusion>>>& counts,
                    std::size_t base, double tile_m);

}  // namespace

Counts countsOf(const Confusion& c) {
    const double n = c.points();
    Counts s;
    s.type1 = c.gg + c.go > 0 ? 100.0 * c.go / (c.gg + c.go) : 0.0;
    s.type2 = c.og + c.oo > 0 ? 100.0 * c.og / (c.og + c.oo) : 0.0;
    s.total = n > 0 ? 100.0 * c.wrong() / n : 0.0;
    const double po = n > 0 ? (c.gg + c.oo) / n : 1.0;
    const double pe = n > 0 ? ((c.gg + c.go) * (c.gg + c.og) + (c.og + c.oo) * (c.go + c.oo)) / (n * n) : 0.0;
    s.kappa = pe < 1.0 ? 100.0 * (po - pe) / (1.0 - pe) : 100.0;
    return s;
}

Tiles tilesOf(const std::vector<core::CloudPoint>& points, double tile_m) {
    Tiles t;
    if (points.empty()) return t;
    double x0 = points[0].position.x, y0 = points[0].position.y, x1 = x0;
    for (const core::CloudPoint& p : points) {
        x0 = std::min(x0, double(p.position.x));
        y0 = std::min(y0, double(p.position.y));
        x1 = std::max(x1, double(p.position.x));
    }
    const std::size_t columns = std::size_t((x1 - x0) / tile_m) + 1;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::size_t tile = std::size_t((double(points[i].position.y) - y0) / tile_m) * columns +
                                 std::size_t((double(points[i].position.x) - x0) / tile_m);
        if (tile >= t.members.size()) t.members.resize(tile + 1);
        t.members[tile].push_back(i);
        t.of.push_back(std::uint32_t(tile));
    }
    return t;
}

double csfPublishedTotal(const std::string& sample) {
    static const char* const names[] = {"samp11", "samp12", "samp21", "samp22", "samp23", "samp24", "samp31", "samp41",
                                        "samp42", "samp51", "samp52", "samp53", "samp54", "samp61", "samp71"};
    static const double totals[] = {12.01, 2.97, 3.42, 8.94, 4.79, 2.87, 1.61, 5.14,
                                    1.58,  3.08, 3.93, 5.20, 3.18, 1.49, 5.71};
    for (std::size_t k = 0; k < std::size(names); ++k)
        if (sample == names[k]) return totals[k];
    return -1.0;
}

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
    const std::size_t sets = errors[train[0]].size(), columns = traits[train[0]].size(), n = train.size();
    for (std::size_t f = 0; f < columns; ++f) {
        // The training rows by this trait, and the sums of each set's errors over the first i.
        std::vector<std::size_t> order = train;
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return traits[a][f] < traits[b][f]; });
        std::vector<double> prefix((n + 1) * sets, 0.0);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t g = 0; g < sets; ++g)
                prefix[(i + 1) * sets + g] = prefix[i * sets + g] + errors[order[i]][g];
        const auto sum = [&](std::size_t from, std::size_t to, std::size_t g) {
            return prefix[to * sets + g] - prefix[from * sets + g];
        };
        for (std::size_t i = 1; i < n; ++i) {
            const double below = traits[order[i - 1]][f], above_value = traits[order[i]][f];
            if (!(below < above_value)) continue;  // a threshold lies between distinct values only
            for (const bool above : {true, false}) {
                // The alternative's rows: [i, n) above the threshold, [0, i) at most at it.
                const std::size_t from = above ? i : 0, to = above ? n : i;
                if (to - from < 2) continue;
                std::size_t alternative = base;
                double picked = sum(from, to, base);
                for (std::size_t g = 0; g < sets; ++g)
                    if (const double e = sum(from, to, g); e < picked) picked = e, alternative = g;
                const double error = (picked + sum(0, n, base) - sum(from, to, base)) / double(n);
                if (error < best_error - 1e-9) {
                    best.trait = int(f);
                    best.threshold = (below + above_value) / 2.0;
                    best.above = above;
                    best.alternative = alternative;
                    best_error = error;
                }
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
    // Per tile size, sample, option set and tile: the confusion counts.
    std::vector<std::vector<Tiles>> tiles(kTiles_m.size());
    std::vector<std::vector<std::vector<std::vector<Confusion>>>> tile_counts(kTiles_m.size());
    for (std::size_t t = 0; t < kTiles_m.size(); ++t)
        for (const AdaptiveSample& a : samples) {
            tiles[t].push_back(tilesOf(*a.points, kTiles_m[t]));
            tile_counts[t].emplace_back(grid.size(), std::vector<Confusion>(tiles[t].back().members.size()));
        }
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
            const std::vector<std::uint8_t> found = sim::classifyGround(*s.points, o);
            Confusion all;
            for (std::size_t i = 0; i < found.size(); ++i) {
                all.add((*s.truth)[i] != 0, found[i] != 0);
                for (std::size_t t = 0; t < kTiles_m.size(); ++t)
                    tile_counts[t][job / grid.size()][job % grid.size()][tiles[t][job / grid.size()].of[i]].add(
                        (*s.truth)[i] != 0, found[i] != 0);
            }
            const Counts c = countsOf(all);
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
    const std::size_t base = summarise(samples, grid, counts);
    for (std::size_t t = 0; t < kTiles_m.size(); ++t)
        summariseTiles(samples, grid, tiles[t], tile_counts[t], base, kTiles_m[t]);
}

namespace {

// The oracle, the best one set, and the rule fitted leave-one-site-out.
std::size_t summarise(const std::vector<AdaptiveSample>& samples, const std::vector<GridPoint>& grid,
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
    return base;
}

// The same per tile: each tile's points labelled by the whole sample's fit with the option
// set chosen for the tile, by the oracle (the fewest wrong points in the tile) or by the
// rule on the tile's own traits fitted leave-one-site-out on the other sites' tiles.
void summariseTiles(const std::vector<AdaptiveSample>& samples, const std::vector<GridPoint>& grid,
                    const std::vector<Tiles>& tiles, const std::vector<std::vector<std::vector<Confusion>>>& counts,
                    std::size_t base, double tile_m) {
    struct Row {
        std::size_t sample, tile;
    };
    std::vector<Row> rows;
    std::vector<std::vector<double>> errors, traits;
    std::vector<Counts> oracle;
    const sim::SmrfOptions d = sim::surveySmrfOptions();
    for (std::size_t k = 0; k < samples.size(); ++k) {
        Confusion best_all;
        for (std::size_t t = 0; t < tiles[k].members.size(); ++t) {
            if (tiles[k].members[t].empty()) continue;
            std::size_t best = base;
            std::vector<double> e;
            for (std::size_t g = 0; g < grid.size(); ++g) {
                e.push_back(100.0 * counts[k][g][t].wrong() / counts[k][g][t].points());
                if (counts[k][g][t].wrong() < counts[k][best][t].wrong()) best = g;
            }
            best_all.add(counts[k][best][t]);
            std::vector<core::CloudPoint> own;
            for (const std::size_t i : tiles[k].members[t]) own.push_back((*samples[k].points)[i]);
            rows.push_back({k, t});
            errors.push_back(std::move(e));
            traits.push_back(sim::traitValues(sim::measureSurvey(own, d)));
        }
        oracle.push_back(countsOf(best_all));
    }
    const std::string what = "tiles of " + fmtNumber(tile_m) + " m";
    printMean((what + ", each tile's best of the grid (the oracle)").c_str(), samples, oracle);
    std::vector<Confusion> chosen(samples.size());
    std::vector<char> sites;
    for (const AdaptiveSample& a : samples)
        if (std::find(sites.begin(), sites.end(), a.name[4]) == sites.end()) sites.push_back(a.name[4]);
    for (const char site : sites) {
        std::vector<std::size_t> train;
        for (std::size_t r = 0; r < rows.size(); ++r)
            if (samples[rows[r].sample].name[4] != site) train.push_back(r);
        const SelectionRule rule = fitSelectionRule(errors, traits, train, base);
        for (std::size_t r = 0; r < rows.size(); ++r)
            if (samples[rows[r].sample].name[4] == site)
                chosen[rows[r].sample].add(counts[rows[r].sample][rule.choose(traits[r])][rows[r].tile]);
        if (rule.trait >= 0)
            std::printf("%s, site %c left out: %s where %s %s %.3g\n", what.c_str(), site,
                        describeSet(grid[rule.alternative]).c_str(),
                        sim::surveyTraitNames()[std::size_t(rule.trait)].c_str(),
                        rule.above ? ">" : "<=", rule.threshold);
    }
    std::vector<Counts> loso;
    for (const Confusion& c : chosen) loso.push_back(countsOf(c));
    printMean((what + ", options chosen per tile by the traits' rule, leave-one-site-out").c_str(), samples, loso);
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
