// tests/sim/dtm_test.cpp: the DTM put together from pieces of terrains (sim/dtm.hpp,
// DtmMosaic): one whole raster gives dtmAscii's text; tiles' own squares, cut from
// rasters that overlap by their buffers, give each cell from the tile that owns it, the
// box around them, and -9999 where no tile held a point; bad pieces are refused.
#include <test_files.hpp>

#include <core/error.hpp>
#include <sim/dtm.hpp>

#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace {

// A raster of `nx` x `ny` cells of `cell` whose first cell's lattice index is (i0, j0),
// each cell's height f(i, j) of its lattice index.
template <class F>
sim::TerrainGrid latticeGrid(int i0, int j0, int nx, int ny, double cell, F f) {
    sim::TerrainGrid g;
    g.nx = nx;
    g.ny = ny;
    g.cell_m = cell;
    g.x0_m = (i0 + 0.5) * cell;
    g.y0_m = (j0 + 0.5) * cell;
    g.z_m.resize(std::size_t(nx) * std::size_t(ny));
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) g.z_m[std::size_t(j) * std::size_t(nx) + std::size_t(i)] = f(i0 + i, j0 + j);
    return g;
}

std::string written(sim::DtmMosaic& mosaic, const std::filesystem::path& file) {
    std::FILE* f = std::fopen(file.c_str(), "wb");
    REQUIRE(f != nullptr);
    mosaic.write(f);
    std::fclose(f);
    return test_support::slurp(file);
}

}  // namespace

TEST_CASE("dtm mosaic: one whole raster is written as dtmAscii writes it") {
    const test_support::TempDir dir("dtm_whole");
    const glm::dvec3 frame(500000.0, 5400000.0, 120.0);
    const auto grid = latticeGrid(-3, 7, 9, 5, 2.0, [](int i, int j) { return float(0.25 * i - 0.5 * j); });
    sim::DtmMosaic mosaic(dir.path, "t.asc", 2.0, frame);
    mosaic.add(grid, glm::dvec2(-1e300), glm::dvec2(1e300));
    CHECK(mosaic.columns() == 9);
    CHECK(mosaic.rows() == 5);
    CHECK(written(mosaic, dir.path / "t.asc") == sim::dtmAscii(grid, frame));
}

TEST_CASE("dtm mosaic: tiles' own squares from overlapping rasters, the box around them, -9999 where none") {
    const test_support::TempDir dir("dtm_tiles");
    // The survey's terrain: height 0.1 i + 0.01 j at lattice cell (i, j). Each tile's
    // raster reaches 3 cells beyond its 10-cell square and disagrees with the survey
    // there (+5 m), so any cell taken from a neighbour's buffer shows.
    const auto truth = [](int i, int j) { return float(0.1 * i + 0.01 * j); };
    const double cell = 1.0, tile = 10.0;
    sim::DtmMosaic mosaic(dir.path, "t.asc", cell, glm::dvec3(0.0));
    // Tiles (0, 0), (1, 0) and (0, 1); (1, 1) holds no point and is never fitted.
    for (const auto& [tx, ty] : std::vector<std::pair<int, int>>{{0, 0}, {1, 0}, {0, 1}}) {
        const int si = tx * 10, sj = ty * 10;
        const auto grid = latticeGrid(si - 3, sj - 3, 16, 16, cell, [&](int i, int j) {
            const bool own = i >= si && i < si + 10 && j >= sj && j < sj + 10;
            return truth(i, j) + (own ? 0.0f : 5.0f);
        });
        mosaic.add(grid, glm::dvec2(tx * tile, ty * tile), glm::dvec2((tx + 1) * tile, (ty + 1) * tile));
    }
    CHECK(mosaic.columns() == 20);
    CHECK(mosaic.rows() == 20);
    std::istringstream in(written(mosaic, dir.path / "t.asc"));
    std::string key;
    int ncols = 0, nrows = 0;
    double xll = 0, yll = 0, size = 0;
    std::string nodata;
    in >> key >> ncols >> key >> nrows >> key >> xll >> key >> yll >> key >> size >> key >> nodata;
    CHECK(ncols == 20);
    CHECK(nrows == 20);
    CHECK(xll == 0.0);
    CHECK(yll == 0.0);
    CHECK(size == 1.0);
    CHECK(nodata == "-9999");
    std::size_t missing = 0, wrong = 0;
    for (int row = 0; row < nrows; ++row)
        for (int col = 0; col < ncols; ++col) {
            std::string value;
            REQUIRE(static_cast<bool>(in >> value));
            const int i = col, j = nrows - 1 - row;  // the northernmost row first
            if (i >= 10 && j >= 10) {
                missing += value == "-9999";
                continue;
            }
            wrong += std::abs(std::stod(value) - double(truth(i, j))) > 0.0005;
        }
    CHECK(missing == 100);
    CHECK(wrong == 0);
}

TEST_CASE("dtm mosaic: nothing to write, or a raster of another cell, is refused in one line") {
    const test_support::TempDir dir("dtm_bad");
    sim::DtmMosaic mosaic(dir.path, "t.asc", 1.0, glm::dvec3(0.0));
    std::FILE* f = std::fopen((dir.path / "t.asc").c_str(), "wb");
    REQUIRE(f != nullptr);
    CHECK_THROWS_WITH_AS(mosaic.write(f), "output: t.asc: no terrain was fitted (no point was read)", core::Error);
    std::fclose(f);
    const auto half = latticeGrid(0, 0, 4, 4, 0.5, [](int, int) { return 0.0f; });
    CHECK_THROWS_WITH_AS(mosaic.add(half, glm::dvec2(-1e9), glm::dvec2(1e9)),
                         doctest::Contains("a terrain of 0.500000 cells on a lattice of 1.000000"), core::Error);
    // A square that misses the raster adds nothing.
    const auto grid = latticeGrid(0, 0, 4, 4, 1.0, [](int, int) { return 1.0f; });
    mosaic.add(grid, glm::dvec2(100.0), glm::dvec2(110.0));
    CHECK(mosaic.columns() == 0);
}
