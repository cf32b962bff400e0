// tests/detect/labelled_scenes.hpp: synthetic labelled clouds for the trained detector's
// tests: flat ground, one tank-sized box (the target) and trees (trunk and a scattered
// crown) and a house-sized box (environment) at places drawn from a seed; and how much of
// the target one segment holds.
#pragma once
#include <core/point_cloud.hpp>
#include <detect/segmentation.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

namespace test_support {

inline void addPoint(core::PointCloud& c, glm::dvec3 p, core::Role role) {
    core::CloudPoint q;
    q.position = glm::vec3(p);
    q.label = role;
    q.rgb = role == core::Role::Ground ? core::kWhite : 0x336699u;
    c.points.push_back(q);
}

/// Top and sides of a box of `size` standing on z = 0 at `centre`, turned by yaw_rad.
inline void addBoxSurface(core::PointCloud& c, std::mt19937& rng, glm::dvec2 centre, glm::dvec3 size, double yaw_rad,
                          double step_m, core::Role role) {
    std::uniform_real_distribution<double> noise(-0.02, 0.02);
    const double cs = std::cos(yaw_rad), sn = std::sin(yaw_rad);
    auto put = [&](double u, double v, double z) {
        addPoint(c, {centre.x + cs * u - sn * v + noise(rng), centre.y + sn * u + cs * v + noise(rng), z + noise(rng)},
                 role);
    };
    const double hl = size.x / 2, hw = size.y / 2;
    for (double u = -hl; u <= hl; u += step_m)
        for (double v = -hw; v <= hw; v += step_m) put(u, v, size.z);
    for (double z = 0.05; z <= size.z; z += step_m) {
        for (double u = -hl; u <= hl; u += step_m) {
            put(u, -hw, z);
            put(u, hw, z);
        }
        for (double v = -hw; v <= hw; v += step_m) {
            put(-hl, v, z);
            put(hl, v, z);
        }
    }
}

/// A tree: a trunk of radius 0.25 m up to 3 m, a crown of `radius_m` scattered in a ball
/// centred 3 m + radius above the ground (leaves: points inside the ball, denser outside).
inline void addTree(core::PointCloud& c, std::mt19937& rng, glm::dvec2 at, double radius_m) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double z = 0.05; z < 3.0; z += 0.15)
        for (int k = 0; k < 8; ++k) {
            const double a = k * 0.785398;
            addPoint(c, {at.x + 0.25 * std::cos(a), at.y + 0.25 * std::sin(a), z}, core::Role::Environment);
        }
    const int leaves = int(900 * radius_m * radius_m);
    for (int k = 0; k < leaves; ++k) {
        glm::dvec3 d{u(rng), u(rng), u(rng)};
        if (glm::dot(d, d) > 1.0) continue;
        d *= radius_m;
        addPoint(c, {at.x + d.x, at.y + d.y, 3.0 + radius_m + d.z}, core::Role::Environment);
    }
}

/// Ground of side 70 m every 0.4 m, one target box of 7 x 3.5 x 2.5 m, `trees` trees and
/// a house of 11 x 8 x 6 m, each at its own place on a grid of 14 m cells (no overlap).
/// Returns the target's centre in `target_at`.
inline core::PointCloud labelledScene(std::uint32_t seed, int trees, glm::dvec2* target_at = nullptr) {
    core::PointCloud c;
    c.origin = {500.0, -300.0, 20.0};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> noise(-0.03, 0.03), jitter(-1.0, 1.0), yaw(0.0, 3.14159);
    for (double x = -35; x <= 35; x += 0.4)
        for (double y = -35; y <= 35; y += 0.4) addPoint(c, {x, y, noise(rng)}, core::Role::Ground);
    std::vector<glm::dvec2> places;
    for (int i = -2; i <= 2; ++i)
        for (int j = -2; j <= 2; ++j) places.push_back({i * 14.0, j * 14.0});
    std::shuffle(places.begin(), places.end(), rng);
    auto place = [&](std::size_t k) { return places[k] + glm::dvec2(jitter(rng), jitter(rng)); };
    const glm::dvec2 target = place(0);
    if (target_at) *target_at = target;
    addBoxSurface(c, rng, target, {7.0, 3.5, 2.5}, yaw(rng), 0.2, core::Role::Target);
    addBoxSurface(c, rng, place(1), {11.0, 8.0, 6.0}, yaw(rng), 0.3, core::Role::Environment);
    std::uniform_real_distribution<double> radius(2.0, 4.0);
    for (int t = 0; t < trees && std::size_t(t) + 2 < places.size(); ++t)
        addTree(c, rng, place(std::size_t(t) + 2), radius(rng));
    c.fields.rgb = c.fields.label = true;
    return c;
}

// The share of the target's points in the segment holding most of them, and that
// segment's share of target points.
inline std::pair<double, double> targetSegment(const core::PointCloud& c, const detect::Segmentation& s) {
    std::size_t total = 0;
    for (const core::CloudPoint& p : c.points) total += p.label == core::Role::Target;
    std::size_t best = 0, best_size = 1;
    for (const auto& seg : s.segments) {
        std::size_t t = 0;
        for (const std::uint32_t i : seg) t += c.points[i].label == core::Role::Target;
        if (t > best) best = t, best_size = seg.size();
    }
    return {double(best) / double(std::max<std::size_t>(total, 1)), double(best) / double(best_size)};
}

}  // namespace test_support
