// tests/sim/ground_surfaces.hpp: known surfaces with box buildings, sampled as a Lidar
// would see them (ground everywhere but under the boxes, roofs, walls from the ground up),
// for the terrain-following ground filters' tests.
#pragma once
#include <sim/ground.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace ground_test {

using Height = std::function<double(double, double)>;

struct Box {
    double cx, cy, half_m, height_m;
    bool covers(double x, double y) const { return std::abs(x - cx) <= half_m && std::abs(y - cy) <= half_m; }
};

struct Labelled {
    std::vector<glm::vec3> points;
    std::vector<std::uint8_t> ground;       // truth
    std::vector<std::uint8_t> high_object;  // roof or wall point more than 1 m above the terrain
};

// Ground sampled every 0.25 m (jittered, seeded) over [-half, half]^2, except under the
// boxes; each box a flat roof height_m above its footprint's highest ground and four
// walls from the ground up, sampled every 0.25 m.
inline Labelled sample(const Height& z, double half_m, const std::vector<Box>& boxes, unsigned seed = 3) {
    Labelled l;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.1, 0.1);
    const double step = 0.25;
    for (double y = -half_m; y <= half_m; y += step)
        for (double x = -half_m; x <= half_m; x += step) {
            const double px = x + jitter(rng), py = y + jitter(rng);
            if (std::any_of(boxes.begin(), boxes.end(), [&](const Box& b) { return b.covers(px, py); })) continue;
            l.points.emplace_back(px, py, z(px, py));
            l.ground.push_back(1);
            l.high_object.push_back(0);
        }
    for (const Box& b : boxes) {
        double highest = -1e9;
        for (double y = b.cy - b.half_m; y <= b.cy + b.half_m; y += step)
            for (double x = b.cx - b.half_m; x <= b.cx + b.half_m; x += step) highest = std::max(highest, z(x, y));
        const double top = highest + b.height_m;
        const auto add = [&](double x, double y, double h) {
            l.points.emplace_back(x, y, h);
            l.ground.push_back(0);
            l.high_object.push_back(h > z(x, y) + 1.0);
        };
        for (double y = b.cy - b.half_m; y <= b.cy + b.half_m; y += step)
            for (double x = b.cx - b.half_m; x <= b.cx + b.half_m; x += step) add(x, y, top);
        const auto wall = [&](double x, double y) {
            for (double h = z(x, y); h < top; h += step) add(x, y, h);
        };
        for (double s = -b.half_m; s <= b.half_m; s += step) {
            wall(b.cx + s, b.cy - b.half_m);
            wall(b.cx + s, b.cy + b.half_m);
            wall(b.cx - b.half_m, b.cy + s);
            wall(b.cx + b.half_m, b.cy + s);
        }
    }
    return l;
}

struct Score {
    double recall = 0;           // of the ground points
    std::size_t high_found = 0;  // roof and wall points > 1 m above the terrain called ground
    std::size_t high = 0;
};

inline Score score(const Labelled& l, const std::vector<std::uint8_t>& found) {
    Score s;
    std::size_t truth = 0, hit = 0;
    for (std::size_t i = 0; i < found.size(); ++i) {
        truth += l.ground[i];
        hit += l.ground[i] && found[i];
        s.high += l.high_object[i];
        s.high_found += l.high_object[i] && found[i];
    }
    s.recall = double(hit) / double(truth);
    return s;
}

// Largest |terrain - z| over the cells at least `margin_m` inside the sampled square.
inline double surfaceError(const sim::TerrainGrid& g, const Height& z, double half_m, double margin_m) {
    double worst = 0;
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const double x = g.x0_m + i * g.cell_m, y = g.y0_m + j * g.cell_m;
            if (std::abs(x) > half_m - margin_m || std::abs(y) > half_m - margin_m) continue;
            worst = std::max(worst, std::abs(double(g.at(i, j)) - z(x, y)));
        }
    return worst;
}

}  // namespace ground_test
