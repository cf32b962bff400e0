// tests/sim/ground_raster_test.cpp: the whole-cloud filters' shared raster under a real
// sensor's errors. Known surfaces are seen by many views, each view misregistered by a
// GNSS/INS error of the presets' size (a height offset and a tilt) and every point moved
// by Gaussian range noise: the fitted terrain stays within a stated tolerance of the true
// surface, the ground is recovered, a vehicle-sized box on a 30 % slope stays coloured,
// and the result does not depend on the points' order, batching or gathering threads.
// A hole of empty cells reaches a tile's square only from a cut side (holeReaches); the
// empty cells between a sparse survey's points are told from a dense survey's gaps
// (sparseEmptyCells). Every cell that holds a point is kept, whether its tile keeps only
// such cells or every cell.
#include "ground_raster.hpp"
#include "ground_surfaces.hpp"

#include <sim/ground.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace ground_test;

// Sizes of the presets (docs/sensor.md): at the paper's 300 m altitude and 45 deg an
// attitude error of 1 mrad (livox-avia) moves a view's ground by about 0.3 m in height;
// the range noise is 0.02 m.
struct Errors {
    double view_offset_m = 0.3;   // one sigma, per view
    double view_tilt = 0.003;     // one sigma, rise over run, per view and axis
    double range_noise_m = 0.02;  // one sigma, per point
};

struct Vehicle {
    double cx, cy;  // a 7 x 3.5 x 2.4 m box standing on the surface
    bool covers(double x, double y) const { return std::abs(x - cx) <= 3.5 && std::abs(y - cy) <= 1.75; }
};

struct Seen {
    std::vector<core::CloudPoint> points;
    std::vector<std::uint8_t> ground;  // truth
    std::vector<double> above_m;       // true height above the surface (0 for ground)
};

// `views` views of the square [-half, half]^2, each sampling the surface every 0.5 m
// (jittered) with its own error; a vehicle's roof and walls are seen by every view.
Seen see(const Height& z, double half_m, int views, const Errors& e, const std::vector<Vehicle>& vehicles,
         unsigned seed = 11) {
    Seen s;
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> jitter(-0.25, 0.25);
    const double step = 0.5;
    for (int v = 0; v < views; ++v) {
        const double offset = e.view_offset_m * gauss(rng), tx = e.view_tilt * gauss(rng),
                     ty = e.view_tilt * gauss(rng);
        const auto add = [&](double x, double y, double h, bool ground, double above) {
            core::CloudPoint p;
            p.position =
                glm::vec3(float(x), float(y), float(h + offset + tx * x + ty * y + e.range_noise_m * gauss(rng)));
            p.view = std::uint16_t(v);
            s.points.push_back(p);
            s.ground.push_back(ground);
            s.above_m.push_back(above);
        };
        for (double y = -half_m; y <= half_m; y += step)
            for (double x = -half_m; x <= half_m; x += step) {
                const double px = x + jitter(rng), py = y + jitter(rng);
                if (std::any_of(vehicles.begin(), vehicles.end(), [&](const Vehicle& b) { return b.covers(px, py); }))
                    continue;
                add(px, py, z(px, py), true, 0.0);
            }
        for (const Vehicle& b : vehicles) {
            // Parked on the slope: the roof 2.4 m above the ground under it, walls from
            // 0.1 m up.
            for (double y = b.cy - 1.75; y <= b.cy + 1.75; y += step)
                for (double x = b.cx - 3.5; x <= b.cx + 3.5; x += step) add(x, y, z(x, y) + 2.4, false, 2.4);
            const auto wall = [&](double x, double y) {
                for (double h = 0.1; h < 2.4; h += step) add(x, y, z(x, y) + h, false, h);
            };
            for (double t = -3.5; t <= 3.5; t += step) {
                wall(b.cx + t, b.cy - 1.75);
                wall(b.cx + t, b.cy + 1.75);
            }
            for (double t = -1.75; t <= 1.75; t += step) {
                wall(b.cx - 3.5, b.cy + t);
                wall(b.cx + 3.5, b.cy + t);
            }
        }
    }
    return s;
}

struct Result {
    std::vector<std::uint8_t> flags;
    sim::TerrainGrid grid;
};

Result run(sim::TerrainFit& fit, const std::vector<core::CloudPoint>& points, std::size_t batch = 4096) {
    for (std::size_t i = 0; i < points.size(); i += batch)
        fit.add(std::span(points).subspan(i, std::min(batch, points.size() - i)));
    fit.fit();
    Result r;
    for (const core::CloudPoint& p : points) {
        float h = 0;
        r.flags.push_back(fit.classify(p, h));
    }
    r.grid = fit.surface();
    return r;
}

double recall(const Seen& s, const std::vector<std::uint8_t>& flags) {
    std::size_t truth = 0, hit = 0;
    for (std::size_t i = 0; i < flags.size(); ++i) {
        truth += s.ground[i];
        hit += s.ground[i] && flags[i];
    }
    return double(hit) / double(truth);
}

// Of the points truly more than 0.5 m above the surface, the share left coloured.
double kept(const Seen& s, const std::vector<std::uint8_t>& flags) {
    std::size_t above = 0, coloured = 0;
    for (std::size_t i = 0; i < flags.size(); ++i)
        if (!s.ground[i] && s.above_m[i] > 0.5) {
            ++above;
            coloured += !flags[i];
        }
    return above ? double(coloured) / double(above) : 1.0;
}

// Mean |terrain - z| over the cells at least `margin_m` inside the square, or with
// `signed_error` mean terrain - z (negative: the terrain lies below the surface).
double meanError(const sim::TerrainGrid& g, const Height& z, double half_m, double margin_m,
                 bool signed_error = false) {
    double sum = 0;
    std::size_t n = 0;
    for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
            const double x = g.x0_m + i * g.cell_m, y = g.y0_m + j * g.cell_m;
            if (std::abs(x) > half_m - margin_m || std::abs(y) > half_m - margin_m) continue;
            const double e = double(g.at(i, j)) - z(x, y);
            sum += signed_error ? e : std::abs(e);
            ++n;
        }
    return sum / double(n);
}

const Height kPlane30 = [](double x, double y) { return 0.3 * x + 0.05 * y; };
const Height kHill = [](double x, double y) { return 10.0 * std::exp(-(x * x + y * y) / (2 * 15.0 * 15.0)); };

}  // namespace

TEST_CASE(
    "with the presets' noise and misregistered views the terrain follows the true surface and the ground is "
    "recovered") {
    const double half = 30.0;
    for (const bool csf : {false, true})
        for (const Height* z : {&kPlane30, &kHill}) {
            CAPTURE(csf);
            CAPTURE(z == &kHill);
            const Seen s = see(*z, half, 24, Errors{}, {});
            auto fit = csf ? sim::startCsf(sim::CsfOptions{}) : sim::startSmrf(sim::SmrfOptions{});
            const Result r = run(*fit, s.points);
            // The cell minimum sat about 2.5 view sigmas (0.75 m) below the surface. Once
            // the views line up the level is a cell's third lowest height: on a 30 %
            // slope that lies near the cell's downhill edge, up to 0.15 m below its centre,
            // and never above the surface (that would whiten the foot of what stands on it).
            CHECK(meanError(r.grid, *z, half, 3.0) <= 0.15);
            CHECK(meanError(r.grid, *z, half, 3.0, true) <= 0.0);
            CHECK(recall(s, r.flags) >= 0.97);
            CHECK(r.grid.views_corrected == 24);
            CHECK(r.grid.ground_sigma_uncorrected_m >= 0.15);
            CHECK(r.grid.ground_sigma_m <= 0.1);
        }
}

TEST_CASE("CSF: a vehicle-sized box on a 30 % slope stays coloured above 0.5 m, with and without sensor errors") {
    // SMRF is left out: its slope-scaled threshold (0.5 m + 1.25 x 0.3) whitens the
    // lowest 0.875 m of what stands on such a slope (docs/ground.md).
    const double half = 30.0;
    Errors none;
    none.view_offset_m = none.view_tilt = none.range_noise_m = 0.0;
    for (const bool noisy : {false, true}) {
        CAPTURE(noisy);
        const Seen s = see(kPlane30, half, 24, noisy ? Errors{} : none, {Vehicle{5.0, -4.0}});
        auto fit = sim::startCsf(sim::CsfOptions{});
        const Result r = run(*fit, s.points);
        CHECK(kept(s, r.flags) >= 0.99);
        CHECK(recall(s, r.flags) >= 0.97);
    }
}

TEST_CASE("under a canopy that hides most of the ground, each view is registered by its ground, not the crowns") {
    // Flat ground seen by 24 misregistered views; over three quarters of the square a
    // canopy 8-12 m up hides it but for a gap one place in 150. Most of a view's 4 x 4
    // cell blocks then have a crown as their lowest point: registered by the median of
    // all its blocks, a view was moved metres down, and with it its ground under the
    // terrain's threshold.
    const double half = 30.0;
    const Errors e;
    std::vector<core::CloudPoint> points;
    std::vector<std::uint8_t> truth;
    std::mt19937 rng(23);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> jitter(-0.25, 0.25), unit(0.0, 1.0);
    for (int v = 0; v < 24; ++v) {
        const double offset = e.view_offset_m * gauss(rng), tx = e.view_tilt * gauss(rng),
                     ty = e.view_tilt * gauss(rng);
        for (double y = -half; y <= half; y += 0.5)
            for (double x = -half; x <= half; x += 0.5) {
                const double px = x + jitter(rng), py = y + jitter(rng);
                const bool hidden = px > -15.0 && unit(rng) > 1.0 / 150.0;
                const double h = hidden ? 8.0 + 4.0 * unit(rng) : 0.0;
                core::CloudPoint p;
                p.position = glm::vec3(float(px), float(py),
                                       float(h + offset + tx * px + ty * py + e.range_noise_m * gauss(rng)));
                p.view = std::uint16_t(v);
                points.push_back(p);
                truth.push_back(!hidden);
            }
    }
    for (const bool csf : {false, true}) {
        CAPTURE(csf);
        auto fit = csf ? sim::startCsf(sim::CsfOptions{}) : sim::startSmrf(sim::SmrfOptions{});
        const Result r = run(*fit, points);
        std::size_t ground = 0, found = 0, crowns_whitened = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            ground += truth[i];
            found += truth[i] && r.flags[i];
            crowns_whitened += !truth[i] && r.flags[i];
        }
        CHECK(double(found) / double(ground) >= 0.97);
        CHECK(crowns_whitened == 0);
        CHECK(r.grid.views_corrected == 24);
        // The ground's height above the terrain, each point's view error taken off: within
        // a few range-noise sigmas of zero on average (the grid's own level may sit lower).
        double sum = 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            float h = 0;
            fit->classify(points[i], h);
            if (truth[i]) sum += std::abs(double(h));
        }
        CHECK(sum / double(ground) <= 0.2);
    }
}

TEST_CASE("with misregistered views the fit depends on the set of points, not their order or batching") {
    const Seen s = see(kHill, 25.0, 16, Errors{}, {Vehicle{0.0, 0.0}});
    std::vector<core::CloudPoint> shuffled = s.points;
    std::mt19937 rng(5);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    for (const bool csf : {false, true}) {
        CAPTURE(csf);
        auto a = csf ? sim::startCsf(sim::CsfOptions{}) : sim::startSmrf(sim::SmrfOptions{});
        auto b = csf ? sim::startCsf(sim::CsfOptions{}) : sim::startSmrf(sim::SmrfOptions{});
        const Result ra = run(*a, s.points, 4096);
        const Result rb = run(*b, shuffled, 777);
        REQUIRE(ra.grid.z_m.size() == rb.grid.z_m.size());
        CHECK(std::memcmp(ra.grid.z_m.data(), rb.grid.z_m.data(), ra.grid.z_m.size() * sizeof(float)) == 0);
        CHECK(ra.grid.ground_sigma_m == rb.grid.ground_sigma_m);
        std::size_t different = 0;
        for (std::size_t i = 0; i < s.points.size(); ++i) {
            float h = 0;
            different += std::uint8_t(b->classify(s.points[i], h)) != ra.flags[i];
        }
        CHECK(different == 0);
    }
}

TEST_CASE("with misregistered views the fit is the same when its points are gathered and fitted on several threads") {
    // Enough points that addAll() shares them among up to four rasters, merged after: as
    // they come (a share is a few views), and highest first, so that the lowest points of
    // a cell all lie in the last share and the merge must keep every one of them.
    const Seen s = see(kHill, 40.0, 16, Errors{}, {Vehicle{0.0, 0.0}, Vehicle{12.0, -9.0}});
    REQUIRE(s.points.size() >= 4 * 65536);
    std::vector<core::CloudPoint> high_first = s.points;
    std::stable_sort(high_first.begin(), high_first.end(),
                     [](const core::CloudPoint& a, const core::CloudPoint& b) { return a.position.z > b.position.z; });
    for (const bool csf : {false, true}) {
        CAPTURE(csf);
        auto a = csf ? sim::startCsf(sim::CsfOptions{}) : sim::startSmrf(sim::SmrfOptions{});
        const Result ra = run(*a, s.points);
        for (const int threads : {2, 3, 4}) {
            CAPTURE(threads);
            for (const bool sorted : {false, true}) {
                CAPTURE(sorted);
                auto b = csf ? sim::startCsf(sim::CsfOptions{}) : sim::startSmrf(sim::SmrfOptions{});
                b->setFitThreads(threads);
                b->addAll(sorted ? high_first : s.points, threads);
                b->fit();
                const sim::TerrainGrid& g = b->surface();
                REQUIRE(g.z_m.size() == ra.grid.z_m.size());
                CHECK(std::memcmp(g.z_m.data(), ra.grid.z_m.data(), g.z_m.size() * sizeof(float)) == 0);
                CHECK(g.ground_sigma_m == ra.grid.ground_sigma_m);
                CHECK(g.views_corrected == ra.grid.views_corrected);
                std::size_t different = 0;
                for (std::size_t i = 0; i < s.points.size(); ++i) {
                    float h = 0, h_a = 0;
                    different += std::uint8_t(b->classify(s.points[i], h)) != ra.flags[i];
                    a->classify(s.points[i], h_a);
                    different += h != h_a;
                }
                CHECK(different == 0);
            }
        }
    }
}

TEST_CASE("a cell's level from its lowest heights: the centre of Gaussian heights, not their minimum") {
    // 400 heights N(5, 0.2^2): the lowest 16 give back the centre within 0.1 m and the spread.
    std::mt19937 rng(9);
    std::normal_distribution<double> gauss(5.0, 0.2);
    std::vector<float> all(400);
    for (float& v : all) v = float(gauss(rng));
    std::sort(all.begin(), all.end());
    const sim::CellLowest fitted = sim::cellLevel(all.data(), sim::kCellLowest, 400, -1);
    CHECK(fitted.slope_sigma_m == doctest::Approx(0.2).epsilon(0.35));
    const sim::CellLowest level = sim::cellLevel(all.data(), sim::kCellLowest, 400, 0.2);
    CHECK(std::abs(level.level_m - 5.0) <= 0.1);
    CHECK(all.front() < 4.6f);  // the minimum alone would sit 2 sigma low
    CHECK(sim::normalQuantile(0.5) == doctest::Approx(0.0).epsilon(1e-3));
    CHECK(sim::normalQuantile(0.025) == doctest::Approx(-1.96).epsilon(1e-3));
}

TEST_CASE("a hole reaches a tile's square only from a cut side and through the four neighbours") {
    // A 10 x 6 raster, every cell observed but a hole along row 3 from the low-x side to
    // x = 3; the tile's square is cells [2, 4] x [2, 4].
    constexpr int nx = 10, ny = 6;
    std::vector<bool> observed(nx * ny, true);
    for (int i = 0; i <= 3; ++i) observed[3 * nx + i] = false;
    const auto reaches = [&](const sim::CutSides& cut) { return sim::holeReaches(observed, nx, ny, cut, 2, 4, 2, 4); };
    CHECK(reaches({.low_x = true}));
    CHECK_FALSE(reaches({.high_x = true}));
    CHECK_FALSE(reaches({.low_y = true, .high_y = true}));
    CHECK_FALSE(reaches({}));
    // An empty square is reached by nothing.
    CHECK_FALSE(sim::holeReaches(observed, nx, ny, {.low_x = true}, 2, 1, 2, 4));
    // Cells that touch only at a corner are two holes: the one at the side stops short.
    for (int i = 2; i <= 3; ++i) observed[3 * nx + i] = true;
    observed[2 * nx + 2] = false;
    CHECK_FALSE(reaches({.low_x = true}));
    // Joined again through a side, it reaches the square from below too.
    observed[2 * nx + 1] = false;
    CHECK(reaches({.low_x = true}));
    for (int j = 0; j <= 1; ++j) observed[j * nx + 2] = false;
    CHECK(reaches({.low_y = true}));
    CHECK_FALSE(sim::holeReaches(observed, nx, ny - 1, {.low_x = true}, 2, 4, 2, 4));  // sizes disagree
}

TEST_CASE("the empty cells left out of sparse openings lie beside a point where most cells are empty") {
    constexpr int nx = 13, ny = 13;
    const auto at = [](int i, int j) { return std::size_t(j) * nx + std::size_t(i); };
    // A point in every third cell both ways (one cell in nine): every empty cell has one
    // beside it.
    std::vector<std::uint8_t> known(nx * ny, 0);
    for (int j = 0; j < ny; j += 3)
        for (int i = 0; i < nx; i += 3) known[at(i, j)] = 1;
    std::vector<std::uint8_t> out = sim::sparseEmptyCells(known, nx, ny);
    for (std::size_t c = 0; c < out.size(); ++c) CHECK(out[c] == (known[c] ? 0 : 1));
    // Every fourth cell: the cells two away from any point are not beside one.
    std::fill(known.begin(), known.end(), 0);
    for (int j = 0; j < ny; j += 4)
        for (int i = 0; i < nx; i += 4) known[at(i, j)] = 1;
    out = sim::sparseEmptyCells(known, nx, ny);
    CHECK(out[at(1, 1)] == 1);
    CHECK(out[at(2, 2)] == 0);
    CHECK(out[at(0, 0)] == 0);
    // A dense survey with a 4 x 4 gap: half or more of the cells around each are known.
    std::fill(known.begin(), known.end(), 1);
    for (int j = 4; j < 8; ++j)
        for (int i = 4; i < 8; ++i) known[at(i, j)] = 0;
    out = sim::sparseEmptyCells(known, nx, ny);
    CHECK(std::count(out.begin(), out.end(), 1) == 0);
    CHECK(sim::sparseEmptyCells(std::vector<std::uint8_t>(nx * ny, 0), nx, ny) ==
          std::vector<std::uint8_t>(nx * ny, 0));
}

TEST_CASE("a row's running minimum and maximum are those of every window, whatever the radius") {
    // Against the windows taken one by one: rows shorter and longer than a block, radii
    // from 0 to past the row's length, empty cells (+-infinity) and ties among the values.
    std::mt19937 rng(21);
    std::uniform_int_distribution<int> level(-3, 3);
    std::vector<float> scratch;
    for (const int n : {1, 2, 5, 16, 37}) {
        std::vector<float> in(std::size_t(n), 0.0f), out(std::size_t(n), 0.0f);
        for (float& v : in) v = float(level(rng)) * 0.5f;
        in[std::size_t(n) / 2] = std::numeric_limits<float>::infinity();
        if (n > 3) in[1] = -std::numeric_limits<float>::infinity();
        for (const int r : {0, 1, 2, 3, 7, 40})
            for (const bool take_max : {false, true}) {
                sim::runningExtreme(in.data(), out.data(), n, r, take_max, scratch);
                for (int i = 0; i < n; ++i) {
                    const auto first = in.begin() + std::max(0, i - r), last = in.begin() + std::min(n, i + r + 1);
                    const float want = take_max ? *std::max_element(first, last) : *std::min_element(first, last);
                    INFO("n " << n << ", r " << r << ", i " << i << (take_max ? ", max" : ", min"));
                    CHECK(out[std::size_t(i)] == want);
                }
            }
    }
}

TEST_CASE("every cell that holds a point is kept, in tiles with few such cells, many, or turning from few to many") {
    // 1 m cells of 64 x 64 m tiles: one point in each of ten tiles (a sparse survey); eight
    // tiles with every cell full (dense, and enough points for addAll() to share); two tiles
    // whose first 256 cells come first and 44 more after (the tile turns dense midway, in
    // whichever order the points come). On a plane, each of those cells must be observed and
    // its level the plane's, and the fit must be the same whatever the order or threads.
    const auto plane = [](double x, double y) { return 100.0 + 0.01 * x + 0.02 * y; };
    std::vector<core::CloudPoint> points;
    const auto put = [&](double x, double y) {
        core::CloudPoint p{};
        p.position = glm::vec3(float(x), float(y), float(plane(x, y)));
        points.push_back(p);
    };
    for (int t = 0; t < 10; ++t) put(64.0 * t + 5.5, 3.5);
    for (int k = 0; k < 4; ++k)
        for (int y = 128; y < 192; ++y)
            for (int x = 0; x < 8 * 64; ++x) put(x + 0.25 + 0.15 * k, y + 0.5);
    for (const int first : {1, 0})
        for (int t = 0; t < 2; ++t)
            for (int c = 0; c < 300; ++c)
                if ((c < 256) == bool(first)) put(64.0 * t + c % 64 + 0.5, 256.0 + c / 64 + 0.5);
    REQUIRE(points.size() >= 2 * 65536);

    sim::SmrfOptions o;
    auto reference = sim::startSmrf(o);
    const Result ra = run(*reference, points);
    const auto* raster = dynamic_cast<const sim::RasterFit*>(reference.get());
    REQUIRE(raster != nullptr);
    const sim::TerrainGrid& g = ra.grid;
    std::size_t unobserved = 0, off_plane = 0;
    for (const core::CloudPoint& p : points) {
        const int i = int(std::floor(p.position.x - (g.x0_m - 0.5))),
                  j = int(std::floor(p.position.y - (g.y0_m - 0.5)));
        REQUIRE((i >= 0 && i < g.nx && j >= 0 && j < g.ny));
        const std::size_t c = std::size_t(j) * std::size_t(g.nx) + std::size_t(i);
        unobserved += !raster->observedCells()[c];
        off_plane += std::abs(g.z_m[c] - plane(g.x0_m + i, g.y0_m + j)) > 0.05;
    }
    CHECK(unobserved == 0);
    CHECK(off_plane == 0);

    std::vector<core::CloudPoint> reversed(points.rbegin(), points.rend()), shuffled = points;
    std::mt19937 rng(9);
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    for (const int threads : {1, 2, 3})
        for (const auto* order : {&points, &reversed, &shuffled}) {
            CAPTURE(threads);
            auto b = sim::startSmrf(o);
            b->addAll(*order, threads);
            b->fit();
            REQUIRE(b->surface().z_m.size() == g.z_m.size());
            CHECK(std::memcmp(b->surface().z_m.data(), g.z_m.data(), g.z_m.size() * sizeof(float)) == 0);
            CHECK(dynamic_cast<const sim::RasterFit&>(*b).observedCells() == raster->observedCells());
        }
}

namespace {
// lowOutliers as its contract reads, cell by cell and round by round, every cell tested
// in every round: what the raster's own pass must give.
std::vector<int> plainLowOutliers(const std::vector<const float*>& low, const std::vector<int>& m, int w, int h,
                                  double gap_m, int& rounds) {
    std::vector<int> skip(low.size(), 0);
    rounds = 0;
    for (int round = 0; round < 4; ++round) {
        std::vector<int> next = skip;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const std::size_t c = std::size_t(j * w + i);
                if (skip[c] >= m[c]) continue;
                std::vector<float> around;
                for (int b = std::max(0, j - 5); b <= std::min(h - 1, j + 5); ++b)
                    for (int a = std::max(0, i - 5); a <= std::min(w - 1, i + 5); ++a) {
                        const std::size_t d = std::size_t(b * w + a);
                        if (d != c && skip[d] < m[d]) around.push_back(low[d][skip[d]]);
                    }
                if (around.size() < 8) continue;
                std::sort(around.begin(), around.end());
                if (double(low[c][skip[c]]) < double(around[std::size_t(double(around.size() - 1) * 0.2)]) - gap_m)
                    next[c] = skip[c] + 1;
            }
        if (next == skip) break;
        skip = next;
        ++rounds;
    }
    return skip;
}
}  // namespace

TEST_CASE("low outliers: the same counts as every cell tested in every round, clusters peeled over rounds") {
    // Ground near 0 m with empty cells; some cells hold low returns 8-40 m down (one or
    // several), and strips of low cells three cells wide, whose inner cells see too
    // many low neighbours to be outliers until the strip's ends are peeled, round by round.
    std::mt19937 rng(31);
    for (int trial = 0; trial < 12; ++trial) {
        CAPTURE(trial);
        const int w = 30 + trial * 3, h = 24 + trial * 2;
        std::vector<std::vector<float>> heights(std::size_t(w * h));
        std::uniform_real_distribution<float> ground(-0.3f, 0.3f), deep(-40.0f, -8.0f), u(0.0f, 1.0f);
        for (auto& cell : heights) {
            if (u(rng) < 0.25f) continue;  // empty
            const int points = 1 + int(u(rng) * 4.0f);
            for (int k = 0; k < points; ++k) cell.push_back(ground(rng));
            if (u(rng) < 0.05f)
                for (int k = 0; k < 1 + int(u(rng) * 3.0f); ++k) cell.push_back(deep(rng));
        }
        // A strip along x, three cells wide, each of its cells a low return over its ground.
        const int y0 = 3 + trial % 7, x0 = trial % 5, len = 8 + trial;
        for (int y = y0; y < y0 + 3 && y < h; ++y)
            for (int x = x0; x < x0 + len && x < w; ++x) {
                auto& cell = heights[std::size_t(y * w + x)];
                cell.push_back(-20.0f - 0.1f * float(x));
                if (cell.size() == 1) cell.push_back(0.1f);
            }
        std::vector<const float*> low(heights.size(), nullptr);
        std::vector<int> m(heights.size(), 0);
        for (std::size_t c = 0; c < heights.size(); ++c) {
            std::sort(heights[c].begin(), heights[c].end());
            low[c] = heights[c].data();
            m[c] = int(heights[c].size());
        }
        int rounds = 0;
        const std::vector<int> expected = plainLowOutliers(low, m, w, h, 6.0, rounds);
        CHECK(sim::lowOutliers(low, m, w, h, 6.0) == expected);
        // The strip's middle is reached only after its ends are gone.
        CHECK(rounds >= 2);
        const std::size_t mid = std::size_t((y0 + 1) * w + x0 + len / 2);
        CHECK(expected[mid] == 0);  // deep inside a wide low patch: judged against it
    }
}

TEST_CASE("the hole filling's fixed sweeps give the same bits on any number of threads") {
    // Rasters from one cell to several dozen blocks of rows, a few known cells to most,
    // and sweep counts below, at and above the threads: every thread count gives the bits
    // of one thread, and the sweeps did move the filled cells (2 sweeps differ from 3).
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> height(-5.0f, 40.0f);
    struct Shape {
        int nx, ny;
        double known_share;
    };
    for (const Shape s : {Shape{1, 1, 1.0}, Shape{5, 3, 0.3}, Shape{7, 12, 0.2}, Shape{64, 13, 0.05},
                          Shape{37, 161, 0.1}, Shape{211, 97, 0.02}, Shape{120, 120, 0.6}}) {
        const std::size_t n = std::size_t(s.nx) * std::size_t(s.ny);
        std::bernoulli_distribution is_known(s.known_share);
        std::vector<std::uint8_t> known(n, 0);
        std::vector<float> start(n, 0.0f);
        for (std::size_t c = 0; c < n; ++c) {
            known[c] = is_known(rng) ? 1 : 0;
            start[c] = known[c] ? height(rng) : 0.0f;
        }
        known[n / 2] = 1;
        start[n / 2] = 12.5f;
        for (const int sweeps : {1, 2, 3, 100}) {
            std::vector<float> one = start;
            sim::inpaint(one, known, s.nx, s.ny, sweeps, 1);
            for (const int threads : {2, 3, 4, 7}) {
                std::vector<float> many = start;
                sim::inpaint(many, known, s.nx, s.ny, sweeps, threads);
                INFO(s.nx << " x " << s.ny << ", " << sweeps << " sweeps, " << threads << " threads");
                CHECK(std::memcmp(one.data(), many.data(), n * sizeof(float)) == 0);
            }
        }
        if (n >= 100) {
            std::vector<float> two = start, three = start;
            sim::inpaint(two, known, s.nx, s.ny, 2, 2);
            sim::inpaint(three, known, s.nx, s.ny, 3, 2);
            CHECK(two != three);
        }
    }
}
