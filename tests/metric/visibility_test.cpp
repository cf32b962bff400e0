// The visibility metric of paper §IV-B against closed forms (headless EGL, llvmpipe).
#include <scene_builders.hpp>

#include <metric/clouds.hpp>
#include <metric/visibility.hpp>

#include <core/error.hpp>
#include <io/cloud_io.hpp>

#include <doctest/doctest.h>

#include <render/orbit_camera.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <unistd.h>

using doctest::Approx;

namespace {

// Box-behind-wall geometry (tests/common/scene_builders.hpp): cube half-size 2 m, walls at 6 m with tops
// at 0.5 m, camera orbit radius 20 m at the cube's centre height, 4 axis-aligned views.
constexpr float kA = 2.0f, kD = 6.0f, kWallTop = 0.5f;
constexpr double kR = 20.0;

metric::MetricOptions axisViews() {
    metric::MetricOptions o;
    o.orbit.radius_m = kR;
    o.orbit.altitude_m = 0.0;
    o.orbit.views = 4;
    o.width = 256;
    o.height = 256;
    o.splat_px = 3.0;
    return o;
}

const metric::MetricClouds& wallClouds() {
    static const metric::MetricClouds clouds = metric::generateClouds(test_support::boxBehindWall(kA, kD, kWallTop));
    return clouds;
}

}  // namespace

TEST_CASE("paper §IV-B arithmetic: 4733 / 6908 = 68.5 %") {
    CHECK(metric::ratio(4733, 6908) == Approx(0.685).epsilon(0.0005));
    CHECK(std::round(metric::ratio(4733, 6908) * 1000.0) == 685.0);
    CHECK(std::isnan(metric::ratio(10, 0)));
}

TEST_CASE("box behind a wall: exact reference matches the closed form, point metric close") {
    const core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
    // The wall's outer top edge (x = D + thickness) sets the shadow line: 0.3381 (0.3393
    // if the wall had no thickness).
    const double expected = test_support::closedFormVisible(kA, kD, kWallTop, kR);
    REQUIRE(std::abs(expected - 0.3381) < 5e-5);
    const metric::MetricClouds& clouds = wallClouds();
    REQUIRE(!clouds.p1.points.empty());
    REQUIRE(clouds.p2.points.size() < clouds.p3.points.size() + clouds.p1.points.size());
    metric::Evaluator evaluator(clouds, &scene);
    REQUIRE(evaluator.hasExact());
    const metric::MetricResult r = evaluator.run(axisViews());
    REQUIRE(r.views.size() == 4);
    CHECK(r.views_used == 4);
    for (const metric::ViewResult& v : r.views) {
        INFO("view " << v.view << " exact " << v.exact << " metric " << v.metric << " visible " << v.visible);
        // Exact: pixel centres sample a ~108 px tall face; the wall's edge and the face's
        // edges each round to a row, so |error| < 1 row / 108 px < 0.01 (seen: 0.0015).
        CHECK(std::abs(v.exact - expected) < 0.01);
        // Point splats (drone clouds at ~0.4 m spacing, 3 px splats) grow the lit area by
        // about a splat at the edges (seen: 0.0035).
        CHECK(std::abs(v.metric - expected) < 0.01);
        CHECK(std::abs(v.visible - expected) < 0.01);
        CHECK(v.i1 > 5000);
    }
    CHECK(std::abs(r.exact_mean - expected) < 0.01);
    CHECK(std::abs(r.metric_mean - expected) < 0.01);
    MESSAGE("closed form " << expected << ", exact " << r.exact_mean << ", metric " << r.metric_mean << ", visible "
                           << r.visible_mean);
}

TEST_CASE("skips (target rectangle, culling) give the same counts inside the rectangle") {
    const core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
    metric::Evaluator evaluator(wallClouds(), &scene);
    metric::MetricOptions o = axisViews();
    o.exact = false;
    const metric::MetricResult skip = evaluator.run(o);
    o.skip = false;
    const metric::MetricResult full = evaluator.run(o);
    for (int k = 0; k < 4; ++k) {
        const auto& a = skip.views[static_cast<std::size_t>(k)];
        const auto& b = full.views[static_cast<std::size_t>(k)];
        CHECK(a.rect.area() < b.rect.area());
        CHECK(a.i1 == b.i1);                  // I1 lies inside the rectangle
        CHECK(a.visible_px == b.visible_px);  // so does I3 and not I2 (it is within I1's splats)
        CHECK(a.i4 <= b.i4);                  // xor also counts P2-only pixels anywhere
        CHECK(std::isnan(a.exact));
    }
    CHECK_FALSE(skip.has_exact);
}

namespace {

// Points placed exactly on pixel centres of view 0 of a one-view orbit: with 1 px splats
// each lights exactly one pixel, so every count below follows from the pixel sets alone.
struct PixelScene {
    static constexpr int kSize = 64;
    glm::dvec3 origin{651000.0, 6862000.0, 85.0};
    metric::MetricOptions options;
    render::CameraPose pose;
    PixelScene() {
        options.orbit.radius_m = 20.0;
        options.orbit.altitude_m = 0.0;
        options.orbit.views = 1;
        options.width = kSize;
        options.height = kSize;
        options.splat_px = 1.0;
        options.exact = false;
        options.look_at_world = origin;
        pose = render::orbitView(options.orbit, glm::dvec3(0.0), 0);
    }
    /// One point per pixel of [x0, x1) x [y0, y1), `range_m` from the eye along its centre ray;
    /// the cloud's own origin is `origin + cloud_shift_m` (clouds from elsewhere).
    void add(core::PointCloud& cloud, int x0, int x1, int y0, int y1, double range_m,
             glm::dvec3 cloud_shift_m = glm::dvec3(0.0)) const {
        cloud.origin = origin + cloud_shift_m;
        for (int py = y0; py < y1; ++py)
            for (int px = x0; px < x1; ++px) {
                core::CloudPoint p;
                const glm::dvec3 d = render::pixelCentreDirection(pose, options.orbit.vfov_deg, kSize, kSize, px, py);
                p.position = glm::vec3(pose.eye + range_m * d - cloud_shift_m);
                cloud.points.push_back(p);
            }
    }
};

}  // namespace

TEST_CASE("I4 = I2 xor I3 counts environment-only pixels (the target's Ladar shadow) as well") {
    // Pixel sets (columns x rows, bottom-left origin) of a 64 x 64 view:
    //   T, the target, 20 m away: the 10 x 10 block [20, 30)^2 without its corner [25, 30)^2 (75 px);
    //   E, environment in front of the target (15 m), seen by the drone with and without the
    //     target: [20, 25) x [20, 30), 50 px, all on T's pixels;
    //   S, environment behind (30 m) that the drone saw only without the target (its Ladar
    //     shadow, so only in P2): T's missing corner [25, 30)^2, 25 px, inside T's screen
    //     rectangle so the skips keep it.
    // I1 = T = 75, I2 = E + S = 75, I3 = T (E is on T) = 75, I2 and I3 = E = 50, so
    // I2 xor I3 = (I3 and not I2) + (I2 and not I3) = 25 + 25 = 50, metric 50 / 75,
    // visible = I3 and not I2 = 25 / 75 (xor minus the environment-only pixels).
    const PixelScene ps;
    metric::MetricClouds c;
    ps.add(c.p1, 20, 30, 20, 25, 20.0);
    ps.add(c.p1, 20, 25, 25, 30, 20.0);
    c.p3 = c.p1;
    ps.add(c.p2, 20, 25, 20, 30, 15.0);
    ps.add(c.p3, 20, 25, 20, 30, 15.0);
    ps.add(c.p2, 25, 30, 25, 30, 30.0);
    REQUIRE(c.p1.points.size() == 75);
    metric::Evaluator evaluator(c, nullptr);
    metric::MetricOptions o = ps.options;
    for (const metric::Rasterizer rasterizer : {metric::Rasterizer::Compute, metric::Rasterizer::Raster})
        for (const bool skip : {true, false}) {
            o.rasterizer = rasterizer;
            o.skip = skip;
            const metric::MetricResult r = evaluator.run(o);
            REQUIRE(r.views.size() == 1);
            const metric::ViewResult& v = r.views[0];
            INFO("raster " << (rasterizer == metric::Rasterizer::Raster) << " skip " << skip);
            CHECK(v.i1 == 75);
            CHECK(v.i2 == 75);
            CHECK(v.i3 == 75);
            CHECK(v.i4 == 50);
            CHECK(v.visible_px == 25);
            CHECK(v.metric == Approx(50.0 / 75.0).epsilon(1e-12));
            CHECK(v.visible == Approx(25.0 / 75.0).epsilon(1e-12));
            CHECK(r.metric_mean - r.visible_mean == Approx(25.0 / 75.0).epsilon(1e-12));
        }
}

TEST_CASE("clouds with their own origins are brought into P1's frame: the same pixel counts") {
    // The xor scene above with P2 and P3 written 1 km away from P1's origin (files from
    // elsewhere): the evaluator shifts them by (their origin - its origin), same counts.
    const PixelScene ps;
    const glm::dvec3 shift_m(1000.0, -500.0, 20.0);
    metric::MetricClouds c;
    ps.add(c.p1, 20, 30, 20, 25, 20.0);
    ps.add(c.p1, 20, 25, 25, 30, 20.0);
    ps.add(c.p3, 20, 30, 20, 25, 20.0, shift_m);
    ps.add(c.p3, 20, 25, 25, 30, 20.0, shift_m);
    ps.add(c.p3, 20, 25, 20, 30, 15.0, shift_m);
    ps.add(c.p2, 20, 25, 20, 30, 15.0, shift_m);
    ps.add(c.p2, 25, 30, 25, 30, 30.0, shift_m);
    metric::Evaluator evaluator(c, nullptr);
    CHECK(evaluator.origin() == ps.origin);
    const metric::MetricResult r = evaluator.run(ps.options);
    REQUIRE(r.views.size() == 1);
    CHECK(r.views[0].i1 == 75);
    CHECK(r.views[0].i2 == 75);
    CHECK(r.views[0].i3 == 75);
    CHECK(r.views[0].i4 == 50);
    CHECK(r.views[0].visible_px == 25);
}

TEST_CASE("a fully hidden target gives 0 (metric, visible and exact)") {
    const core::Scene scene = test_support::boxBehindWall(kA, kD, 4.0f, /*roof=*/true);
    const metric::MetricClouds clouds = metric::generateClouds(scene);
    REQUIRE(!clouds.p1.points.empty());
    metric::Evaluator evaluator(clouds, &scene);
    metric::MetricOptions o = axisViews();
    o.orbit.views = 2;
    const metric::MetricResult r = evaluator.run(o);
    REQUIRE(r.views_used == 2);
    for (const metric::ViewResult& v : r.views) {
        CHECK(v.i1 > 0);
        CHECK(v.i4 == 0);
        CHECK(v.metric == 0.0);
        CHECK(v.visible == 0.0);
        CHECK(v.exact_target_px > 0);
        CHECK(v.exact_visible_px == 0);
        CHECK(v.exact == 0.0);
    }
    CHECK(r.metric_mean == 0.0);
}

TEST_CASE("views with the target out of frame are reported and left out of the means") {
    const core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
    metric::Evaluator evaluator(wallClouds(), &scene);
    metric::MetricOptions o = axisViews();
    // Orbit around a point 40 m east of the target: looking west the target is in frame,
    // looking east it is behind the camera.
    o.look_at_world = scene.origin + glm::dvec3(40.0, 0.0, 0.0);
    o.orbit.radius_m = 10.0;
    for (bool skip : {true, false}) {
        o.skip = skip;
        const metric::MetricResult r = evaluator.run(o);
        REQUIRE(r.views.size() == 4);
        const metric::ViewResult& west = r.views[0];  // eye at +50 m looking at +40 m: target ahead
        const metric::ViewResult& east = r.views[2];  // eye at +30 m looking at +40 m: behind
        CHECK(west.used);
        CHECK(west.i1 > 0);
        CHECK_FALSE(east.used);
        CHECK(east.i1 == 0);
        CHECK(std::isnan(east.metric));
        CHECK(east.frustum_skipped == skip);
        CHECK(r.views_used < 4);
        double sum = 0.0;
        int n = 0;
        for (const auto& v : r.views)
            if (v.used) {
                sum += v.metric;
                ++n;
            }
        CHECK(n == r.views_used);
        CHECK(r.metric_mean == Approx(sum / n));
    }
}

TEST_CASE("all views out of frame: no mean, no division by zero") {
    const core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
    metric::Evaluator evaluator(wallClouds(), &scene);
    metric::MetricOptions o = axisViews();
    o.look_at_world = scene.origin + glm::dvec3(0.0, 0.0, 500.0);  // look at the sky
    o.orbit.radius_m = 5.0;
    o.orbit.altitude_m = 1.0;
    const metric::MetricResult r = evaluator.run(o);
    CHECK(r.views_used == 0);
    CHECK(std::isnan(r.metric_mean));
    CHECK(std::isnan(r.exact_mean));
}

TEST_CASE("an empty P1 is a clear error") {
    metric::MetricClouds clouds;
    core::CloudPoint p;
    clouds.p2.points.push_back(p);
    CHECK_THROWS_WITH_AS(metric::Evaluator(clouds, nullptr),
                         doctest::Contains("metric: P1 (the target-only cloud) is empty"), core::Error);
}

TEST_CASE("options are validated naming the option and the allowed range") {
    metric::MetricOptions o;
    o.width = 8;
    CHECK_THROWS_WITH_AS(metric::validate(o), "metric: --width = 8: allowed 16..8192 pixels", core::Error);
    o = {};
    o.splat_px = 0.5;
    CHECK_THROWS_WITH_AS(metric::validate(o), "metric: --splat-px = 0.5: allowed [1, 64] pixels", core::Error);
    o = {};
    o.orbit.views = 0;
    CHECK_THROWS_WITH_AS(metric::validate(o), "metric: --views = 0: allowed 1..65535", core::Error);
    o = {};
    o.picture_view = 100;
    CHECK_THROWS_WITH_AS(metric::validate(o), doctest::Contains("--picture-view = 100"), core::Error);
    o = {};
    o.orbit.radius_m = 0.0;
    CHECK_THROWS_WITH_AS(metric::validate(o), doctest::Contains("--radius-m = 0"), core::Error);
    o = metric::MetricOptions{};
    o.orbit.altitude_m = 1e12;  // past float's metre steps: the target would leave every frame
    CHECK_THROWS_WITH_AS(metric::validate(o), "metric: --altitude-m = 1e+12: allowed [-1e7, 1e7] metres", core::Error);
    o = metric::MetricOptions{};
    o.orbit.radius_m = 2e7;
    CHECK_THROWS_WITH_AS(metric::validate(o), doctest::Contains("--radius-m = 2e+07: allowed (0, 1e7]"), core::Error);
    o = metric::MetricOptions{};
    o.look_at_world = glm::dvec3(1e300, 0.0, 0.0);
    CHECK_THROWS_WITH_AS(metric::validate(o), doctest::Contains("--look-at: out of range"), core::Error);
    CHECK_NOTHROW(metric::validate(metric::MetricOptions{}));
}

TEST_CASE("a scene without a target cannot give the clouds") {
    core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
    scene.meshes.erase(scene.meshes.begin());
    CHECK_THROWS_WITH_AS(metric::generateClouds(scene), doctest::Contains("has no target mesh"), core::Error);
}

TEST_CASE("compute and GL_POINTS rasterisers light the same pixels") {
    const core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
    metric::Evaluator evaluator(wallClouds(), &scene);
    metric::MetricOptions o = axisViews();
    o.exact = false;
    o.orbit.altitude_m = 4.0;  // off-axis: top and side faces, uneven splats
    for (double splat : {1.0, 2.0, 3.0}) {
        o.splat_px = splat;
        o.rasterizer = metric::Rasterizer::Compute;
        const metric::MetricResult a = evaluator.run(o);
        o.rasterizer = metric::Rasterizer::Raster;
        const metric::MetricResult b = evaluator.run(o);
        for (std::size_t k = 0; k < a.views.size(); ++k) {
            INFO("splat " << splat << " view " << k);
            // Same rule (pixel centres inside the square); float rounding of the projected
            // centres may flip a pixel on an exact edge now and then: 0.5 % slack.
            CHECK(std::abs(double(a.views[k].i1 - b.views[k].i1)) <= 0.005 * double(b.views[k].i1) + 2);
            CHECK(std::abs(double(a.views[k].i3 - b.views[k].i3)) <= 0.005 * double(b.views[k].i3) + 2);
            CHECK(std::abs(a.views[k].metric - b.views[k].metric) < 0.01);
            CHECK(a.views[k].depth_visible_px >= 0);
            CHECK(b.views[k].depth_visible_px == -1);
        }
    }
}

TEST_CASE("depth-aware variant: close to the closed form, 0 when hidden") {
    const double expected = test_support::closedFormVisible(kA, kD, kWallTop, kR);
    {
        const core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
        metric::Evaluator evaluator(wallClouds(), &scene);
        const metric::MetricResult r = evaluator.run(axisViews());
        CHECK(std::abs(r.depth_visible_mean - expected) < 0.08);
    }
    {
        const core::Scene scene = test_support::boxBehindWall(kA, kD, 4.0f, /*roof=*/true);
        metric::Evaluator evaluator(metric::generateClouds(scene), &scene);
        metric::MetricOptions o = axisViews();
        o.orbit.views = 2;
        const metric::MetricResult r = evaluator.run(o);
        CHECK(r.depth_visible_mean == 0.0);
    }
}

TEST_CASE("environment behind the target: xor counts it as hiding, exact and depth-aware do not") {
    // Cube at the origin, a wall 8 m behind it as seen from the camera at +x: nothing is in
    // front of the target, so the exact visible fraction is 1; but P2's wall points land on
    // the target's pixels, so I2 xor I3 is 0 there (docs/metric.md, "xor and visible").
    core::Scene scene;
    scene.source = "cube before a wall (in code)";
    scene.meshes.push_back(test_support::boxMesh({-kA, -kA, -kA}, {kA, kA, kA}, core::Role::Target, "cube"));
    scene.meshes.push_back(
        test_support::boxMesh({-8.1f, -12.0f, -3.0f}, {-8.0f, 12.0f, 8.0f}, core::Role::Environment, "wall"));
    metric::Evaluator evaluator(metric::generateClouds(scene), &scene);
    metric::MetricOptions o = axisViews();
    o.orbit.views = 1;  // eye at (+20, 0, 0)
    const metric::MetricResult r = evaluator.run(o);
    REQUIRE(r.views_used == 1);
    const metric::ViewResult& v = r.views[0];
    MESSAGE("exact " << v.exact << ", depth-aware " << v.depth_visible << ", xor " << v.metric << ", visible "
                     << v.visible);
    CHECK(v.exact == 1.0);
    CHECK(v.depth_visible > 0.95);
    CHECK(v.metric < 0.5);
    CHECK(v.visible < 0.5);
}

TEST_CASE("clouds read back from PCD files give the same counts, without an exact reference") {
    const core::Scene scene = test_support::boxBehindWall(kA, kD, kWallTop);
    const metric::MetricClouds& clouds = wallClouds();
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("ladarvr_metric_files_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    io::writeCloud(dir / "p1.pcd", clouds.p1, io::CloudFormat::PcdBinary);
    io::writeCloud(dir / "p2.pcd", clouds.p2, io::CloudFormat::PcdBinary);
    io::writeCloud(dir / "p3.ply", clouds.p3, io::CloudFormat::PlyBinary);
    metric::MetricClouds files;
    files.p1 = io::readCloud(dir / "p1.pcd");
    files.p2 = io::readCloud(dir / "p2.pcd");
    files.p3 = io::readCloud(dir / "p3.ply");
    std::filesystem::remove_all(dir);
    REQUIRE(files.p1.origin == scene.origin);  // the origin travels in the header
    metric::Evaluator from_files(files, nullptr);
    CHECK_FALSE(from_files.hasExact());
    metric::Evaluator from_scene(clouds, &scene);
    metric::MetricOptions o = axisViews();
    const metric::MetricResult a = from_files.run(o);
    const metric::MetricResult b = from_scene.run(o);
    CHECK_FALSE(a.has_exact);
    CHECK(std::isnan(a.exact_mean));
    CHECK(a.origin == b.origin);
    for (std::size_t k = 0; k < a.views.size(); ++k) {
        // Look-at: P1's bounds centre instead of the mesh's (the cube is sampled to its edges).
        CHECK(std::abs(a.views[k].metric - b.views[k].metric) < 0.02);
        CHECK(std::abs(double(a.views[k].i1 - b.views[k].i1)) < 0.03 * double(b.views[k].i1));
    }
}
