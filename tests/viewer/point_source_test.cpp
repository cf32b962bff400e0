// tests/viewer/point_source_test.cpp: the streamed cloud as a point source: each chunk a
// leaf with its bounds and count, resident on arrival, evicted on request; and the point
// renderer following the source's residency (headless, EGL).
#include <viewer/cloud_feed.hpp>
#include <viewer/point_source.hpp>

#include "point_renderer.hpp"

#include <render/egl_context.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>

using namespace viewer;

namespace {

core::PointCloud line(std::size_t n) {  // points 1 m apart along x, rising in z
    core::PointCloud cloud;
    cloud.origin = glm::dvec3(1000.0, 2000.0, 30.0);
    for (std::size_t i = 0; i < n; ++i) {
        core::CloudPoint p;
        p.position = glm::vec3(float(i), 0.5f, float(i % 10));
        cloud.points.push_back(p);
    }
    return cloud;
}

std::size_t residentCount(const PointSource& source) {
    const auto nodes = allNodes(source);
    return static_cast<std::size_t>(
        std::count_if(nodes.begin(), nodes.end(), [](const PointNode* n) { return n->resident(); }));
}

}  // namespace

TEST_CASE("a streamed cloud's chunks are leaves of the point source, resident on arrival") {
    CloudFeed feed;
    CloudFeedSource source(feed);
    CHECK(source.poll() == 0);  // nothing arrived yet
    CHECK(source.roots().empty());
    feed.feedCloud(line(350), 100);
    REQUIRE(source.finished());
    CHECK(source.error().empty());
    CHECK(source.origin() == glm::dvec3(1000.0, 2000.0, 30.0));
    CHECK(source.pointsArrived() == 350);
    REQUIRE(source.poll() == 4);
    CHECK(source.poll() == 0);  // taken once
    const auto nodes = allNodes(source);
    REQUIRE(nodes.size() == 4);
    const std::size_t counts[] = {100, 100, 100, 50};
    for (std::size_t i = 0; i < 4; ++i) {
        const PointNode& node = *nodes[i];
        CHECK(node.children().empty());
        CHECK(node.pointCount() == counts[i]);
        REQUIRE(node.resident());
        CHECK(node.points()->points.size() == counts[i]);
        // Bounds: the chunk's x range (its points, reordered into LOD cells, are the same ones).
        CHECK(node.bounds().lo.x == doctest::Approx(100.0 * i));
        CHECK(node.bounds().hi.x == doctest::Approx(100.0 * i + counts[i] - 1));
        std::size_t in_cells = 0;
        for (const LodCell& c : node.points()->cells) in_cells += c.count;
        CHECK(in_cells == counts[i]);
    }
    CHECK(residentCount(source) == 4);

    // Evicting drops the points but keeps what is known of the node; a stream cannot be
    // read twice, so a request does not bring them back.
    auto kept = nodes[1]->points();  // a holder (an index being built) keeps its copy alive
    nodes[1]->evict();
    CHECK_FALSE(nodes[1]->resident());
    CHECK(nodes[1]->points() == nullptr);
    CHECK(nodes[1]->pointCount() == 100);
    CHECK(nodes[1]->bounds().lo.x == doctest::Approx(100.0));
    CHECK(kept->points.size() == 100);
    nodes[1]->request();
    CHECK_FALSE(nodes[1]->resident());
    CHECK(residentCount(source) == 3);
}

TEST_CASE("the point renderer draws what the source has resident and drops what it evicts") {
    render::EglContext context;
    PointRenderer renderer;
    CloudFeed feed;
    feed.feedCloud(line(1000), 400);
    CloudFeedSource source(feed);
    REQUIRE(source.poll() == 3);
    // Upload in steps of 300 points per frame: 1000 points take four frames.
    CHECK(renderer.stream(source, 300) == 300);
    CHECK(renderer.uploadedPoints() == 300);
    CHECK(renderer.pendingPoints() == 700);
    while (renderer.pendingPoints() > 0) renderer.stream(source, 300);
    CHECK(renderer.uploadedPoints() == 1000);
    const std::size_t cells = renderer.cellCount();
    CHECK(cells >= 3);
    // The middle chunk is evicted: its points and its cells leave the GPU.
    const auto nodes = allNodes(source);
    const std::size_t middle_cells = nodes[1]->points()->cells.size();
    nodes[1]->evict();
    CHECK(renderer.stream(source, 300) == 0);
    CHECK(renderer.uploadedPoints() == 600);
    CHECK(renderer.cellCount() == cells - middle_cells);
    // Evicted while still waiting for upload: nothing of it is uploaded afterwards.
    CloudFeed feed2;
    feed2.feedCloud(line(500), 250);
    CloudFeedSource source2(feed2);
    source2.poll();
    PointRenderer second;
    CHECK(second.stream(source2, 100) == 100);
    allNodes(source2)[0]->evict();
    second.stream(source2, 0);
    CHECK(second.uploadedPoints() == 0);
    CHECK(second.pendingPoints() == 250);
    while (second.pendingPoints() > 0) second.stream(source2, 100);
    CHECK(second.uploadedPoints() == 250);
}
