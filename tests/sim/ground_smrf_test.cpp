// tests/sim/ground_smrf_test.cpp: the simple morphological filter on known surfaces
// (a tilted plane, a Gaussian hill, a terrace with a 2 m step) with box buildings on
// them: the ground is recovered, the boxes are not, and the fitted terrain is the surface;
// a cone shows the windows are disks; in a sparse survey the openings that leave the
// empty cells out keep a step's upper edge.
#include "ground_surfaces.hpp"

#include <sim/ground.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace ground_test;

void checkSurface(const char* name, const Height& z, const std::vector<Box>& boxes, double max_error_m) {
    CAPTURE(std::string(name));
    const double half = 50.0;
    const Labelled l = sample(z, half, boxes);
    sim::TerrainGrid grid;
    std::vector<float> height;
    const auto found = sim::findGroundSmrf(l.points, sim::SmrfOptions{}, &grid, &height);
    REQUIRE(found.size() == l.points.size());
    const Score s = score(l, found);
    CHECK(s.recall >= 0.99);
    CHECK(s.high > 1000);
    CHECK(s.high_found == 0);
    CHECK(grid.nx >= 100);
    // The terrain runs through the ground, under the boxes too (interpolated), within
    // the minimum surface's bias (the lowest point of a cell sits below its centre's
    // height on a slope) and the inpainting's error.
    CHECK(surfaceError(grid, z, half, 2.0) <= max_error_m);
    // Height above ground: a roof point stands its box's height above the terrain.
    for (std::size_t i = 0; i < l.points.size(); ++i)
        if (!l.ground[i] && l.high_object[i]) {
            CHECK(height[i] == doctest::Approx(double(l.points[i].z) - grid.heightAt(l.points[i].x, l.points[i].y)));
            break;
        }
}

}  // namespace

TEST_CASE("SMRF recovers a tilted plane (30 % slope) and not the buildings on it") {
    checkSurface(
        "tilted plane", [](double x, double y) { return 0.3 * x + 0.05 * y; },
        {{-20, 10, 6, 8}, {15, -15, 9, 5}, {25, 25, 4, 12}}, 0.25);
}

TEST_CASE("SMRF recovers a Gaussian hill (15 m high) and not the buildings on its flanks") {
    checkSurface(
        "Gaussian hill", [](double x, double y) { return 15.0 * std::exp(-(x * x + y * y) / (2.0 * 30.0 * 30.0)); },
        {{-25, 0, 6, 7}, {10, 28, 5, 10}, {30, -20, 8, 6}}, 0.35);
}

TEST_CASE("SMRF recovers a terrace with a 2 m step and not the buildings on either level") {
    const Height terrace = [](double x, double) { return x < 0.0 ? 0.0 : 2.0; };
    const double half = 50.0;
    const Labelled l = sample(terrace, half, {{-25, -20, 7, 6}, {25, 20, 7, 9}, {20, -25, 4, 4}});
    sim::TerrainGrid grid;
    const auto found = sim::findGroundSmrf(l.points, sim::SmrfOptions{}, &grid);
    const Score s = score(l, found);
    CHECK(s.recall >= 0.99);
    CHECK(s.high_found == 0);
    // Away from the step (the bilinear terrain ramps across one cell there) both levels hold.
    for (int j = 0; j < grid.ny; ++j)
        for (int i = 0; i < grid.nx; ++i) {
            const double x = grid.x0_m + i * grid.cell_m;
            if (std::abs(x) < 1.5 || std::abs(x) > half - 2) continue;
            CHECK(std::abs(double(grid.at(i, j)) - terrace(x, 0)) <= 0.2);
        }
}

TEST_CASE("SMRF: a building wider than twice the window stays ground (the window's meaning)") {
    const Height flat = [](double, double) { return 0.0; };
    const Labelled l = sample(flat, 40.0, {{0, 0, 12, 5}});  // 24 m wide
    sim::SmrfOptions narrow;
    narrow.window_m = 6.0;  // openings up to 6 m radius cannot remove 12 m of half-width
    const Score small = score(l, sim::findGroundSmrf(l.points, narrow));
    CHECK(small.high_found > 1000);
    const Score wide = score(l, sim::findGroundSmrf(l.points, sim::SmrfOptions{}));
    CHECK(wide.high_found == 0);
}

TEST_CASE("SMRF with raised segments: a building wider than twice the window is an object, the ground stays") {
    const Height flat = [](double, double) { return 0.0; };
    const Labelled l = sample(flat, 50.0, {{0, 0, 25, 6}, {-40, 35, 5, 4}});  // 50 m wide, and a small one
    sim::SmrfOptions o;
    o.window_m = 6.0;  // openings up to 6 m radius leave the large roof ground
    const Score plain = score(l, sim::findGroundSmrf(l.points, o));
    CHECK(plain.high_found > 1000);
    o.raised_segments = true;
    const Score raised = score(l, sim::findGroundSmrf(l.points, o));
    CHECK(raised.high_found == 0);
    CHECK(raised.recall >= 0.99);
}

TEST_CASE("SMRF with raised segments: a tall roof that the data's edge cuts is an object, seen across its shadow") {
    // A flat roof 20 m up over [0, 50] x [0, 50], the data's corner: the edge cuts it on
    // two sides. On the other two, 10 m of shadow without a point (no wall returns)
    // between roof and ground, as a tall building leaves under an oblique scan.
    const Height flat = [](double, double) { return 0.0; };
    const Labelled all = sample(flat, 50.0, {{25, 25, 25, 20}});
    Labelled l;
    for (std::size_t i = 0; i < all.points.size(); ++i) {
        const glm::vec3& p = all.points[i];
        const bool wall = !all.ground[i] && p.z < 19.9f;
        const bool shadow = all.ground[i] && p.x > -10.0f && p.y > -10.0f;
        if (wall || shadow || p.x > 50.0f || p.y > 50.0f) continue;
        l.points.push_back(p);
        l.ground.push_back(all.ground[i]);
        l.high_object.push_back(all.high_object[i]);
    }
    sim::SmrfOptions o;
    const Score plain = score(l, sim::findGroundSmrf(l.points, o));
    CHECK(plain.high_found > 10000);  // 50 m wide: more than the openings remove
    o.raised_segments = true;
    const Score raised = score(l, sim::findGroundSmrf(l.points, o));
    CHECK(raised.high_found == 0);
    CHECK(raised.recall >= 0.99);
}

TEST_CASE("SMRF with raised segments keeps a plateau 12 m up that the data's edge cuts, reached by a slope") {
    const Height plateau = [](double x, double) { return std::clamp(0.5 * (x - 5.0), 0.0, 12.0); };
    const Labelled l = sample(plateau, 50.0, {});
    sim::SmrfOptions o;
    o.raised_segments = true;
    CHECK(score(l, sim::findGroundSmrf(l.points, o)).recall >= 0.99);
}

TEST_CASE("SMRF with raised segments keeps a 2 m terrace and a hill: their patches rise on one side or join the rest") {
    for (const Height& z : std::vector<Height>{
             [](double x, double) { return x < 0.0 ? 0.0 : 2.5; },
             [](double x, double y) { return 15.0 * std::exp(-(x * x + y * y) / (2.0 * 20.0 * 20.0)); }}) {
        const Labelled l = sample(z, 50.0, {});
        sim::SmrfOptions o;
        o.raised_segments = true;
        CHECK(score(l, sim::findGroundSmrf(l.points, o)).recall >= 0.99);
    }
}

TEST_CASE("SMRF's windows are disks: a cone steeper than a square's corners allow keeps its top") {
    // Flanks rising at 0.6 under a slope bar of 0.7: a disk of radius r lowers the top by
    // 0.6 r, under the bar; a square's corners, r * sqrt(2) away, would lower it by 0.85 r
    // and take the top for an object.
    const Height cone = [](double x, double y) { return 20.0 - 0.6 * std::hypot(x, y); };
    const Labelled l = sample(cone, 30.0, {});
    sim::SmrfOptions o;
    o.slope = 0.7;
    sim::TerrainGrid grid;
    const auto found = sim::findGroundSmrf(l.points, o, &grid);
    const Score s = score(l, found);
    CHECK(s.recall >= 0.999);
    // The top's cells keep their own minimum surface, not one filled in from around them.
    CHECK(surfaceError(grid, cone, 30.0, 27.0) <= 0.2);
}

TEST_CASE("SMRF's result depends on the set of points, not their order or batching") {
    const Labelled l =
        sample([](double x, double y) { return 0.1 * x + 3.0 * std::sin(y / 15.0); }, 30.0, {{5, 5, 5, 6}});
    const auto a = sim::findGroundSmrf(l.points, sim::SmrfOptions{});
    // The same points reversed, through a whole-cloud run fed in uneven batches.
    std::vector<core::CloudPoint> cloud(l.points.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) cloud[i].position = l.points[cloud.size() - 1 - i];
    const auto fit = sim::startSmrf(sim::SmrfOptions{});
    for (std::size_t i = 0; i < cloud.size(); i += 777)
        fit->add(std::span(cloud).subspan(i, std::min<std::size_t>(777, cloud.size() - i)));
    fit->fit();
    std::size_t different = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        float h = 0;
        different += std::uint8_t(fit->classify(cloud[i].position, h)) != a[cloud.size() - 1 - i];
    }
    CHECK(different == 0);
}

TEST_CASE("SMRF options are checked, naming the option and what is allowed") {
    sim::SmrfOptions o;
    o.cell_m = 0.0;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("--smrf-cell-m"), core::Error);
    o = {};
    o.slope = -1;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("--smrf-slope"), core::Error);
    o = {};
    o.window_m = std::nan("");
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("--smrf-window-m"), core::Error);
    o = {};
    o.threshold_m = -0.1;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("--smrf-threshold-m"), core::Error);
    o = {};
    o.scalar = INFINITY;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("--smrf-scalar"), core::Error);
    o = {};
    o.fill_sweeps = -1;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("fill_sweeps = -1: allowed [0, 10000]"), core::Error);
    o = {};
    o.sparse_openings = true;
    o.reconstruct = 1;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("reconstruct = 1: allowed 0 when sparse_openings is on"),
                         core::Error);
    // A cloud wider than the raster may hold is refused, naming the cell size.
    o = {};
    o.max_cells = 100;
    std::vector<glm::vec3> wide{{0, 0, 0}, {50, 50, 0}};
    CHECK_THROWS_WITH_AS(sim::findGroundSmrf(wide, o), doctest::Contains("--smrf-cell-m"), core::Error);
}

TEST_CASE("a raster given an extent spans it, the empty cells filled, as a tile spans its buffer") {
    // Flat ground on [0, 10) x [0, 10); the extent [-5, 20) x [-3, 12) holds the cells whose
    // centres lie in it: 25 x 15 of 1 m, the first at (-4.5, -2.5).
    std::vector<core::CloudPoint> points;
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i) {
            core::CloudPoint p;
            p.position = {0.25f + 0.5f * float(i), 0.25f + 0.5f * float(j), 2.0f};
            points.push_back(p);
        }
    const std::unique_ptr<sim::TerrainFit> fit = sim::startSmrf(sim::SmrfOptions{});
    fit->add(points);
    fit->setExtent({-5.0, -3.0}, {20.0, 12.0});
    fit->fit();
    const sim::TerrainGrid& grid = fit->surface();
    CHECK(grid.nx == 25);
    CHECK(grid.ny == 15);
    CHECK(grid.x0_m == doctest::Approx(-4.5));
    CHECK(grid.y0_m == doctest::Approx(-2.5));
    CHECK(grid.observed_cells == 100);
    CHECK(grid.at(0, 0) == doctest::Approx(2.0));  // filled from the ground, 5 cells away
    float h = 0;
    CHECK(fit->classify(points.front(), h));
}

TEST_CASE("an empty cloud fits an empty terrain and no point is ground") {
    sim::TerrainGrid grid;
    CHECK(sim::findGroundSmrf({}, sim::SmrfOptions{}, &grid).empty());
    CHECK(grid.empty());
}

TEST_CASE("SMRF keeps rolling ground on a 60 % slope: the threshold grows with the local slope") {
    // Bumps of 0.5 m on a 60 % incline: an interpolated minimum surface runs up to a metre
    // under the crests, beyond the plain 0.5 m threshold. The cells' levels (their heights
    // spread that much within a cell, so the robust level is taken) close most of the gap;
    // Pingel's elevation scalar (1.25 m per unit slope) keeps the rest ground.
    const Height z = [](double x, double y) {
        return 0.6 * x + 0.5 * std::sin(2.0 * M_PI * x / 5.0) * std::cos(2.0 * M_PI * y / 7.0);
    };
    const Labelled l = sample(z, 40.0, {});
    const Score with_scalar = score(l, sim::findGroundSmrf(l.points, sim::SmrfOptions{}));
    sim::SmrfOptions flat;
    flat.scalar = 0.0;
    const Score without = score(l, sim::findGroundSmrf(l.points, flat));
    CHECK(with_scalar.recall >= 0.95);
    CHECK(without.recall < with_scalar.recall);
}

TEST_CASE("SMRF with sparse openings keeps a step's upper edge in a sparse survey and still takes out its roofs") {
    // A 3 m step, straight or oblique, seen every 2.5 m (0.16 points a square metre, as the
    // sparsest ISPRS samples), with two roofs 6 m high seen as sparsely. In 1 m cells five
    // in six are empty: filled, each cell of the upper row stands above the cells filled
    // towards the lower row, and the smallest openings cut it.
    for (const Height& z : std::vector<Height>{[](double x, double) { return x < 0.3 ? 0.0 : 3.0; },
                                               [](double x, double y) { return x + 0.5 * y < 0.3 ? 0.0 : 3.0; }}) {
        const std::vector<Box> roofs{{-25, 20, 7, 6}, {25, -20, 6, 6}};
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> jitter(-0.3, 0.3);
        std::vector<glm::vec3> points;
        std::vector<std::uint8_t> truth;
        for (double y = -50; y <= 50; y += 2.5)
            for (double x = -50; x <= 50; x += 2.5) {
                const double px = x + jitter(rng), py = y + jitter(rng);
                const bool roof =
                    std::any_of(roofs.begin(), roofs.end(), [&](const Box& b) { return b.covers(px, py); });
                points.emplace_back(px, py, z(px, py) + (roof ? 6.0 : 0.0));
                truth.push_back(roof ? 0 : 1);
            }
        const auto missed = [&](const std::vector<std::uint8_t>& found, std::uint8_t kind) {
            std::size_t n = 0;
            for (std::size_t i = 0; i < found.size(); ++i) n += truth[i] == kind && found[i] != kind;
            return n;
        };
        sim::SmrfOptions o;
        o.fill_sweeps = 100;
        const auto filled = sim::findGroundSmrf(points, o);
        CHECK(missed(filled, 1) >= 20);  // the upper edge: about one point in fifty
        CHECK(missed(filled, 0) == 0);
        o.sparse_openings = true;
        const auto sparse = sim::findGroundSmrf(points, o);
        CHECK(missed(sparse, 1) <= 3);
        CHECK(missed(sparse, 0) == 0);
    }
}

TEST_CASE("SMRF with sparse openings changes nothing in a dense survey") {
    const Height terrace = [](double x, double) { return x < 0.0 ? 0.0 : 2.0; };
    const Labelled l = sample(terrace, 40.0, {{-20, -15, 7, 6}, {20, 15, 5, 9}});
    sim::SmrfOptions o;
    const auto plain = sim::findGroundSmrf(l.points, o);
    o.sparse_openings = true;
    CHECK(sim::findGroundSmrf(l.points, o) == plain);
}
