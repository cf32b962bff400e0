// tests/bench/ground_isprs_multiscale_test.cpp: the multiscale surface filters' pieces on
// known answers: the hole filling keeps a plane, the surface through scattered points on a
// slope lies on it, MCC takes the points standing above a plane off and keeps the plane, the
// residual pyramid finds a sloping plane's points under a block, and the low outliers found
// are the points far below their neighbours.
#include "ground_isprs_mcc.hpp"

#include <core/point_cloud.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

// A point every `spacing_m` on z = 0.3 x + 0.1 y over [0, size_m)^2, jittered by a fixed
// pattern so that points do not sit on cell centres.
std::vector<core::CloudPoint> slopedPlane(double size_m, double spacing_m) {
    std::vector<core::CloudPoint> points;
    int k = 0;
    for (double y = 0; y < size_m; y += spacing_m)
        for (double x = 0; x < size_m; x += spacing_m, ++k) {
            core::CloudPoint p;
            const double px = x + 0.37 * spacing_m * ((k * 7) % 5) / 4.0,
                         py = y + 0.41 * spacing_m * ((k * 3) % 4) / 3.0;
            p.position = glm::vec3(float(px), float(py), float(0.3 * px + 0.1 * py));
            p.label = core::Role::Ground;
            points.push_back(p);
        }
    return points;
}

double planeAt(double x, double y) { return 0.3 * x + 0.1 * y; }

}  // namespace

TEST_CASE("multiscale: the hole filling keeps a plane's known cells and puts its holes on it") {
    const int nx = 40, ny = 30;
    std::vector<float> z(std::size_t(nx * ny), 0.0f);
    std::vector<std::uint8_t> known(z.size(), 0);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            if ((i * 7 + j * 3) % 11 == 0 || (i < 3 && j < 3)) {
                z[std::size_t(j * nx + i)] = float(2.0 + 0.5 * i - 0.25 * j);
                known[std::size_t(j * nx + i)] = 1;
            }
    bench::fillHoles(z, known, nx, ny, 20);
    double worst = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            worst = std::max(worst, std::abs(z[std::size_t(j * nx + i)] - (2.0 + 0.5 * i - 0.25 * j)));
    CHECK(worst < 0.05);
}

TEST_CASE("multiscale: the surface through scattered points on a slope lies on the slope") {
    const std::vector<core::CloudPoint> points = slopedPlane(60, 1.3);
    std::vector<std::uint8_t> every_third(points.size(), 0);
    for (std::size_t i = 0; i < points.size(); i += 3) every_third[i] = 1;
    for (const double cell_m : {1.0, 2.0, 8.0}) {
        const bench::HeightRaster s = bench::surfaceThrough(points, every_third, cell_m, false);
        double worst = 0;
        for (const core::CloudPoint& p : points)
            worst =
                std::max(worst, std::abs(s.heightAt(p.position.x, p.position.y) - planeAt(p.position.x, p.position.y)));
        INFO("cell " << cell_m << " m");
        CHECK(worst < 0.05);
    }
}

TEST_CASE("multiscale: MCC takes the points standing on a plane off and keeps the plane") {
    std::vector<core::CloudPoint> points = slopedPlane(80, 1.0);
    const std::size_t ground = points.size();
    // A 6 x 6 m block 3 m high (a roof's points) and a few 1.5 m shrubs.
    for (double y = 30; y < 36; y += 1.0)
        for (double x = 40; x < 46; x += 1.0) {
            core::CloudPoint p;
            p.position = glm::vec3(float(x + 0.3), float(y + 0.6), float(planeAt(x + 0.3, y + 0.6) + 3.0));
            points.push_back(p);
        }
    for (const double x : {10.2, 25.7, 61.1}) {
        core::CloudPoint p;
        p.position = glm::vec3(float(x), float(x / 2), float(planeAt(x, x / 2) + 1.5));
        points.push_back(p);
    }
    const std::vector<std::uint8_t> g = bench::mccGround(points, bench::MccOptions{});
    std::size_t ground_kept = 0, objects_kept = 0;
    for (std::size_t i = 0; i < points.size(); ++i) (i < ground ? ground_kept : objects_kept) += g[i];
    CHECK(ground_kept == ground);
    CHECK(objects_kept == 0);
}

TEST_CASE("multiscale: the residual pyramid finds a sloping plane's points and leaves a block on it") {
    std::vector<core::CloudPoint> points = slopedPlane(80, 1.0);
    const std::size_t ground = points.size();
    for (double y = 30; y < 40; y += 1.0)
        for (double x = 40; x < 50; x += 1.0) {
            core::CloudPoint p;
            p.position = glm::vec3(float(x + 0.3), float(y + 0.6), float(planeAt(x + 0.3, y + 0.6) + 4.0));
            points.push_back(p);
        }
    const std::vector<std::uint8_t> g = bench::pyramidGround(points, bench::PyramidOptions{});
    std::size_t ground_kept = 0, objects_kept = 0;
    for (std::size_t i = 0; i < points.size(); ++i) (i < ground ? ground_kept : objects_kept) += g[i];
    CHECK(ground_kept == ground);
    CHECK(objects_kept == 0);
}

TEST_CASE("multiscale: a point far below its neighbours is a low outlier, the plane's points are not") {
    std::vector<core::CloudPoint> points = slopedPlane(30, 1.0);
    core::CloudPoint deep;
    deep.position = glm::vec3(15.2f, 14.7f, float(planeAt(15.2, 14.7) - 8.0));
    points.push_back(deep);
    const std::vector<std::uint8_t> low = bench::lowOutliers(points, 6.0);
    for (std::size_t i = 0; i + 1 < points.size(); ++i) REQUIRE(low[i] == 0);
    CHECK(low.back() == 1);
}
