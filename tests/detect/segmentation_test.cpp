// tests/detect/segmentation_test.cpp: the trained detector's segments under a noisy
// sensor: the height threshold follows the measured ground thickness, a sparse trail of
// points (noise, mixed returns) does not chain a vehicle to the crown above it, the
// views' height errors are taken off before heights are measured, and a vehicle against
// a wall or under a touching crown is split from them at the split height, the
// clustering gives what a brute-force reading of its rule gives, and the segments do not
// depend on the number of threads.
#include <core/error.hpp>
#include <detect/segmentation.hpp>

#include "labelled_scenes.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>

namespace {

// Ground of side 40 m every step_m whose points belong to `views` views; each view's
// ground is shifted by its own height error (a misregistered view) and every point has
// Gaussian range noise of sigma_m.
core::PointCloud noisyGround(double sigma_m, int views, double view_error_m, std::uint32_t seed, double step_m = 0.2) {
    core::PointCloud c;
    c.origin = {100.0, 200.0, 30.0};
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, sigma_m), shift(0.0, view_error_m);
    std::vector<double> view_shift(static_cast<std::size_t>(views));
    for (double& s : view_shift) s = shift(rng);
    std::uniform_int_distribution<int> pick(0, views - 1);
    for (double x = -20; x <= 20; x += step_m)
        for (double y = -20; y <= 20; y += step_m) {
            core::CloudPoint p;
            const int v = pick(rng);
            p.view = std::uint16_t(v);
            p.position = glm::vec3(glm::dvec3(x, y, view_shift[std::size_t(v)] + noise(rng)));
            p.label = core::Role::Ground;
            c.points.push_back(p);
        }
    c.fields.rgb = c.fields.label = c.fields.view = true;
    return c;
}

std::size_t largestSegment(const detect::Segmentation& s) {
    std::size_t n = 0;
    for (const auto& seg : s.segments) n = std::max(n, seg.size());
    return n;
}

}  // namespace

TEST_CASE("segments: the height threshold grows with the measured ground thickness") {
    core::PointCloud c = noisyGround(0.2, 1, 0.0, 5);
    std::mt19937 rng(6);
    const std::size_t ground_points = c.points.size();
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {7.0, 3.5, 2.5}, 0.3, 0.2, core::Role::Target);
    detect::SegmentOptions o;
    const detect::Segmentation s = detect::segmentCloud(c, o);
    CHECK(s.ground_sigma_m == doctest::Approx(0.2).epsilon(0.25));
    CHECK(s.min_height_m == doctest::Approx(3.0 * s.ground_sigma_m));
    o.ground_sigmas = 0.0;
    const detect::Segmentation flat = detect::segmentCloud(c, o);
    CHECK(flat.min_height_m == o.min_height_m);
    // The ground points left above the threshold: fewer with the thickness-aware one.
    std::size_t ground_above = 0, ground_above_flat = 0;
    for (std::size_t i = 0; i < ground_points; ++i) {
        ground_above += s.height_m[i] > s.min_height_m;
        ground_above_flat += flat.height_m[i] > flat.min_height_m;
    }
    INFO(ground_above << " against " << ground_above_flat);
    CHECK(ground_above * 4 < ground_above_flat);
    CHECK(ground_above_flat > 100);
}

TEST_CASE("segments: the views' height errors are taken off the ground before heights are measured") {
    // Eight views each shifted by about 0.6 m: one view's ground stands well above another's.
    core::PointCloud c = noisyGround(0.03, 8, 0.6, 7);
    detect::SegmentOptions o;
    const detect::Segmentation with_views = detect::segmentCloud(c, o);
    c.fields.view = false;  // the same points without their views: one ground, as thick as all views together
    const detect::Segmentation without = detect::segmentCloud(c, o);
    INFO(with_views.ground_sigma_m << " against " << without.ground_sigma_m);
    CHECK(with_views.ground_sigma_m < 0.06);
    CHECK(without.ground_sigma_m > 0.15);
}

TEST_CASE("segments: a sparse trail of points does not chain a vehicle to the crown above it") {
    // Sampled as a full paper cloud is: 100 points per square metre, about 6 per voxel face.
    core::PointCloud c = noisyGround(0.02, 1, 0.0, 9, 0.1);
    std::mt19937 rng(10);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {7.0, 3.5, 2.5}, 0.0, 0.1, core::Role::Target);
    // A crown: a dense slab 1.5 m above the vehicle's roof, wider than the vehicle.
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 12000; ++k)
        test_support::addPoint(c, {6.0 * u(rng), 4.0 * u(rng), 4.5 + 0.5 * u(rng)}, core::Role::Environment);
    // The trail: single points every 0.2 m from the roof up to the crown (mixed returns).
    for (double z = 2.6; z < 4.0; z += 0.2) test_support::addPoint(c, {1.0, 0.5, z}, core::Role::Environment);
    detect::SegmentOptions o;
    o.split_height_m = 0;        // step 2 alone (the split below would part them too,
    o.max_vehicle_length_m = 0;  // and so would step 5's under the crown)
    o.core_points = 1;           // every voxel joins: the trail chains the vehicle and the crown
    const detect::Segmentation chained = detect::segmentCloud(c, o);
    o.core_points = 3;
    const detect::Segmentation apart = detect::segmentCloud(c, o);
    CHECK(apart.core_points == 3);
    CHECK(apart.points_per_voxel_face > 6.0);
    auto targetShare = [&](const detect::Segmentation& s) {
        // The share of target points in the segment holding most of them.
        double best = 0;
        for (const auto& seg : s.segments) {
            std::size_t t = 0;
            for (const std::uint32_t i : seg) t += c.points[i].label == core::Role::Target;
            if (t * 2 > seg.size() || best == 0) best = std::max(best, double(t) / double(seg.size()));
        }
        return best;
    };
    CHECK(targetShare(chained) < 0.5);
    CHECK(targetShare(apart) > 0.95);
    CHECK(largestSegment(apart) < largestSegment(chained));
}

namespace {

// A wall 20 m long, 0.3 m thick and `height_m` tall along y = y0, sampled every 0.1 m.
void addWall(core::PointCloud& c, double y0, double height_m) {
    for (double x = -10; x <= 10; x += 0.1)
        for (double z = 0.05; z <= height_m; z += 0.1) {
            test_support::addPoint(c, {x, y0, z}, core::Role::Environment);
            test_support::addPoint(c, {x, y0 - 0.3, z}, core::Role::Environment);
        }
}

}  // namespace

TEST_CASE("segments: a vehicle parked 0.3 m from a tall wall is split from it") {
    core::PointCloud c = noisyGround(0.02, 1, 0.0, 13, 0.1);
    std::mt19937 rng(14);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {7.0, 3.5, 2.5}, 0.0, 0.1, core::Role::Target);
    addWall(c, -1.75 - 0.3, 10.0);  // the wall's face 0.3 m from the vehicle's side
    detect::SegmentOptions o;
    o.split_height_m = 0;
    const detect::Segmentation whole = detect::segmentCloud(c, o);
    CHECK(whole.split_segments == 0);
    CHECK(test_support::targetSegment(c, whole).second < 0.5);  // one segment, mostly wall
    o.split_height_m = 4.0;
    const detect::Segmentation split = detect::segmentCloud(c, o);
    CHECK(split.split_segments == 1);
    const auto [found, purity] = test_support::targetSegment(c, split);
    INFO(found << " of the vehicle in a segment " << purity << " vehicle");
    CHECK(found > 0.8);  // less its lowest rows, within the terrain's tolerance
    CHECK(purity > 0.95);
    // The wall stays one segment (less its lowest rows), with none of the vehicle.
    std::size_t wall_points = 0;
    for (const core::CloudPoint& p : c.points) wall_points += p.label == core::Role::Environment;
    const auto wall = std::max_element(split.segments.begin(), split.segments.end(),
                                       [](const auto& a, const auto& b) { return a.size() < b.size(); });
    CHECK(wall->size() * 10 > wall_points * 9);
    CHECK(std::none_of(wall->begin(), wall->end(),
                       [&](std::uint32_t i) { return c.points[i].label == core::Role::Target; }));
}

TEST_CASE("segments: a vehicle under a crown that touches a wall keeps its roof below the gap") {
    // The crown, 1.5 m above the roof, spans the vehicle and reaches the wall: one segment
    // without the split. The vehicle's columns stop at the gap under the crown, so they do
    // not rise and the vehicle stands free; the wall's and the crown's stay together.
    core::PointCloud c = noisyGround(0.02, 1, 0.0, 19, 0.1);
    std::mt19937 rng(20);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {7.0, 3.5, 2.5}, 0.0, 0.1, core::Role::Target);
    addWall(c, -1.75 - 0.3, 10.0);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 12000; ++k)
        test_support::addPoint(c, {6.0 * u(rng), 4.0 * u(rng), 4.5 + 0.5 * u(rng)}, core::Role::Environment);
    detect::SegmentOptions o;
    o.split_height_m = 0;
    CHECK(test_support::targetSegment(c, detect::segmentCloud(c, o)).second < 0.5);
    o.split_height_m = 4.0;
    const detect::Segmentation split = detect::segmentCloud(c, o);
    CHECK(split.split_segments == 1);
    const auto [found, purity] = test_support::targetSegment(c, split);
    INFO(found << " of the vehicle in a segment " << purity << " vehicle");
    CHECK(found > 0.8);
    CHECK(purity > 0.95);
}

TEST_CASE("segments: a tall segment with nothing standing free below the split height is kept whole") {
    core::PointCloud c = noisyGround(0.02, 1, 0.0, 15, 0.1);
    std::mt19937 rng(16);
    addWall(c, 0.0, 10.0);
    test_support::addTree(c, rng, {0.0, 6.0}, 3.0);  // a trunk rising into a crown up to 9 m
    detect::SegmentOptions o;
    const detect::Segmentation s = detect::segmentCloud(c, o);
    CHECK(s.split_segments == 0);
    o.split_height_m = 0;
    CHECK(detect::segmentCloud(c, o).segments == s.segments);
}

TEST_CASE("segments: a sparsely sampled cloud joins every voxel") {
    // 6 points per square metre, 0.4 a voxel face: a surface has no voxel of 3 points.
    core::PointCloud c = noisyGround(0.02, 1, 0.0, 11, 0.4);
    std::mt19937 rng(12);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {7.0, 3.5, 2.5}, 0.4, 0.4, core::Role::Target);
    detect::SegmentOptions o;
    const detect::Segmentation s = detect::segmentCloud(c, o);
    CHECK(s.core_points == 1);
    REQUIRE(!s.segments.empty());
    std::size_t box = 0;
    for (const core::CloudPoint& p : c.points) box += p.label == core::Role::Target;
    // The box stands as one segment (less its lowest rows, within SMRF's ground
    // tolerance); with a bar of 3 no voxel would be dense and it would fall apart.
    CHECK(largestSegment(s) * 2 > box);
    o.core_points = 1;
    CHECK(detect::segmentCloud(c, o).segments == s.segments);
}

TEST_CASE("segments: the clustering equals a brute-force reading of its rule") {
    // Blobs of points of varied density above flat ground (dense voxels, sparse ones, lone
    // points), clustered by segmentCloud and by the rule done pair by pair: voxels of
    // voxel_m from the cloud's low corner; dense voxels whose centroids lie within the
    // tolerance join; a sparse voxel joins its nearest dense voxel within it (ties: the
    // one whose first point comes first); segments in the order of their first point,
    // those under min_points dropped.
    core::PointCloud c = noisyGround(0.02, 1, 0.0, 21, 0.1);
    const std::size_t ground_points = c.points.size();
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int b = 0; b < 12; ++b) {
        const glm::dvec3 centre{-16.0 + 32.0 * u(rng), -16.0 + 32.0 * u(rng), 1.5 + u(rng)};
        const glm::dvec3 half{0.3 + 1.7 * u(rng), 0.3 + 1.7 * u(rng), 0.2 + 0.6 * u(rng)};
        const int points = 30 + int(1500 * u(rng));
        for (int k = 0; k < points; ++k)
            test_support::addPoint(c, centre + half * glm::dvec3(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1),
                                   core::Role::Environment);
    }
    for (int k = 0; k < 300; ++k)
        test_support::addPoint(c, {-19.0 + 38.0 * u(rng), -19.0 + 38.0 * u(rng), 1.0 + 2.5 * u(rng)},
                               core::Role::Environment);
    detect::SegmentOptions o;
    o.split_height_m = 0;
    const detect::Segmentation got = detect::segmentCloud(c, o);
    REQUIRE(got.above_points == c.points.size() - ground_points);  // every blob point, no ground

    const glm::dvec3 lo = c.bounds().lo;
    std::vector<std::array<std::int64_t, 3>> cell;
    std::vector<glm::dvec3> sum;
    std::vector<std::size_t> count, voxel_of(c.points.size());
    for (std::size_t i = ground_points; i < c.points.size(); ++i) {
        const glm::dvec3 p = glm::dvec3(c.points[i].position) - lo;
        const std::array<std::int64_t, 3> k{std::int64_t(std::floor(p.x / o.voxel_m)),
                                            std::int64_t(std::floor(p.y / o.voxel_m)),
                                            std::int64_t(std::floor(p.z / o.voxel_m))};
        const std::size_t v = std::size_t(std::find(cell.begin(), cell.end(), k) - cell.begin());
        if (v == cell.size()) cell.push_back(k), sum.emplace_back(0.0), count.push_back(0);
        sum[v] += p;
        ++count[v];
        voxel_of[i] = v;
    }
    const std::size_t voxels = cell.size();
    CHECK(got.voxels == voxels);
    const double tol2 = o.cluster_tolerance_m * o.cluster_tolerance_m;
    auto near2 = [&](std::size_t a, std::size_t b) {
        const glm::dvec3 d = sum[a] / double(count[a]) - sum[b] / double(count[b]);
        return glm::dot(d, d);
    };
    auto dense = [&](std::size_t v) { return count[v] >= std::size_t(got.core_points); };
    std::vector<std::size_t> group(voxels);
    std::iota(group.begin(), group.end(), std::size_t(0));
    for (bool changed = true; changed;) {  // dense pairs: relabel to the smaller group until stable
        changed = false;
        for (std::size_t a = 0; a < voxels; ++a)
            for (std::size_t b = 0; b < voxels; ++b)
                if (a != b && dense(a) && dense(b) && near2(a, b) <= tol2 && group[b] < group[a])
                    group[a] = group[b], changed = true;
    }
    std::size_t sparse_joined = 0;
    std::vector<std::size_t> final_group = group;
    for (std::size_t a = 0; a < voxels; ++a) {
        if (dense(a)) continue;
        std::size_t best = voxels;
        for (std::size_t b = 0; b < voxels; ++b)
            if (dense(b) && near2(a, b) <= tol2 && (best == voxels || near2(a, b) < near2(a, best)))
                best = b;  // b ascending: an equally near later one does not replace it
        if (best != voxels) final_group[a] = group[best], ++sparse_joined;
    }
    std::vector<std::vector<std::uint32_t>> want;
    std::vector<std::size_t> slot(voxels, SIZE_MAX);
    for (std::size_t i = ground_points; i < c.points.size(); ++i) {
        std::size_t& s = slot[final_group[voxel_of[i]]];
        if (s == SIZE_MAX) s = want.size(), want.emplace_back();
        want[s].push_back(std::uint32_t(i));
    }
    std::erase_if(want, [&](const auto& seg) { return seg.size() < std::size_t(o.min_points); });
    CHECK(got.core_points == 3);
    CHECK(sparse_joined > 0);
    CHECK(want.size() >= 5);
    CHECK(got.segments == want);
}

TEST_CASE("segments: the same whatever the thread count, on a cloud the clustering cuts into parts") {
    // Enough points above the terrain (over 4 x 65536) that the clustering, its sort and
    // its sweeps run in up to four parts: blobs of varied density, lone points, and a
    // vehicle beside a tall wall so that the split runs too.
    core::PointCloud c = noisyGround(0.02, 1, 0.0, 31, 0.1);
    const std::size_t ground_points = c.points.size();
    std::mt19937 rng(32);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    test_support::addBoxSurface(c, rng, {0.0, 0.0}, {7.0, 3.5, 2.5}, 0.0, 0.1, core::Role::Target);
    addWall(c, -1.75 - 0.3, 10.0);
    while (c.points.size() - ground_points < 300000) {
        const glm::dvec3 centre{-18.0 + 36.0 * u(rng), -18.0 + 36.0 * u(rng), 1.0 + 4.0 * u(rng)};
        const glm::dvec3 half{0.2 + 1.5 * u(rng), 0.2 + 1.5 * u(rng), 0.2 + 1.0 * u(rng)};
        const int points = 5 + int(4000 * u(rng) * u(rng));
        for (int k = 0; k < points; ++k)
            test_support::addPoint(c, centre + half * glm::dvec3(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1),
                                   core::Role::Environment);
    }
    detect::SegmentOptions o;
    o.split_height_m = 4.0;
    const detect::Segmentation one = detect::segmentCloud(c, o, 1);
    REQUIRE(one.above_points > 4 * 65536);
    CHECK(one.split_segments >= 1);
    CHECK(one.segments.size() >= 20);
    for (const int threads : {2, 3, 4, 8}) {
        CAPTURE(threads);
        const detect::Segmentation many = detect::segmentCloud(c, o, threads);
        CHECK(many.above_points == one.above_points);
        CHECK(many.voxels == one.voxels);
        CHECK(many.split_segments == one.split_segments);
        CHECK(many.height_m == one.height_m);
        CHECK(many.segments == one.segments);
    }
    CHECK_THROWS_WITH_AS(detect::segmentCloud(c, o, 0), "detect: threads = 0: allowed >= 1", core::Error);
}

TEST_CASE("segments: options out of range are one line naming the option") {
    detect::SegmentOptions o;
    o.core_points = 0;
    CHECK_THROWS_WITH(detect::validate(o), doctest::Contains("--segment-core-points = 0: allowed [1, 1000]"));
    o = {};
    o.ground_sigmas = -1;
    CHECK_THROWS_WITH(detect::validate(o), doctest::Contains("--ground-sigmas = -1: allowed [0, 20]"));
    o = {};
    o.split_height_m = 0.5;
    CHECK_THROWS_WITH(detect::validate(o),
                      doctest::Contains("--split-height-m = 0.5: allowed 0 (no split) or [1, 100] m"));
}
