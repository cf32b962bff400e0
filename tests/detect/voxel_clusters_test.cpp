// tests/detect/voxel_clusters_test.cpp: the clustering on voxels (detect/src/voxel_clusters.hpp)
// on its own: the radix sort equals a stable sort by key whatever the parts, and clusters of
// known shape: two blobs apart, a sparse voxel between them taken by the nearer one, not
// chaining them, and a point past the key's range refused in one line.
#include "voxel_clusters.hpp"

#include <test_files.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using detect::detail::KeyedPoints;

core::PointCloud cloudOf(const std::vector<glm::vec3>& positions) {
    core::PointCloud cloud;
    for (const glm::vec3& p : positions) {
        core::CloudPoint q;
        q.position = p;
        cloud.points.push_back(q);
    }
    return cloud;
}

// `count` points spread over a cube of side 0.1 m around `centre`: one voxel of 0.25 m
// when the centre sits in the middle of one.
void addBlob(std::vector<glm::vec3>& points, glm::vec3 centre, int count) {
    for (int k = 0; k < count; ++k)
        points.push_back(centre + glm::vec3(0.01f * float(k % 5), 0.01f * float((k / 5) % 5), 0.01f * float(k / 25)));
}

}  // namespace

TEST_CASE("voxel clusters: the radix sort equals a stable sort by key, whatever the parts") {
    std::mt19937_64 random(7);
    // Enough pairs for four parts; keys that differ in a few bytes only, and many ties.
    KeyedPoints keyed(4 * detect::detail::kMinPointsPerPart + 123);
    for (std::size_t k = 0; k < keyed.size(); ++k)
        keyed[k] = {(random() % 5000) << 20 | (random() % 3), std::uint32_t(k)};
    KeyedPoints expected = keyed;
    std::stable_sort(expected.begin(), expected.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t parts : {1u, 2u, 3u, 4u}) {
        CAPTURE(parts);
        KeyedPoints sorted = keyed;
        detect::detail::sortByKey(sorted, parts);
        CHECK(sorted == expected);
    }
}

TEST_CASE("voxel clusters: a sparse voxel between two blobs joins the nearer and chains nothing") {
    detect::SegmentOptions o;  // voxel 0.25 m, tolerance 0.5 m
    std::vector<glm::vec3> points;
    addBlob(points, {0.1f, 0.1f, 0.1f}, 10);   // voxel (0, 0, 0), dense
    addBlob(points, {0.85f, 0.1f, 0.1f}, 10);  // voxel (3, 0, 0): centroids 0.75 m apart, beyond reach
    points.push_back({0.38f, 0.12f, 0.12f});   // voxel (1, 0, 0), one point: within reach of both,
                                               // nearer the first
    const core::PointCloud cloud = cloudOf(points);
    std::vector<std::uint32_t> idx(points.size());
    for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = std::uint32_t(k);
    std::size_t voxels = 0;
    const auto groups = detect::detail::clusterPoints(cloud, idx, glm::dvec3(0.0), o, 3, 1, &voxels);
    CHECK(voxels == 3);
    REQUIRE(groups.size() == 2);
    std::vector<std::uint32_t> first(10), second(10);
    for (std::uint32_t k = 0; k < 10; ++k) first[k] = k, second[k] = 10 + k;
    first.push_back(20);
    CHECK(groups[0] == first);
    CHECK(groups[1] == second);

    // With a bar of one point every voxel is dense, and the single point chains the blobs.
    const auto chained = detect::detail::clusterPoints(cloud, idx, glm::dvec3(0.0), o, 1, 1);
    REQUIRE(chained.size() == 1);
    CHECK(chained[0] == idx);
}

TEST_CASE("voxel clusters: a point past the key's range is refused, naming the voxel option") {
    detect::SegmentOptions o;
    o.voxel_m = 0.05;
    const core::PointCloud cloud = cloudOf({{0.0f, 0.0f, 0.0f}, {60000.0f, 0.0f, 0.0f}});
    const std::vector<std::uint32_t> idx{0, 1};
    CHECK(test_support::errorOf([&] { detect::detail::clusterPoints(cloud, idx, glm::dvec3(0.0), o, 1, 1); }) ==
          "detect: the cloud is too wide for --segment-voxel-m 0.050000 (at most 2^20 voxels across); allowed a "
          "larger voxel");
}
