// tests/sim/ground_reconstruct_test.cpp: morphological reconstruction (sim/src/
// ground_reconstruct.hpp) against a plain iteration of geodesic dilations on seeded random
// rasters, the h-dome of a box and of a slope, and SMRF's reconstruction options
// (SmrfOptions::reconstruct) on a staircase of narrow terraces beside a box building:
// the terraces' upper edges that the plain openings cut are kept, the box is not, and
// the answer is the same whatever the order of the points.
#include "ground_reconstruct.hpp"
#include "ground_surfaces.hpp"

#include <sim/ground.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

namespace {

using namespace ground_test;

// The reconstruction by its definition: elementary geodesic dilations until nothing moves.
std::vector<float> reconstructSlowly(std::vector<float> marker, const std::vector<float>& mask, int w, int h) {
    for (std::size_t c = 0; c < marker.size(); ++c) marker[c] = std::min(marker[c], mask[c]);
    for (bool moved = true; moved;) {
        moved = false;
        std::vector<float> next = marker;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                float v = marker[std::size_t(j * w + i)];
                for (int jj = std::max(0, j - 1); jj <= std::min(h - 1, j + 1); ++jj)
                    for (int ii = std::max(0, i - 1); ii <= std::min(w - 1, i + 1); ++ii)
                        v = std::max(v, marker[std::size_t(jj * w + ii)]);
                v = std::min(v, mask[std::size_t(j * w + i)]);
                if (v != marker[std::size_t(j * w + i)]) moved = true;
                next[std::size_t(j * w + i)] = v;
            }
        marker.swap(next);
    }
    return marker;
}

// A staircase of terraces 6 m wide, each 2.5 m above the one before over a 1 m bank,
// rising in x from x = -10 m (flat below that): a mean slope of 0.36.
double staircase(double x, double) {
    const double t = x + 10.0;
    if (t < 0.0) return 0.0;
    const double k = std::floor(t / 7.0), u = t - 7.0 * k;
    return 2.5 * k + (u > 6.0 ? 2.5 * (u - 6.0) : 0.0);
}

// On a terrace's last metre before its bank drops (the upper edge), away from the
// sampled square's border.
bool onUpperEdge(const glm::vec3& p) {
    const double t = double(p.x) + 10.0;
    if (t < 0.0 || std::abs(p.x) > 45.0 || std::abs(p.y) > 45.0) return false;
    const double u = t - 7.0 * std::floor(t / 7.0);
    return u >= 5.0 && u <= 6.0;
}

struct EdgeScore {
    double edge_recall = 0;  // of the upper edges' ground points
    Score all;
};

EdgeScore scoreStaircase(const Labelled& l, const std::vector<std::uint8_t>& found) {
    EdgeScore s;
    s.all = score(l, found);
    std::size_t edge = 0, kept = 0;
    for (std::size_t i = 0; i < found.size(); ++i)
        if (l.ground[i] && onUpperEdge(l.points[i])) {
            ++edge;
            kept += found[i];
        }
    s.edge_recall = edge > 0 ? double(kept) / double(edge) : 0.0;
    return s;
}

}  // namespace

TEST_CASE("reconstruction by dilation: the hybrid algorithm gives what geodesic dilations reach when they settle") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> level(0.0f, 10.0f);
    const std::vector<std::pair<int, int>> sizes = {{1, 1}, {7, 1}, {1, 9}, {23, 17}, {40, 31}};
    for (const std::pair<int, int>& size : sizes) {
        const int w = size.first, h = size.second;
        CAPTURE(w);
        CAPTURE(h);
        std::vector<float> mask(std::size_t(w) * std::size_t(h)), marker(mask.size());
        for (std::size_t c = 0; c < mask.size(); ++c) {
            mask[c] = level(rng);
            // Markers mostly low, a few above their mask (clipped): seeds to spread from.
            marker[c] = level(rng) < 1.0f ? mask[c] + 1.0f : level(rng) - 8.0f;
        }
        const std::vector<float> expected = reconstructSlowly(marker, mask, w, h);
        std::vector<float> fast = marker;
        sim::reconstructByDilation(fast, mask, w, h);
        CHECK(fast == expected);
        std::vector<float> bounded = marker;
        sim::geodesicDilation(bounded, mask, w, h, w * h);  // a path visits each cell at most once
        CHECK(bounded == expected);
    }
}

TEST_CASE("reconstruction: a plateau joined to the seed comes back, one beyond a valley does not") {
    // One row: plateau A (5), valley (1), plateau B (5); the seed is in A.
    const std::vector<float> mask = {5, 5, 5, 1, 1, 5, 5, 5};
    std::vector<float> marker(mask.size(), 0.0f);
    marker[0] = 9.0f;  // clipped to 5
    sim::reconstructByDilation(marker, mask, int(mask.size()), 1);
    CHECK(marker == std::vector<float>{5, 5, 5, 1, 1, 1, 1, 1});
    // One step of geodesic dilation reaches one cell further.
    std::vector<float> one(mask.size(), 0.0f);
    one[0] = 5.0f;
    sim::geodesicDilation(one, mask, int(mask.size()), 1, 1);
    CHECK(one == std::vector<float>{5, 5, 0, 0, 0, 0, 0, 0});
}

TEST_CASE("h-domes: a box on flat ground is a dome, a slope that climbs on is not") {
    const int w = 30, h = 20;
    std::vector<float> box(std::size_t(w) * h, 0.0f), slope(box.size());
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            if (i >= 10 && i < 16 && j >= 5 && j < 11) box[std::size_t(j * w + i)] = 6.0f;
            slope[std::size_t(j * w + i)] = 0.5f * float(i);
        }
    const std::vector<float> box_domes = sim::hDomes(box, w, h, 2.0f);
    CHECK(box_domes[std::size_t(7 * w + 12)] == doctest::Approx(2.0));   // on the roof: h
    CHECK(box_domes[std::size_t(15 * w + 25)] == doctest::Approx(0.0));  // the ground around it
    const std::vector<float> slope_domes = sim::hDomes(slope, w, h, 2.0f);
    CHECK(slope_domes[std::size_t(10 * w + 5)] == doctest::Approx(0.0));
    // The top of the slope has nothing above it: it is the top 2 m of a dome.
    CHECK(slope_domes[std::size_t(10 * w + w - 1)] == doctest::Approx(2.0));
}

TEST_CASE("SMRF with openings by reconstruction keeps the terraces that the plain openings cut, not the boxes") {
    const Labelled l = sample(staircase, 50.0, {{-30.0, 0.0, 6.0, 6.0}, {-30.0, 30.0, 4.0, 3.0}});
    const EdgeScore plain = scoreStaircase(l, sim::findGroundSmrf(l.points, sim::SmrfOptions{}));
    CAPTURE(plain.edge_recall);
    CAPTURE(plain.all.recall);
    // The plain openings cut the staircase (whole stretches of terraces, their upper edges
    // with them): what the reconstruction must mend.
    CHECK(plain.edge_recall < 0.9);
    CHECK(plain.all.high_found == 0);

    sim::SmrfOptions opening;
    opening.reconstruct = 1;  // the erosion reconstructed under the surface, however far
    const EdgeScore s = scoreStaircase(l, sim::findGroundSmrf(l.points, opening));
    CAPTURE(s.edge_recall);
    CAPTURE(s.all.recall);
    CHECK(s.edge_recall >= 0.99);
    CHECK(s.all.recall >= plain.all.recall + 0.05);
    CHECK(s.all.high > 1000);
    CHECK(s.all.high_found == 0);  // the boxes' roofs and walls stay objects

    // SMRF's ground given back up steps a cell at a time: no box comes back, and no ground
    // is lost.
    sim::SmrfOptions steps;
    steps.reconstruct = 4;
    steps.reconstruct_steps = 1;
    steps.reconstruct_h_m = 5.0;
    steps.reconstruct_tol_m = 0.1;
    const EdgeScore g = scoreStaircase(l, sim::findGroundSmrf(l.points, steps));
    CHECK(g.edge_recall >= plain.edge_recall);
    CHECK(g.all.recall >= plain.all.recall);
    CHECK(g.all.high_found == 0);
}

TEST_CASE("SMRF with reconstruction gives the same answer whatever the order of the points") {
    const Labelled l = sample(staircase, 40.0, {{-25.0, 0.0, 5.0, 6.0}});
    for (const int mode : {1, 2, 3, 4, 5}) {
        CAPTURE(mode);
        sim::SmrfOptions o;
        o.reconstruct = mode;
        o.reconstruct_steps = mode == 1 ? 0 : 2;
        const std::vector<std::uint8_t> first = sim::findGroundSmrf(l.points, o);
        std::vector<std::size_t> order(l.points.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::shuffle(order.begin(), order.end(), std::mt19937(5));
        std::vector<glm::vec3> shuffled;
        for (const std::size_t i : order) shuffled.push_back(l.points[i]);
        const std::vector<std::uint8_t> second = sim::findGroundSmrf(shuffled, o);
        std::size_t differ = 0;
        for (std::size_t k = 0; k < order.size(); ++k) differ += first[order[k]] != second[k];
        CHECK(differ == 0);
        CHECK(sim::findGroundSmrf(l.points, o) == first);
    }
}

TEST_CASE("SMRF's reconstruction options are checked") {
    sim::SmrfOptions o;
    o.reconstruct = 6;
    CHECK_THROWS_WITH(sim::validate(o), doctest::Contains("smrf reconstruct"));
    o.reconstruct = 1;
    o.reconstruct_h_m = 0.0;
    CHECK_THROWS_WITH(sim::validate(o), doctest::Contains("reconstruct_h_m"));
    o.reconstruct_h_m = 2.0;
    o.reconstruct_steps = -1;
    CHECK_THROWS_WITH(sim::validate(o), doctest::Contains("reconstruct_steps"));
    o.reconstruct_steps = 0;
    o.reconstruct_to_m = -1.0;
    CHECK_THROWS_WITH(sim::validate(o), doctest::Contains("reconstruct_to_m"));
    o.reconstruct_to_m = 1.0;
    CHECK_NOTHROW(sim::validate(o));
}
