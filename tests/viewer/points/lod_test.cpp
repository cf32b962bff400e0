// tests/viewer/points/lod_test.cpp: viewer LOD: frustum culling of cells (union of the
// eyes), the LOD order (a prefix of a cell is close to a uniform subsample, its layers
// ordered by place) and the point budget allocation, with known answers; then a headless
// EGL draw: a view looking away from the cloud draws fewer points, a budget caps them.
#include <viewer/cloud_feed.hpp>
#include <viewer/lod.hpp>
#include <viewer/cloud_feed_source.hpp>

#include "points/point_renderer.hpp"

#include <render/egl_context.hpp>
#include <render/orbit_camera.hpp>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

using namespace viewer;

namespace {

core::Bounds box(glm::dvec3 centre, double half) {
    core::Bounds b;
    b.extend(centre - glm::dvec3(half));
    b.extend(centre + glm::dvec3(half));
    return b;
}

// Camera at the origin looking along +x (or -x), z up, 60 deg vertical FoV, near 0.1, far 1000.
render::Frustum frustumLooking(double dir_x) {
    const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), glm::dvec3(dir_x, 0.0, 0.0), glm::dvec3(0.0, 0.0, 1.0));
    return render::Frustum::fromMatrix(render::projectionMatrix(60.0, 1.0, 0.1, 1000.0) * view);
}

}  // namespace

TEST_CASE("cells outside the frustum are culled, the others kept (known set)") {
    const std::vector<core::Bounds> boxes = {
        box({10, 0, 0}, 1),    // 0 straight ahead: kept
        box({-10, 0, 0}, 1),   // 1 behind: culled
        box({10, 100, 0}, 1),  // 2 far to the left of a 60 deg view: culled
        box({0, 0, 0}, 1),     // 3 the eye is inside it: kept
        box({500, 0, 0}, 5),   // 4 ahead, inside far: kept
        box({2000, 0, 0}, 5),  // 5 beyond the far plane: culled
        box({10, 0, 30}, 1),   // 6 above the 30 deg half-FoV: culled
        box({10, 0, 5}, 1),    // 7 inside the 30 deg half-FoV (atan(5/10) = 26.6 deg): kept
    };
    const std::vector<render::Frustum> one = {frustumLooking(1.0)};
    CHECK(visibleInAny(one, boxes) == std::vector<bool>{true, false, false, true, true, false, false, true});
    // The union of two eyes looking opposite ways also keeps the box behind.
    const std::vector<render::Frustum> two = {frustumLooking(1.0), frustumLooking(-1.0)};
    CHECK(visibleInAny(two, boxes) == std::vector<bool>{true, true, false, true, true, false, false, true});
    CHECK(visibleInAny(one, std::vector<core::Bounds>{core::Bounds{}}) == std::vector<bool>{false});
}

TEST_CASE("screen importance: (r / d)^2, 1 inside, larger when nearer") {
    const core::Bounds b = box({0, 0, 0}, 1.0);  // half diagonal sqrt(3)
    const double r = std::sqrt(3.0);
    CHECK(screenImportance(b, {10.0 * r, 0, 0}) == doctest::Approx(0.01));
    CHECK(screenImportance(b, {0.5, 0, 0}) == doctest::Approx(1.0));
    CHECK(screenImportance(b, {20, 0, 0}) > screenImportance(b, {40, 0, 0}));
    CHECK(screenImportance(core::Bounds{}, {0, 0, 0}) == 0.0);
}

TEST_CASE("budget allocation: known answers (proportional share, saturation, culled cells)") {
    using V = std::vector<std::size_t>;
    CHECK(allocateBudget(std::vector<double>{1, 1, 2}, V{100, 100, 100}, 100) == V{25, 25, 50});
    // The important cell has only 10 points: it is full, the others share the rest.
    CHECK(allocateBudget(std::vector<double>{1, 1, 8}, V{100, 100, 10}, 110) == V{50, 50, 10});
    // Importance 0 (culled) gets nothing, even with an unlimited budget.
    CHECK(allocateBudget(std::vector<double>{0, 1}, V{100, 100}, 0) == V{0, 100});
    CHECK(allocateBudget(std::vector<double>{0, 1}, V{100, 100}, 50) == V{0, 50});
    // Budget >= total: every visible point.
    CHECK(allocateBudget(std::vector<double>{0.1, 5, 1}, V{7, 9, 11}, 27) == V{7, 9, 11});
    CHECK(allocateBudget(std::vector<double>{0.1, 5, 1}, V{7, 9, 11}, 1000) == V{7, 9, 11});
}

TEST_CASE("budget allocation on random cells: sum <= budget, monotone in importance, capped by size") {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> imp(1e-6, 1.0);
    std::uniform_int_distribution<std::size_t> size(0, 20000);
    for (int trial = 0; trial < 50; ++trial) {
        const std::size_t n = 1 + trial * 7;
        std::vector<double> importance(n);
        std::vector<std::size_t> sizes(n);
        for (std::size_t i = 0; i < n; ++i) {
            importance[i] = imp(rng);
            sizes[i] = size(rng);
        }
        const std::size_t total = std::accumulate(sizes.begin(), sizes.end(), std::size_t{0});
        const std::size_t budget = 1 + rng() % (total + 1);
        const auto counts = allocateBudget(importance, sizes, budget);
        const std::size_t sum = std::accumulate(counts.begin(), counts.end(), std::size_t{0});
        REQUIRE(sum <= budget);
        CHECK(sum + n >= std::min(budget, total));  // at most one point lost per cell to rounding
        for (std::size_t i = 0; i < n; ++i) {
            REQUIRE(counts[i] <= sizes[i]);
            for (std::size_t j = 0; j < n; ++j)  // more important and not full -> not fewer points
                if (importance[i] > importance[j] && counts[j] > counts[i]) REQUIRE(counts[i] == sizes[i]);
        }
        if (budget >= total) CHECK(counts == sizes);
    }
}

TEST_CASE("LOD order: cells partition the points, each prefix is a uniform subsample, deterministic") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 100.0f);
    std::vector<core::CloudPoint> points(100000);
    for (std::size_t i = 0; i < points.size(); ++i) {
        // Sorted along x in the input (like a scan line): a plain prefix would be one strip.
        points[i].position = {float(i) * 100.0f / float(points.size()), u(rng), 0.5f * u(rng)};
        points[i].range_m = float(i);  // identity of the point
    }
    std::vector<core::CloudPoint> a = points, b = points;
    const auto cells = buildLodOrder(a);
    const auto cells_b = buildLodOrder(b);
    REQUIRE(cells.size() == 16);  // ceil(sqrt(100000 / 8192)) = 4 -> 4 x 4 grid, all non-empty
    REQUIRE(cells_b.size() == cells.size());
    for (std::size_t i = 0; i < a.size(); ++i) REQUIRE(a[i].range_m == b[i].range_m);
    // A permutation: every point once.
    std::vector<char> seen(points.size(), 0);
    for (const auto& p : a) seen[static_cast<std::size_t>(p.range_m)]++;
    CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<long>(points.size()));
    std::size_t next = 0;
    for (const auto& c : cells) {
        REQUIRE(c.first == next);
        next += c.count;
        // The first 10 % of the cell has the cell's mean x and y within 1.5 m (a 25 m cell:
        // a uniform sample of ~600 points has a standard error of ~0.3 m); the input order
        // (a strip) would be ~11 m off in x.
        glm::dvec3 mean_all(0.0), mean_prefix(0.0);
        const std::size_t k = c.count / 10;
        for (std::size_t i = 0; i < c.count; ++i) {
            const glm::dvec3 p(a[c.first + i].position);
            REQUIRE(p.x >= c.bounds.lo.x);
            REQUIRE(p.x <= c.bounds.hi.x);
            mean_all += p / double(c.count);
            if (i < k) mean_prefix += p / double(k);
        }
        CHECK(c.bounds.size().x <= 25.01);
        CHECK(std::abs(mean_prefix.x - mean_all.x) < 1.5);
        CHECK(std::abs(mean_prefix.y - mean_all.y) < 1.5);
        // Prefixes that end inside a layer too (3 %, 30 %, 70 %): each quarter of the cell
        // holds its share of the prefix's points within a factor of 1.5.
        for (const double fraction : {0.03, 0.3, 0.7}) {
            const auto len = static_cast<std::size_t>(fraction * double(c.count));
            std::array<double, 4> quarter{};
            const glm::dvec3 mid = c.bounds.centre();
            for (std::size_t i = 0; i < len; ++i) {
                const glm::dvec3 p(a[c.first + i].position);
                quarter[(p.x < mid.x ? 0 : 1) + (p.y < mid.y ? 0 : 2)] += 1.0;
            }
            for (const double q : quarter) {
                CHECK(q > double(len) / 4.0 / 1.5);
                CHECK(q < double(len) / 4.0 * 1.5);
            }
        }
    }
    CHECK(next == points.size());
}

TEST_CASE("LOD order: each layer is ordered by place, so neighbours in the order are near each other") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 100.0f);
    std::vector<core::CloudPoint> points(65536);
    for (auto& p : points) p.position = {u(rng), u(rng), 0.0f};
    std::vector<core::CloudPoint> shuffled = points;
    LodOptions one_cell;
    one_cell.cell_points = points.size();
    const auto cells = buildLodOrder(points, one_cell);
    REQUIRE(cells.size() == 1);
    // The last layer (the second half): consecutive points about one point spacing apart,
    // against about half the cell's size for the shuffled order alone.
    auto meanStep = [](const std::vector<core::CloudPoint>& v, std::size_t from, std::size_t to) {
        double sum = 0.0;
        for (std::size_t i = from + 1; i < to; ++i)
            sum += glm::distance(glm::dvec2(v[i].position.x, v[i].position.y),
                                 glm::dvec2(v[i - 1].position.x, v[i - 1].position.y));
        return sum / double(to - from - 1);
    };
    const std::size_t n = points.size();
    CHECK(meanStep(points, n / 2, n) < 2.0);     // spacing of 32768 points in 100 x 100 m: ~0.55 m
    CHECK(meanStep(shuffled, n / 2, n) > 30.0);  // the input order: uniformly random
    // The key: Morton order inside each of 8 x 8 blocks, blocks in bit-reversed order, so the
    // first four blocks are one in each quarter of the box.
    core::Bounds b;
    b.extend(glm::dvec3(0.0));
    b.extend(glm::dvec3(8.0, 8.0, 1.0));
    std::vector<std::pair<std::uint32_t, int>> blocks;
    for (int by = 0; by < 8; ++by)
        for (int bx = 0; bx < 8; ++bx)
            blocks.push_back({spreadOrderKey(glm::dvec3(bx + 0.5, by + 0.5, 0.0), b), (bx / 4) + 2 * (by / 4)});
    std::sort(blocks.begin(), blocks.end());
    std::array<int, 4> seen{};
    for (int i = 0; i < 4; ++i) seen[static_cast<std::size_t>(blocks[static_cast<std::size_t>(i)].second)]++;
    CHECK(seen == std::array<int, 4>{1, 1, 1, 1});
    CHECK(spreadOrderKey(glm::dvec3(0.1, 0.1, 0.0), b) < spreadOrderKey(glm::dvec3(0.9, 0.9, 0.0), b));
}

TEST_CASE("headless draw: looking away from the cloud draws fewer points, the budget caps them") {
    render::EglContext context;
    viewer::PointRenderer renderer;
    // 40,000 points on a 200 m x 200 m patch in front of the camera (+x side).
    core::PointCloud cloud;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 200.0f);
    for (int i = 0; i < 40000; ++i) {
        core::CloudPoint p;
        p.position = {20.0f + u(rng), u(rng) - 100.0f, 0.0f};
        cloud.points.push_back(p);
    }
    viewer::CloudFeed feed;
    feed.feedCloud(cloud, 10000);
    viewer::CloudFeedSource source(feed);
    source.poll();
    renderer.stream(source, cloud.points.size());
    REQUIRE(renderer.uploadedPoints() == 40000);
    REQUIRE(renderer.cellCount() >= 4 * 4);
    viewer::EyeTarget target, out;
    REQUIRE(target.ensure(64, 64));
    REQUIRE(out.ensure(64, 64));
    auto eyeLooking = [](glm::dvec3 at) {
        viewer::EyeDraw e;
        e.view = glm::lookAt(glm::dvec3(0.0, 0.0, 30.0), at, glm::dvec3(0.0, 0.0, 1.0));
        e.projection = render::projectionMatrix(60.0, 1.0, e.near_m, e.far_m);
        return e;
    };
    const viewer::ViewStyle style;
    auto draw = [&](const viewer::EyeDraw& e, std::size_t budget, bool cull) {
        renderer.planFrame(std::span<const viewer::EyeDraw>(&e, 1), budget, cull);
        return renderer.drawEye(target, e, style, viewer::ViewMode::Free, out.fbo, 0, 0, 64, 64);
    };
    const viewer::EyeDraw toward = eyeLooking({120.0, 0.0, 0.0});
    const viewer::EyeDraw away = eyeLooking({-120.0, 0.0, 0.0});
    const auto all = draw(toward, 0, false);
    CHECK(all.points_drawn == 40000);
    const auto ahead = draw(toward, 0, true);
    const auto behind = draw(away, 0, true);
    CHECK(ahead.points_drawn > 20000);  // most of the patch is in view
    CHECK(behind.points_drawn < 4000);  // only cells reaching behind the camera
    CHECK(behind.chunks_culled > behind.chunks_drawn);
    const auto budgeted = draw(toward, 5000, true);
    CHECK(budgeted.points_drawn <= 5000);
    CHECK(budgeted.points_drawn > 4000);
    CHECK(renderer.plannedPoints() <= 5000);
    target.destroy();
    out.destroy();
}

TEST_CASE("the feed builds the LOD order on the producer's side when enabled") {
    core::PointCloud cloud;
    for (int i = 0; i < 30000; ++i) {
        core::CloudPoint p;
        p.position = {float(i % 300), float(i / 300), 0.0f};
        p.range_m = float(i);
        cloud.points.push_back(p);
    }
    viewer::CloudFeed feed;
    feed.enableLodOrder();
    feed.feedCloud(cloud, 20000);
    const auto chunks = feed.take();
    REQUIRE(chunks.size() == 2);
    std::vector<core::CloudPoint> first(cloud.points.begin(), cloud.points.begin() + 20000);
    const auto cells = buildLodOrder(first);  // the same seed: the same order and cells
    REQUIRE(chunks[0].cells.size() == cells.size());
    CHECK(chunks[0].cells.size() == 4);  // ceil(sqrt(20000 / 8192)) = 2: a 2 x 2 grid
    for (std::size_t i = 0; i < first.size(); ++i) REQUIRE(chunks[0].points[i].range_m == first[i].range_m);
    CHECK(chunks[1].points.size() == 10000);
    CHECK_FALSE(chunks[1].cells.empty());
}

TEST_CASE("allocateFocusedBudget: focused cells drawn whole, the rest shares what they leave") {
    using V = std::vector<std::size_t>;
    const std::vector<double> importance{1, 1, 2, 0};
    const V sizes{100, 100, 100, 100};
    // No focus: allocateBudget's answer.
    CHECK(allocateFocusedBudget(importance, sizes, {false, false, false, false}, 100) == V{25, 25, 50, 0});
    // The first cell focused: all of it; the other two share the 20 left by importance.
    CHECK(allocateFocusedBudget(importance, sizes, {true, false, false, false}, 120) == V{100, 6, 13, 0});
    // The focus takes more than the budget: it alone is drawn.
    CHECK(allocateFocusedBudget(importance, sizes, {true, true, false, false}, 150) == V{100, 100, 0, 0});
    // A focused cell out of view (importance 0) gets nothing.
    CHECK(allocateFocusedBudget(importance, sizes, {false, false, false, true}, 100) == V{25, 25, 50, 0});
    // Unlimited: everything in view.
    CHECK(allocateFocusedBudget(importance, sizes, {true, false, false, false}, 0) == V{100, 100, 100, 0});
}

TEST_CASE("LodFocus::touches: a box within a sphere's radius of its centre") {
    LodFocus focus;
    core::Bounds box;
    box.lo = glm::dvec3(0.0);
    box.hi = glm::dvec3(10.0);
    CHECK_FALSE(focus.touches(box));
    focus.spheres.push_back({glm::dvec3(13.0, 5.0, 5.0), 2.9});
    CHECK_FALSE(focus.touches(box));
    focus.spheres.push_back({glm::dvec3(13.0, 14.0, 5.0), 5.1});  // 3 and 4 from the corner edge: 5
    CHECK(focus.touches(box));
    CHECK_FALSE(focus.touches(core::Bounds{}));
}
