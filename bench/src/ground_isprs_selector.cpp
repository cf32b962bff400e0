// bench/src/ground_isprs_selector.cpp: see ground_isprs_selector.hpp. The trees learn on
// the tiles' rows of the other sites and predict the left-out site's tiles.
#include "ground_isprs_selector.hpp"

#include "ground_isprs_selector_fits.hpp"
#include "ground_isprs_selector_segments.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace bench {
namespace {

// What the sets say over `members`: the place's density (a ratio to the sample's), share of
// its area with points, terrain slope, relief and curvature; per set the share called
// ground, the mean height above its terrain and the shares of points high above it and
// just above it; per set but the base, the share labelled otherwise, how far its terrain
// lies from the base's (mean, 90th percentile) and the ground it drops and adds.
std::vector<float> placeFeatures(const SampleFits& f, const std::vector<std::size_t>& members,
                                 const std::vector<std::size_t>& sets, double area_m2) {
    const double n = double(std::max<std::size_t>(1, members.size()));
    std::vector<std::uint64_t> cells;
    std::vector<double> slope, terrain, rough;
    for (const std::size_t i : members) {
        cells.push_back(f.cell[i]);
        slope.push_back(f.slope[i]);
        terrain.push_back(f.terrain_m[i]);
        rough.push_back(f.rough_m[i]);
    }
    std::sort(cells.begin(), cells.end());
    const double occupied = double(std::unique(cells.begin(), cells.end()) - cells.begin());
    std::vector<float> x = {
        float(occupied > 0 && f.points_per_cell > 0 ? std::log2(n / occupied / f.points_per_cell) : 0.0),
        float(std::min(1.0, occupied / area_m2)),
        float(quantile(slope, 0.5)),
        float(quantile(slope, 0.9)),
        float(quantile(terrain, 0.95) - quantile(terrain, 0.05)),
        float(quantile(rough, 0.5)),
    };
    const std::size_t base = sets[0];
    for (const std::size_t g : sets) {
        double ground = 0, height = 0, high = 0, low = 0;
        for (const std::size_t i : members) {
            const double h = f.height_m[g][i];
            ground += f.ground[g][i];
            height += std::clamp(h, -5.0, 20.0);
            high += h > 2.5;
            low += h > 0.3 && h <= 2.5;
        }
        x.insert(x.end(), {float(ground / n), float(height / n), float(high / n), float(low / n)});
        if (g == base) continue;
        double differ = 0, lost = 0, gained = 0, shift = 0;
        std::vector<double> apart;
        for (const std::size_t i : members) {
            const double d = double(f.height_m[base][i]) - double(f.height_m[g][i]);  // its terrain minus the base's
            differ += f.ground[g][i] != f.ground[base][i];
            lost += f.ground[base][i] && !f.ground[g][i];
            gained += !f.ground[base][i] && f.ground[g][i];
            shift += d;
            apart.push_back(std::abs(d));
        }
        x.insert(x.end(), {float(differ / n), float(shift / n), float(quantile(apart, 0.9)), float(lost / n),
                           float(gained / n)});
    }
    return x;
}

// How the sets are compared: the tile, which sets, which trees, and whether each row
// carries its whole sample's description besides the tile's.
struct Variant {
    double tile_m = 50;
    std::vector<std::size_t> sets;
    bool multiclass = false;
    bool context = false;
    TreeShape shape;
    std::string place() const {
        std::ostringstream s;
        s << sets.size() << " sets (";
        for (std::size_t k = 0; k < sets.size(); ++k) s << (k ? ", " : "") << selectorSets()[sets[k]].name;
        s << "), " << tile_m << " m tiles";
        return s.str();
    }
    std::string describe() const {
        return place() + (multiclass ? ", one multi-class tree set" : ", pairwise trees") +
               (context ? ", with the sample's description" : "") + shape.describe();
    }
};

// One tile's row: its sample, its points, its features and its wrong points under each set
// of the variant.
struct TileRow {
    std::size_t sample = 0;
    const std::vector<std::size_t>* points = nullptr;
    std::vector<float> x;
    std::vector<double> wrong;
};

std::vector<TileRow> tileRows(const std::vector<AdaptiveSample>& samples, const std::vector<SampleFits>& fits,
                              const std::vector<Tiles>& tiles, const Variant& v) {
    std::vector<TileRow> rows;
    for (std::size_t k = 0; k < samples.size(); ++k) {
        std::vector<float> context;
        if (v.context) {
            std::vector<std::size_t> all(samples[k].points->size());
            for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
            context = placeFeatures(fits[k], all, v.sets, double(all.size()));
        }
        for (const std::vector<std::size_t>& members : tiles[k].members) {
            if (members.empty()) continue;
            TileRow r{k, &members, placeFeatures(fits[k], members, v.sets, v.tile_m * v.tile_m), {}};
            r.x.insert(r.x.end(), context.begin(), context.end());
            for (const std::size_t g : v.sets) {
                double wrong = 0;
                for (const std::size_t i : members)
                    wrong += ((*samples[k].truth)[i] != 0) != (fits[k].ground[g][i] != 0);
                r.wrong.push_back(wrong);
            }
            rows.push_back(std::move(r));
        }
    }
    return rows;
}

std::size_t argmin(const std::vector<double>& v) {
    return std::size_t(std::min_element(v.begin(), v.end()) - v.begin());
}

// Each test row's chosen position in v.sets, from trees learned on the training rows.
std::vector<std::size_t> chooseTiles(const std::vector<AdaptiveSample>& samples, const std::vector<TileRow>& rows,
                                     const std::vector<std::size_t>& train, const std::vector<std::size_t>& test,
                                     const Variant& v) {
    const std::size_t columns = rows[0].x.size(), sets = v.sets.size();
    std::vector<float> test_x;
    for (const std::size_t r : test) test_x.insert(test_x.end(), rows[r].x.begin(), rows[r].x.end());
    // The rows to learn from (those where the sets differ), their weights averaging 1.
    const auto learn = [&](const auto& target, int classes) {
        std::vector<float> x, labels, weights;
        double sum = 0;
        for (const std::size_t r : train) {
            const auto [label, weight] = target(rows[r]);
            if (weight <= 0) continue;
            x.insert(x.end(), rows[r].x.begin(), rows[r].x.end());
            labels.push_back(label);
            weights.push_back(weight);
            sum += weight;
        }
        for (float& w : weights) w = float(w * double(weights.size()) / sum);
        if (labels.empty()) return std::vector<float>(test.size() * std::size_t(classes == 2 ? 1 : classes), 0.0f);
        return learnAndPredict(x, labels, weights, test_x, columns, classes, v.shape);
    };
    const auto points = [&](const TileRow& r) { return double(samples[r.sample].points->size()); };
    std::vector<std::size_t> chosen(test.size(), 0);
    if (v.multiclass) {
        // The best set's class; weight the mean of what the others lose against it.
        const std::vector<float> p = learn(
            [&](const TileRow& r) {
                const std::size_t best = argmin(r.wrong);
                double regret = 0;
                for (const double w : r.wrong) regret += w - r.wrong[best];
                return PairTarget{float(best), float(100.0 * regret / double(sets - 1) / points(r))};
            },
            int(sets));
        for (std::size_t t = 0; t < test.size(); ++t)
            chosen[t] = std::size_t(
                std::max_element(p.begin() + std::ptrdiff_t(t * sets), p.begin() + std::ptrdiff_t((t + 1) * sets)) -
                (p.begin() + std::ptrdiff_t(t * sets)));
        return chosen;
    }
    std::vector<std::vector<double>> beats(test.size());
    for (std::size_t g = 1; g < sets; ++g) {
        const std::vector<float> p =
            learn([&](const TileRow& r) { return pairTarget(r.wrong[0], r.wrong[g], points(r)); }, 2);
        for (std::size_t t = 0; t < test.size(); ++t) beats[t].push_back(p[t]);
    }
    for (std::size_t t = 0; t < test.size(); ++t) chosen[t] = choosePairwise(beats[t]);
    return chosen;
}

// Per sample: the counts of the labels each tile takes from its chosen set.
struct Outcome {
    std::vector<Counts> selector, oracle;
    std::vector<std::vector<std::uint8_t>> labels;
};

Outcome scoreVariant(const std::vector<AdaptiveSample>& samples, const std::vector<SampleFits>& fits,
                     const std::vector<Tiles>& tiles, const Variant& v) {
    const std::vector<TileRow> rows = tileRows(samples, fits, tiles, v);
    std::vector<Confusion> selector(samples.size()), oracle(samples.size());
    Outcome out;
    for (std::size_t k = 0; k < samples.size(); ++k) out.labels.emplace_back(samples[k].points->size(), 0);
    std::vector<char> sites;
    for (const AdaptiveSample& a : samples)
        if (std::find(sites.begin(), sites.end(), a.name[4]) == sites.end()) sites.push_back(a.name[4]);
    for (const char site : sites) {
        std::vector<std::size_t> train, test;
        for (std::size_t r = 0; r < rows.size(); ++r)
            (samples[rows[r].sample].name[4] == site ? test : train).push_back(r);
        const std::vector<std::size_t> chosen = chooseTiles(samples, rows, train, test, v);
        for (std::size_t t = 0; t < test.size(); ++t) {
            const TileRow& r = rows[test[t]];
            const std::size_t best = argmin(r.wrong);
            for (const std::size_t i : *r.points) {
                const bool truth = (*samples[r.sample].truth)[i] != 0;
                const std::uint8_t found = fits[r.sample].ground[v.sets[chosen[t]]][i];
                out.labels[r.sample][i] = found;
                selector[r.sample].add(truth, found != 0);
                oracle[r.sample].add(truth, fits[r.sample].ground[v.sets[best]][i] != 0);
            }
        }
    }
    for (std::size_t k = 0; k < samples.size(); ++k) {
        out.selector.push_back(countsOf(selector[k]));
        out.oracle.push_back(countsOf(oracle[k]));
    }
    return out;
}

std::vector<Counts> baseCounts(const std::vector<AdaptiveSample>& samples, const std::vector<SampleFits>& fits) {
    std::vector<Counts> base;
    for (std::size_t k = 0; k < samples.size(); ++k) {
        Confusion c;
        for (std::size_t i = 0; i < fits[k].ground[0].size(); ++i)
            c.add((*samples[k].truth)[i] != 0, fits[k].ground[0][i] != 0);
        base.push_back(countsOf(c));
    }
    return base;
}

}  // namespace

const std::vector<SelectorSet>& selectorSets() {
    static const std::vector<SelectorSet> sets = {
        {"default", 0.15, 18.0, 0.5, 1.25},
        {"gentle 0.06", 0.06, 18.0, 0.3, 1.25},
        {"steep 0.35, 8 m", 0.35, 8.0, 0.5, 1.25},
        {"steep 0.35, 8 m, scalar 2", 0.35, 8.0, 0.5, 2.0},
    };
    return sets;
}

std::size_t choosePairwise(const std::vector<double>& beats_base) {
    std::size_t chosen = 0;
    double best = 0.5;
    for (std::size_t g = 0; g < beats_base.size(); ++g)
        if (beats_base[g] > best) best = beats_base[g], chosen = g + 1;
    return chosen;
}

PairTarget pairTarget(double wrong_base, double wrong_other, double sample_points) {
    PairTarget t;
    t.label = wrong_other < wrong_base ? 1.0f : 0.0f;
    t.weight = sample_points > 0 ? float(100.0 * std::abs(wrong_base - wrong_other) / sample_points) : 0.0f;
    return t;
}

std::vector<std::vector<std::uint8_t>> runSelector(const std::vector<AdaptiveSample>& samples) {
    std::vector<char> sites;
    for (const AdaptiveSample& a : samples)
        if (std::find(sites.begin(), sites.end(), a.name[4]) == sites.end()) sites.push_back(a.name[4]);
    if (sites.size() < 2)
        throw core::Error("bench ground-isprs: --selector: the samples come from " + std::to_string(sites.size()) +
                          " site; allowed samples of at least two sites (leave-one-site-out)");
    std::vector<SampleFits> fits;
    for (const AdaptiveSample& a : samples) {
        fits.push_back(fitSample(*a.points));
        std::fprintf(stderr, "bench ground-isprs: selector: %s fitted with %zu sets\n", a.name.c_str(),
                     selectorSets().size());
    }
    std::printf("SMRF's option set chosen per tile by learned trees, leave-one-site-out. The sets:");
    for (const SelectorSet& s : selectorSets())
        std::printf(" %s (slope %g, window %g m, threshold %g m, scalar %g);", s.name, s.slope, s.window_m,
                    s.threshold_m, s.scalar);
    std::printf(
        "\n\n| configuration | mean type I | mean type II | mean total error | mean kappa | samples past CSF "
        "published + 1 |\n|---|---:|---:|---:|---:|---|\n");
    const std::vector<Counts> base = baseCounts(samples, fits);
    printLine("`ladarvr ground` (the default set)", samples, base);
    const std::vector<std::vector<std::size_t>> subsets = {{0, 1}, {0, 2}, {0, 1, 2}, {0, 1, 2, 3}};
    const Variant primary{50.0, {0, 1, 2}, false, false, TreeShape{}};
    Outcome chosen;
    for (const double tile_m : {100.0, 50.0, 25.0}) {
        std::vector<Tiles> tiles;
        for (const AdaptiveSample& a : samples) tiles.push_back(tilesOf(*a.points, tile_m));
        for (const std::vector<std::size_t>& sets : subsets) {
            bool oracle_printed = false;
            for (const bool multiclass : {false, true})
                for (const bool context : {false, true}) {
                    if (multiclass && sets.size() == 2) continue;  // the same choice as the pairwise trees
                    const Variant v{tile_m, sets, multiclass, context, TreeShape{}};
                    Outcome o = scoreVariant(samples, fits, tiles, v);
                    if (!oracle_printed) printLine("oracle, each tile's best of " + v.place(), samples, o.oracle);
                    oracle_printed = true;
                    printLine("selector, " + v.describe(), samples, o.selector);
                    if (v.tile_m == primary.tile_m && v.sets == primary.sets && !multiclass && !context)
                        chosen = std::move(o);
                }
        }
    }
    const std::vector<Counts> patches = printSegmentSelector(samples, fits, TreeShape{});
    // Other shapes of trees, for the variant fixed beforehand and the patches of 3 sets.
    for (const TreeShape shape : {TreeShape{2, 100, 1}, TreeShape{4, 100, 1}, TreeShape{3, 30, 1}, TreeShape{3, 300, 1},
                                  TreeShape{3, 100, 10}}) {
        std::vector<Tiles> tiles;
        for (const AdaptiveSample& a : samples) tiles.push_back(tilesOf(*a.points, primary.tile_m));
        Variant v = primary;
        v.shape = shape;
        printLine("selector, " + v.describe(), samples, scoreVariant(samples, fits, tiles, v).selector);
        printSegmentSelector(samples, fits, shape, true);
    }
    std::printf(
        "\nPer sample, total error %% (kappa), the selector fixed beforehand (%s) and the same 3 sets "
        "chosen per patch of disagreement:\n\n"
        "| sample | `ladarvr ground` | oracle | selector | per patch | CSF published |\n"
        "|---|---:|---:|---:|---:|---:|\n",
        primary.describe().c_str());
    for (std::size_t k = 0; k < samples.size(); ++k)
        std::printf("| %s | %.2f (%.1f) | %.2f (%.1f) | %.2f (%.1f) | %.2f (%.1f) | %.2f |\n", samples[k].name.c_str(),
                    base[k].total, base[k].kappa, chosen.oracle[k].total, chosen.oracle[k].kappa,
                    chosen.selector[k].total, chosen.selector[k].kappa, patches[k].total, patches[k].kappa,
                    csfPublishedTotal(samples[k].name));
    const Counts mb = meanOf(base), mo = meanOf(chosen.oracle), ms = meanOf(chosen.selector), mp = meanOf(patches);
    std::printf("| mean | %.2f (%.1f) | %.2f (%.1f) | %.2f (%.1f) | %.2f (%.1f) | |\n", mb.total, mb.kappa, mo.total,
                mo.kappa, ms.total, ms.kappa, mp.total, mp.kappa);
    std::fflush(stdout);
    return std::move(chosen.labels);
}

}  // namespace bench
