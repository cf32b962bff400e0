// tests/viewer/points/point_source_test.cpp: the streamed cloud as a point source: each chunk a
// leaf with its bounds and count, resident on arrival, evicted on request; the point
// renderer following the source's residency (headless, EGL); and the frame loop's stream
// judging the cloud whole only once it took the chunks that came before the stream's end.
#include <viewer/cloud_feed.hpp>
#include <viewer/cloud_feed_source.hpp>

#include "points/point_renderer.hpp"
#include "points/source_stream.hpp"

#include <render/egl_context.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>
#include <utility>

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

// A stream whose chunk arrives, and whose end comes, just after a poll took what had
// arrived: what the loader's thread can do between a frame's poll and its look at finished().
class EndAfterPoll final : public PointSource {
  public:
    explicit EndAfterPoll(core::PointCloud cloud) : cloud_(std::move(cloud)) {}
    std::size_t poll() override {
        const std::size_t added = source_.poll();
        if (!feed_.finished()) feed_.feedCloud(std::move(cloud_));  // appends, then ends the feed
        return added;
    }
    std::span<PointNode* const> roots() const override { return source_.roots(); }
    glm::dvec3 origin() const override { return source_.origin(); }
    core::CloudFields fields() const override { return source_.fields(); }
    bool finished() const override { return source_.finished(); }
    std::string error() const override { return source_.error(); }
    std::size_t pointsArrived() const override { return source_.pointsArrived(); }

  private:
    CloudFeed feed_;
    CloudFeedSource source_{feed_};
    core::PointCloud cloud_;
};

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
    CHECK_FALSE(source.originFinal());  // a stream's frame is final at its end
    feed.feedCloud(line(350), 100);
    REQUIRE(source.finished());
    CHECK(source.originFinal());
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

TEST_CASE("a stream is whole and indexed for picking only once a poll after its end took every chunk") {
    render::EglContext context;
    RunLog log;
    EndAfterPoll source(line(300));
    SourceStream stream;
    stream.start(ViewerOptions{}, log);
    stream.reset(source);
    stream.update(0, log);  // took nothing; the chunk and the end came after the poll
    CHECK(stream.loadedSinceFrame() == -1);
    CHECK(stream.picks() == nullptr);
    stream.update(1, log);  // took the chunk and uploaded it
    CHECK(stream.loadedSinceFrame() == 1);
    while (!stream.picks()) stream.update(2, log);  // the index is built on a worker thread
    CHECK(stream.picks()->size() == 300);
}
