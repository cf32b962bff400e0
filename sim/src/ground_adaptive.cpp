// sim/src/ground_adaptive.cpp: see sim/ground_adaptive.hpp.
#include <sim/ground_adaptive.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace sim {
namespace {

double quantileOf(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size())));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}

}  // namespace

const std::vector<std::string>& surveyTraitNames() {
    static const std::vector<std::string> names = {"points_per_m2", "empty_share", "slope_p50", "slope_p90",
                                                   "steep_share",   "relief_m",    "rough_m",   "object_share",
                                                   "high_share",    "edge_share"};
    return names;
}

std::vector<double> traitValues(const SurveyTraits& t) {
    return {t.points_per_m2, t.empty_share, t.slope_p50,    t.slope_p90,  t.steep_share,
            t.relief_m,      t.rough_m,     t.object_share, t.high_share, t.edge_share};
}

SurveyTraits measureSurvey(std::span<const core::CloudPoint> points, const SmrfOptions& o) {
    SurveyTraits t;
    if (points.empty()) return t;
    const std::unique_ptr<TerrainFit> fit = startSmrf(o);
    fit->add(points);
    fit->fit();
    const TerrainGrid& g = fit->surface();
    if (g.empty()) return t;
    const std::size_t cells = std::size_t(g.nx) * std::size_t(g.ny);
    // Per cell: its points, and whether one of them is not ground.
    std::vector<std::uint32_t> count(cells, 0);
    std::vector<std::uint8_t> object(cells, 0);
    std::size_t not_ground = 0, high = 0;
    for (const core::CloudPoint& p : points) {
        float height_m = 0;
        const bool ground = fit->classify(p, height_m);
        not_ground += !ground;
        high += height_m > 2.5f;
        const int i = int(std::lround(std::clamp((double(p.position.x) - g.x0_m) / g.cell_m, 0.0, double(g.nx - 1))));
        const int j = int(std::lround(std::clamp((double(p.position.y) - g.y0_m) / g.cell_m, 0.0, double(g.ny - 1))));
        const std::size_t c = std::size_t(j) * std::size_t(g.nx) + std::size_t(i);
        ++count[c];
        if (!ground && height_m > 0.5f) object[c] = 1;
    }
    const double n = double(points.size());
    t.object_share = double(not_ground) / n;
    t.high_share = double(high) / n;
    std::vector<double> slopes, heights, rough;
    std::size_t observed = 0, ground_cells = 0, edge_cells = 0, steep = 0;
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const std::size_t c = std::size_t(j) * std::size_t(g.nx) + std::size_t(i);
            if (count[c] == 0) continue;
            ++observed;
            const double s = g.slopeAt(g.x0_m + i * g.cell_m, g.y0_m + j * g.cell_m);
            slopes.push_back(s);
            steep += s > 0.5;
            heights.push_back(g.at(i, j));
            if (i >= 2 && j >= 2 && i + 2 < g.nx && j + 2 < g.ny) {
                const double around = (g.at(i - 2, j) + g.at(i + 2, j) + g.at(i, j - 2) + g.at(i, j + 2)) / 4.0;
                rough.push_back(std::abs(double(g.at(i, j)) - around));
            }
            if (object[c]) continue;
            ++ground_cells;
            bool edge = false;
            for (int dj = -1; dj <= 1 && !edge; ++dj)
                for (int di = -1; di <= 1 && !edge; ++di) {
                    const int ii = i + di, jj = j + dj;
                    if (ii < 0 || jj < 0 || ii >= g.nx || jj >= g.ny) continue;
                    edge = object[std::size_t(jj) * std::size_t(g.nx) + std::size_t(ii)] != 0;
                }
            edge_cells += edge;
        }
    const double cell_area_m2 = g.cell_m * g.cell_m;
    t.points_per_m2 = observed > 0 ? n / (double(observed) * cell_area_m2) : 0.0;
    t.empty_share = 1.0 - double(observed) / double(cells);
    t.slope_p50 = quantileOf(slopes, 0.5);
    t.slope_p90 = quantileOf(slopes, 0.9);
    t.steep_share = observed > 0 ? double(steep) / double(observed) : 0.0;
    t.relief_m = quantileOf(heights, 0.95) - quantileOf(heights, 0.05);
    t.rough_m = quantileOf(rough, 0.5);
    t.edge_share = ground_cells > 0 ? double(edge_cells) / double(ground_cells) : 0.0;
    return t;
}

}  // namespace sim
