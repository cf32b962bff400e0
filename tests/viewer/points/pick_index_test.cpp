// tests/viewer/points/pick_index_test.cpp: the pointer's cone pick against known answers and
// against a scan of every point.
#include <viewer/pick_index.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <random>
#include <span>

using namespace viewer;

namespace {
core::CloudPoint at(double x, double y, double z, core::Role label = core::Role::Environment) {
    core::CloudPoint p;
    p.position = glm::vec3(float(x), float(y), float(z));
    p.label = label;
    return p;
}
}  // namespace

TEST_CASE("a ray through a known point picks that point") {
    std::vector<core::CloudPoint> points;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-50.0f, 50.0f);
    for (int i = 0; i < 20000; ++i) points.push_back(at(u(rng), u(rng), u(rng) * 0.1));
    // The known point sits 1 m above every other point; a ray from above through it
    // meets it first, from any direction that comes down on it.
    const glm::dvec3 known(12.25, -7.5, 6.0);
    points.push_back(at(known.x, known.y, known.z, core::Role::Target));
    const PickIndex index(points);
    for (const glm::dvec3 from :
         {glm::dvec3(0.0, 0.0, 100.0), glm::dvec3(30.0, 20.0, 80.0), glm::dvec3(-60.0, 0.0, 40.0)}) {
        const glm::dvec3 origin = known + from;
        const auto hit = index.pick(origin, known - origin);
        REQUIRE(hit);
        CHECK(hit->index == points.size() - 1);
        CHECK(glm::length(hit->local - known) < 1e-5);
    }
    // A cloud of the known point alone: it is the pick, with its label and range.
    const std::vector<core::CloudPoint> one = {at(known.x, known.y, known.z, core::Role::Target),
                                               at(known.x + 5.0, known.y, known.z)};
    const PickIndex small(one);
    const auto h = small.pick(glm::dvec3(0.0), known);
    REQUIRE(h);
    CHECK(h->index == 0);
    CHECK(h->label == core::Role::Target);
    CHECK(h->distance_m == doctest::Approx(glm::length(known)).epsilon(1e-6));
    CHECK(glm::length(h->local - known) < 1e-5);
}

TEST_CASE("the pick is the nearest point inside the cone, not the nearest to the axis") {
    // On the axis at 20 m, and 0.3 deg off the axis at 10 m: the nearer one wins.
    const double off = 10.0 * std::tan(0.3 * 3.14159265358979 / 180.0);
    const std::vector<core::CloudPoint> points = {at(20.0, 0.0, 0.0), at(10.0, off, 0.0), at(5.0, 1.0, 0.0)};
    const PickIndex index(points);
    const auto hit = index.pick(glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0));
    REQUIRE(hit);
    CHECK(hit->index == 1);
    // With a narrower cone (0.2 deg) the point off the axis is outside: the far one wins.
    PickOptions narrow;
    narrow.angle_deg = 0.2;
    CHECK(index.pick(glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), narrow)->index == 0);
    // Behind the origin and off to the side: nothing.
    CHECK_FALSE(index.pick(glm::dvec3(0.0), glm::dvec3(-1.0, 0.0, 0.0)));
    CHECK_FALSE(index.pick(glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 1.0)));
    CHECK_FALSE(index.pick(glm::dvec3(0.0), glm::dvec3(0.0)));  // no direction
    // Beyond the range: nothing.
    PickOptions short_range;
    short_range.max_range_m = 4.0;
    CHECK_FALSE(index.pick(glm::dvec3(0.0), glm::dvec3(1.0, 0.0, 0.0), short_range));
}

TEST_CASE("the k-d tree pick equals the scan on random rays over a terrain-like cloud") {
    std::vector<core::CloudPoint> points;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-200.0f, 200.0f), h(0.0f, 8.0f);
    for (int i = 0; i < 100000; ++i) points.push_back(at(u(rng), u(rng), i % 10 == 0 ? h(rng) : 0.0f));
    const PickIndex index(points);
    std::uniform_real_distribution<double> angle(0.0, 6.283), radius(20.0, 300.0);
    int hits = 0;
    for (int k = 0; k < 200; ++k) {
        const double a = angle(rng), r = radius(rng);
        const glm::dvec3 origin(r * std::cos(a), r * std::sin(a), 40.0 + r * 0.3);
        const glm::dvec3 target(u(rng) * 0.5, u(rng) * 0.5, 0.0);
        const auto fast = index.pick(origin, target - origin), slow = index.pickByScan(origin, target - origin);
        REQUIRE(bool(fast) == bool(slow));
        if (fast) {
            ++hits;
            CHECK(fast->distance_m == doctest::Approx(slow->distance_m).epsilon(1e-9));
        }
    }
    CHECK(hits > 150);
}

TEST_CASE("distance to the nearest ground-truth target point") {
    const std::vector<core::CloudPoint> points = {at(0, 0, 0), at(10, 0, 0, core::Role::Target),
                                                  at(12, 0, 0, core::Role::Target)};
    const PickIndex index(points);
    CHECK(*index.nearestTargetDistance(glm::dvec3(10.5, 0.0, 0.0)) == doctest::Approx(0.5));
    CHECK(*index.nearestTargetDistance(glm::dvec3(0.0, 3.0, 0.0)) == doctest::Approx(std::sqrt(109.0)));
    const std::vector<core::CloudPoint> none = {at(0, 0, 0)};
    CHECK_FALSE(PickIndex(none).nearestTargetDistance(glm::dvec3(0.0)));
}

TEST_CASE("pick options are validated") {
    PickOptions o;
    o.angle_deg = 0.0;
    CHECK_THROWS_WITH_AS(validate(o), "view: --pick-angle 0: allowed (0, 10] degrees", core::Error);
    o.angle_deg = 11.0;
    CHECK_THROWS_AS(validate(o), core::Error);
    o.angle_deg = 0.5;
    CHECK_NOTHROW(validate(o));
}

TEST_CASE("a pick set over the chunks of a stream picks what one index over the whole cloud picks") {
    // A terrain-like cloud with some targets, streamed as chunks (the point source's leaves):
    // one PickIndex per chunk in a PickSet against one PickIndex over every point.
    std::vector<core::CloudPoint> points;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-150.0f, 150.0f), h(0.0f, 6.0f);
    for (int i = 0; i < 60000; ++i)
        points.push_back(at(u(rng), u(rng), i % 7 == 0 ? h(rng) : 0.0f,
                            i % 500 == 0 ? core::Role::Target : core::Role::Environment));
    const PickIndex whole(points);
    PickSet set;
    constexpr std::size_t kChunk = 7000;  // 9 chunks, the last one shorter
    for (std::size_t first = 0; first < points.size(); first += kChunk) {
        const std::size_t n = std::min(kChunk, points.size() - first);
        set.add(std::make_shared<const PickIndex>(std::span<const core::CloudPoint>(points.data() + first, n)));
    }
    REQUIRE(set.nodes() == 9);
    CHECK(set.size() == points.size());
    CHECK(set.hasTargets());
    std::uniform_real_distribution<double> angle(0.0, 6.283), radius(20.0, 250.0);
    int hits = 0;
    for (int k = 0; k < 300; ++k) {
        const double a = angle(rng), r = radius(rng);
        const glm::dvec3 origin(r * std::cos(a), r * std::sin(a), 30.0 + r * 0.2);
        const glm::dvec3 target(u(rng) * 0.6, u(rng) * 0.6, 0.0);
        const auto one = whole.pick(origin, target - origin), per_node = set.pick(origin, target - origin);
        REQUIRE(bool(one) == bool(per_node));
        if (!one) continue;
        ++hits;
        // The same point: its position, distance and label; its node and index within it
        // name the same point of the whole cloud.
        CHECK(per_node->local == one->local);
        CHECK(per_node->distance_m == one->distance_m);
        CHECK(per_node->label == one->label);
        CHECK(points[per_node->node * kChunk + per_node->index].position == points[one->index].position);
        const glm::dvec3 probe = target + glm::dvec3(0.0, 0.0, 3.0);
        REQUIRE(set.nearestTargetDistance(probe));
        CHECK(*set.nearestTargetDistance(probe) == doctest::Approx(*whole.nearestTargetDistance(probe)).epsilon(1e-9));
    }
    CHECK(hits > 200);
    // An empty set picks nothing and knows no target.
    const PickSet empty;
    CHECK_FALSE(empty.pick(glm::dvec3(0.0, 0.0, 50.0), glm::dvec3(0.0, 0.0, -1.0)));
    CHECK_FALSE(empty.nearestTargetDistance(glm::dvec3(0.0)));
    CHECK_FALSE(empty.hasTargets());
}

TEST_CASE("a pick set's hit names the level of the node it came from") {
    // Three nodes of an octree: a coarse root (level 0) and two finer nodes (levels 2 and 5),
    // each one point on a vertical line at a known height; the ray comes down the line.
    PickSet set;
    const std::vector<core::CloudPoint> root = {at(0.0, 0.0, 1.0)}, mid = {at(0.0, 0.0, 3.0)},
                                        fine = {at(0.0, 0.0, 2.0)};
    set.add(std::make_shared<const PickIndex>(root), 0);
    set.add(std::make_shared<const PickIndex>(mid), 2);
    set.add(std::make_shared<const PickIndex>(fine), 5);
    const glm::dvec3 down(0.0, 0.0, -1.0);
    // From above, the highest point (level 2) is met first.
    auto hit = set.pick(glm::dvec3(0.0, 0.0, 10.0), down);
    REQUIRE(hit);
    CHECK(hit->node == 1);
    CHECK(hit->level == 2);
    // From between 3 m and 2 m, the point at 2 m (level 5) is.
    hit = set.pick(glm::dvec3(0.0, 0.0, 2.5), down);
    REQUIRE(hit);
    CHECK(hit->node == 2);
    CHECK(hit->level == 5);
    // A set built without levels (a streamed cloud's chunks) says -1.
    PickSet plain;
    plain.add(std::make_shared<const PickIndex>(root));
    hit = plain.pick(glm::dvec3(0.0, 0.0, 10.0), down);
    REQUIRE(hit);
    CHECK(hit->level == -1);
}
