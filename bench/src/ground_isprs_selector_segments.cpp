// bench/src/ground_isprs_selector_segments.cpp: see ground_isprs_selector_segments.hpp.
#include "ground_isprs_selector_segments.hpp"

#include "ground_isprs_selector.hpp"

#include <core/point_cloud.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace bench {
namespace {

// A point's 2 m cell: (row, column) from its 1 m cell.
std::int64_t rowOf(std::uint64_t cell) { return std::int64_t(cell >> 32) / 2; }
std::int64_t columnOf(std::uint64_t cell) { return std::int64_t(cell & 0xffffffffu) / 2; }
std::uint64_t keyOf(std::int64_t row, std::int64_t column) {
    return (std::uint64_t(row) << 32) | std::uint64_t(column);
}

// The points of each 2 m cell: (cell, point) sorted, looked up by cell.
struct CellIndex {
    std::vector<std::pair<std::uint64_t, std::size_t>> entries;
    template <class Keep>
    CellIndex(const SampleFits& f, Keep keep) {
        for (std::size_t i = 0; i < f.cell.size(); ++i)
            if (keep(i)) entries.push_back({keyOf(rowOf(f.cell[i]), columnOf(f.cell[i])), i});
        std::sort(entries.begin(), entries.end());
    }
    // [first, last) of the cell's entries.
    std::pair<std::size_t, std::size_t> find(std::int64_t row, std::int64_t column) const {
        if (row < 0 || column < 0) return {0, 0};
        const std::uint64_t key = keyOf(row, column);
        const auto lo = std::lower_bound(entries.begin(), entries.end(), std::make_pair(key, std::size_t(0)));
        auto hi = lo;
        while (hi != entries.end() && hi->first == key) ++hi;
        return {std::size_t(lo - entries.begin()), std::size_t(hi - entries.begin())};
    }
};

// The residual spread of z about the least-squares plane through the points.
double planeResidual_m(const std::vector<core::CloudPoint>& points, const std::vector<std::size_t>& members) {
    if (members.size() < 4) return 0.0;
    double mx = 0, my = 0, mz = 0;
    for (const std::size_t i : members)
        mx += points[i].position.x, my += points[i].position.y, mz += points[i].position.z;
    const double n = double(members.size());
    mx /= n, my /= n, mz /= n;
    double sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0, szz = 0;
    for (const std::size_t i : members) {
        const double x = points[i].position.x - mx, y = points[i].position.y - my, z = points[i].position.z - mz;
        sxx += x * x, sxy += x * y, syy += y * y, sxz += x * z, syz += y * z, szz += z * z;
    }
    const double det = sxx * syy - sxy * sxy;
    if (std::abs(det) < 1e-9) return std::sqrt(szz / n);
    const double a = (sxz * syy - syz * sxy) / det, b = (syz * sxx - sxz * sxy) / det;
    const double residual = szz - a * sxz - b * syz;  // the sum of squares left
    return std::sqrt(std::max(0.0, residual) / n);
}

// A patch's row: its size, which way the set moves it, its heights above both terrains,
// its spread and planarity, the step from the ground around it, how much of its ring holds
// points, the terrain's slope and curvature, its density as a ratio to the sample's.
std::vector<float> patchFeatures(const std::vector<core::CloudPoint>& points, const SampleFits& f, const CellIndex& all,
                                 const std::vector<std::size_t>& members, std::size_t g) {
    const double n = double(members.size());
    std::vector<std::uint64_t> cells;
    double base_ground = 0, hb = 0, hg = 0, apart = 0, z = 0, slope = 0, rough = 0;
    std::vector<double> hbs, hgs, zs;
    for (const std::size_t i : members) {
        cells.push_back(keyOf(rowOf(f.cell[i]), columnOf(f.cell[i])));
        base_ground += f.ground[0][i];
        hb += f.height_m[0][i], hg += f.height_m[g][i];
        hbs.push_back(f.height_m[0][i]), hgs.push_back(f.height_m[g][i]);
        apart += double(f.height_m[0][i]) - double(f.height_m[g][i]);
        z += points[i].position.z, zs.push_back(points[i].position.z);
        slope += f.slope[i], rough += f.rough_m[i];
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    double spread = 0;
    for (const double v : zs) spread += (v - z / n) * (v - z / n);
    // The ring: the patch's cells and their 8 neighbours; the points there both sets call ground.
    double around = 0, around_n = 0, ring = 0, ring_held = 0;
    for (const std::uint64_t c : cells)
        for (std::int64_t dr = -1; dr <= 1; ++dr)
            for (std::int64_t dc = -1; dc <= 1; ++dc) {
                const std::int64_t r = std::int64_t(c >> 32) + dr, col = std::int64_t(c & 0xffffffffu) + dc;
                const bool own = std::binary_search(cells.begin(), cells.end(), keyOf(r, col));
                const auto [lo, hi] = all.find(r, col);
                if (!own) ++ring, ring_held += hi > lo;
                for (std::size_t e = lo; e < hi; ++e) {
                    const std::size_t i = all.entries[e].second;
                    if (f.ground[0][i] && f.ground[g][i]) around += points[i].position.z, around_n += 1;
                }
            }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double ground_z = around_n > 0 ? around / around_n : nan;
    const double cells_m2 = 4.0 * double(cells.size());
    return {float(std::log2(n)),
            float(std::log2(double(cells.size()))),
            float(base_ground / n),
            float(hb / n),
            float(quantile(hbs, 0.9)),
            float(hg / n),
            float(quantile(hgs, 0.9)),
            float(apart / n),
            float(std::sqrt(spread / n)),
            float(planeResidual_m(points, members)),
            float(z / n - ground_z),
            float(quantile(zs, 0.1) - ground_z),
            float(ring > 0 ? ring_held / ring : 1.0),
            float(slope / n),
            float(rough / n),
            float(f.points_per_cell > 0 ? std::log2(n / cells_m2 / f.points_per_cell) : 0.0)};
}

// One patch: its sample, set, points, row, and the wrong points under the base and the set.
struct PatchRow {
    std::size_t sample = 0, set = 0;
    std::vector<std::size_t> points;
    std::vector<float> x;
    double wrong_base = 0, wrong_set = 0;
};

}  // namespace

std::vector<std::vector<std::size_t>> disagreementPatches(const SampleFits& f, std::size_t g) {
    const CellIndex differ(f, [&](std::size_t i) { return f.ground[0][i] != f.ground[g][i]; });
    // Union-find over the cells holding a point that differs.
    std::vector<std::uint64_t> cells;
    for (const auto& e : differ.entries)
        if (cells.empty() || cells.back() != e.first) cells.push_back(e.first);
    std::vector<std::size_t> parent(cells.size());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    const auto root = [&](std::size_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    };
    for (std::size_t a = 0; a < cells.size(); ++a)
        for (std::int64_t dr = -1; dr <= 1; ++dr)
            for (std::int64_t dc = -1; dc <= 1; ++dc) {
                const std::int64_t r = std::int64_t(cells[a] >> 32) + dr, c = std::int64_t(cells[a] & 0xffffffffu) + dc;
                if (r < 0 || c < 0) continue;
                const auto it = std::lower_bound(cells.begin(), cells.end(), keyOf(r, c));
                if (it != cells.end() && *it == keyOf(r, c)) parent[root(std::size_t(it - cells.begin()))] = root(a);
            }
    std::vector<std::vector<std::size_t>> patches;
    std::vector<std::size_t> patch_of(cells.size(), std::size_t(-1));
    for (const auto& [key, i] : differ.entries) {
        const std::size_t r = root(std::size_t(std::lower_bound(cells.begin(), cells.end(), key) - cells.begin()));
        if (patch_of[r] == std::size_t(-1)) patch_of[r] = patches.size(), patches.emplace_back();
        patches[patch_of[r]].push_back(i);
    }
    return patches;
}

std::vector<Counts> printSegmentSelector(const std::vector<AdaptiveSample>& samples,
                                         const std::vector<SampleFits>& fits, const TreeShape& shape, bool three_only) {
    // Every sample's patches under every set but the base, described once.
    std::vector<PatchRow> rows;
    for (std::size_t k = 0; k < samples.size(); ++k) {
        const CellIndex all(fits[k], [](std::size_t) { return true; });
        for (std::size_t g = 1; g < selectorSets().size(); ++g)
            for (std::vector<std::size_t>& patch : disagreementPatches(fits[k], g)) {
                PatchRow r{k, g, std::move(patch), {}, 0, 0};
                r.x = patchFeatures(*samples[k].points, fits[k], all, r.points, g);
                for (const std::size_t i : r.points) {
                    const bool truth = (*samples[k].truth)[i] != 0;
                    r.wrong_base += truth != (fits[k].ground[0][i] != 0);
                    r.wrong_set += truth != (fits[k].ground[g][i] != 0);
                }
                rows.push_back(std::move(r));
            }
    }
    // Each patch's probability that its set is right there, from the other sites' patches.
    std::vector<double> beats(rows.size(), 0.0);
    std::vector<char> sites;
    for (const AdaptiveSample& a : samples)
        if (std::find(sites.begin(), sites.end(), a.name[4]) == sites.end()) sites.push_back(a.name[4]);
    for (const char site : sites)
        for (std::size_t g = 1; g < selectorSets().size(); ++g) {
            std::vector<float> train, labels, weights, test;
            std::vector<std::size_t> tested;
            double sum = 0;
            for (std::size_t r = 0; r < rows.size(); ++r) {
                if (rows[r].set != g) continue;
                const double n = double(samples[rows[r].sample].points->size());
                if (samples[rows[r].sample].name[4] == site) {
                    test.insert(test.end(), rows[r].x.begin(), rows[r].x.end());
                    tested.push_back(r);
                    continue;
                }
                const PairTarget t = pairTarget(rows[r].wrong_base, rows[r].wrong_set, n);
                if (t.weight <= 0) continue;
                train.insert(train.end(), rows[r].x.begin(), rows[r].x.end());
                labels.push_back(t.label);
                weights.push_back(t.weight);
                sum += t.weight;
            }
            if (tested.empty() || labels.empty()) continue;
            for (float& w : weights) w = float(w * double(weights.size()) / sum);
            const std::vector<float> p = learnAndPredict(train, labels, weights, test, rows[0].x.size(), 2, shape);
            for (std::size_t t = 0; t < tested.size(); ++t) beats[tested[t]] = p[t];
        }
    const std::vector<std::vector<std::size_t>> subsets = {{0, 1}, {0, 2}, {0, 1, 2}, {0, 1, 2, 3}};
    std::vector<Counts> primary;
    for (const std::vector<std::size_t>& sets : subsets) {
        if (three_only && sets.size() != 3) continue;
        // The base's labels, then each set's patches taken where chosen (later sets last).
        std::vector<std::vector<std::uint8_t>> oracle, chosen;
        for (const SampleFits& f : fits) oracle.push_back(f.ground[0]), chosen.push_back(f.ground[0]);
        for (const PatchRow& r : rows) {
            if (std::find(sets.begin(), sets.end(), r.set) == sets.end()) continue;
            for (const std::size_t i : r.points) {
                if (r.wrong_set < r.wrong_base) oracle[r.sample][i] = fits[r.sample].ground[r.set][i];
                if (beats[std::size_t(&r - rows.data())] > 0.5) chosen[r.sample][i] = fits[r.sample].ground[r.set][i];
            }
        }
        std::vector<Counts> o, c;
        for (std::size_t k = 0; k < samples.size(); ++k) {
            Confusion co, cc;
            for (std::size_t i = 0; i < oracle[k].size(); ++i) {
                co.add((*samples[k].truth)[i] != 0, oracle[k][i] != 0);
                cc.add((*samples[k].truth)[i] != 0, chosen[k][i] != 0);
            }
            o.push_back(countsOf(co));
            c.push_back(countsOf(cc));
        }
        std::string names;
        for (const std::size_t g : sets) names += std::string(names.empty() ? "" : ", ") + selectorSets()[g].name;
        const std::string what = std::to_string(sets.size()) + " sets (" + names + "), per patch of disagreement";
        if (!three_only) printLine("oracle, each patch's better of " + what, samples, o);
        printLine("selector, " + what + ", pairwise trees" + shape.describe(), samples, c);
        if (sets.size() == 3) primary = c;
    }
    return primary;
}

}  // namespace bench
