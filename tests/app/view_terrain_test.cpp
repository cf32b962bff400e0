// The ground under a viewed cloud (app/src/view_terrain.cpp), without a window: the grid
// built from a file's class 2 follows the ground, not what stands on it; its cells are
// bounded; the SMRF fit of a cloud without class 2 finds the same slope; a file's
// even sample stays within its bound, a COPC file's is its top levels.
#include <test_files.hpp>
#include <test_paths.hpp>
#include <view_terrain.hpp>

#include <io/cloud_io.hpp>
#include <io/copc.hpp>
#include <io/copc_writer.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

namespace {

constexpr double kSlope = 0.1;  // the ground rises 0.1 m per metre of x

// A sloped ground (z = 0.1 x) of class 2 over 100 m x 50 m at 0.5 m spacing, in a local
// frame, with a 10 m x 10 m box of class 6 (a building, 8 m high) standing on it at x
// 40..50, y 20..30: its roof and walls, and no ground under it.
std::vector<core::CloudPoint> slopeWithBox() {
    std::vector<core::CloudPoint> points;
    const auto inBox = [](double x, double y) { return x >= 40.0 && x <= 50.0 && y >= 20.0 && y <= 30.0; };
    for (int j = 0; j <= 100; ++j)
        for (int i = 0; i <= 200; ++i) {
            const double x = i * 0.5, y = j * 0.5;
            core::CloudPoint p;
            if (inBox(x, y)) {
                p.position = glm::vec3(float(x), float(y), float(kSlope * 45.0 + 8.0));  // the roof
                p.label = core::Role::Environment;
            } else {
                p.position = glm::vec3(float(x), float(y), float(kSlope * x));
                p.label = core::Role::Ground;
            }
            points.push_back(p);
        }
    for (int k = 0; k <= 80; ++k)  // a wall
        for (int i = 0; i <= 20; ++i) {
            core::CloudPoint p;
            p.position = glm::vec3(40.0f, float(20.0 + i * 0.5), float(kSlope * 40.0 + k * 0.1));
            p.label = core::Role::Environment;
            points.push_back(p);
        }
    return points;
}

// The grid's height at the centre of the cell nearest world (x, y).
double heightAt(const viewer::ViewTerrain& t, double x, double y) {
    const int i = std::clamp(int(std::lround((x - t.x0) / t.cell)), 0, t.nx - 1);
    const int j = std::clamp(int(std::lround((y - t.y0) / t.cell)), 0, t.ny - 1);
    return double(t.z[std::size_t(j) * std::size_t(t.nx) + std::size_t(i)]);
}

}  // namespace

TEST_CASE("the class 2 grid follows the sloped ground under a building, in world coordinates") {
    const glm::dvec3 origin(500000.0, 4000000.0, 200.0);
    const std::vector<core::CloudPoint> points = slopeWithBox();
    const viewer::ViewTerrain t = app::groundGrid(points, origin, 1.0);
    REQUIRE_FALSE(t.empty());
    CHECK(t.cell >= 1.0);
    CHECK(t.x0 == doctest::Approx(origin.x));
    CHECK(t.y0 == doctest::Approx(origin.y));
    // Every cell, the box's included, lies on the slope: the grid's height at the centre
    // of each cell is the ground's there, give or take the slope across a cell.
    double worst = 0.0;
    for (int j = 0; j < t.ny; ++j)
        for (int i = 0; i < t.nx; ++i) {
            const double x_local = i * t.cell;
            const double ground = origin.z + kSlope * x_local;
            worst =
                std::max(worst, std::fabs(double(t.z[std::size_t(j) * std::size_t(t.nx) + std::size_t(i)]) - ground));
        }
    CHECK(worst < kSlope * 6.0);  // the farthest cell under the box takes an edge's height
    // Under the building's middle: the ground, not the roof 8 m above it.
    CHECK(std::fabs(heightAt(t, origin.x + 45.0, origin.y + 25.0) - (origin.z + kSlope * 45.0)) < 0.6);
}

TEST_CASE("the class 2 grid stays within its cells, coarser past the bound") {
    const std::vector<core::CloudPoint> points = slopeWithBox();
    const viewer::ViewTerrain t = app::groundGrid(points, glm::dvec3(0.0), 1.0, 200);
    REQUIRE_FALSE(t.empty());
    CHECK(std::size_t(t.nx) * std::size_t(t.ny) <= 200);
    CHECK(t.z.size() == std::size_t(t.nx) * std::size_t(t.ny));
    CHECK(t.cell > 5.0);
    CHECK(std::fabs(heightAt(t, 80.0, 10.0) - kSlope * 80.0) < kSlope * t.cell);
}

TEST_CASE("no ground point: no class 2 grid") {
    std::vector<core::CloudPoint> points = slopeWithBox();
    for (core::CloudPoint& p : points) p.label = core::Role::Environment;
    CHECK(app::groundPointCount(points) == 0);
    CHECK(app::groundGrid(points, glm::dvec3(0.0), 1.0).empty());
}

TEST_CASE("SMRF's fit of the same cloud without classes follows the slope too") {
    std::vector<core::CloudPoint> points = slopeWithBox();
    for (core::CloudPoint& p : points) p.label = core::Role::Environment;
    const viewer::ViewTerrain t = app::fittedGrid(points, glm::dvec3(10.0, 20.0, 30.0), sim::CoordinateUnits{});
    REQUIRE_FALSE(t.empty());
    CHECK(std::fabs(heightAt(t, 10.0 + 45.0, 20.0 + 25.0) - (30.0 + kSlope * 45.0)) < 1.0);
    CHECK(std::fabs(heightAt(t, 10.0 + 80.0, 20.0 + 10.0) - (30.0 + kSlope * 80.0)) < 0.5);
}

TEST_CASE("a file's terrain sample is even and within its bound") {
    // hexbin-crop.las: 38,367 points, 35,318 of them class 2.
    const std::filesystem::path file = std::filesystem::path(test_support::dataDir()) / "real" / "hexbin-crop.las";
    const std::atomic<bool> go{false};
    const core::PointCloud all = app::readTerrainSample(file, 1000000, go);
    CHECK(all.points.size() == 38367);
    CHECK(app::groundPointCount(all.points) == 35318);
    const core::PointCloud some = app::readTerrainSample(file, 10000, go);
    CHECK(some.points.size() <= 10000);
    CHECK(some.points.size() >= 9000);
    const std::atomic<bool> stopped{true};
    CHECK(app::readTerrainSample(file, 10000, stopped).points.empty());
}

TEST_CASE("a COPC file's terrain sample is its top levels, whole, within the bound") {
    // The sloped ground and building as COPC with small nodes: several levels.
    const std::vector<core::CloudPoint> points = slopeWithBox();
    const test_support::TempDir dir("view_terrain_copc");
    const std::filesystem::path file = dir.path / "slope.copc.laz";
    io::CopcOptions copc;
    copc.max_node_points = 1000;
    {
        io::CloudWriter writer(file, io::CloudFormat::Copc, glm::dvec3(0.0), core::CloudFields{}, {}, &copc);
        writer.append(points);
        writer.commit();
    }
    const io::CopcReader reader(file);
    std::map<int, std::size_t> per_level;
    for (const io::CopcNode& n : reader.nodes()) per_level[n.key.level] += std::size_t(n.point_count);
    REQUIRE(per_level.size() >= 3);
    // A bound that takes the two top levels whole but not the third.
    const std::size_t two = per_level[0] + per_level[1];
    const std::atomic<bool> go{false};
    const core::PointCloud sample = app::readTerrainSample(file, two + per_level[2] / 2, go);
    CHECK(sample.points.size() == two);
    // The top levels keep the ground below the building: the class 2 grid follows the slope.
    const viewer::ViewTerrain t = app::groundGrid(sample.points, sample.origin, 1.0);
    REQUIRE_FALSE(t.empty());
    CHECK(std::fabs(heightAt(t, 80.0, 10.0) - kSlope * 80.0) < kSlope * t.cell + 0.2);
    // The root alone when even the second level is over the bound, and of a root over
    // the bound every k-th point.
    CHECK(app::readTerrainSample(file, per_level[0] + 1, go).points.size() == per_level[0]);
    CHECK(app::readTerrainSample(file, 10, go).points.size() == 10);
}
