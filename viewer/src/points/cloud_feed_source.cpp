// viewer/src/points/cloud_feed_source.cpp: the streamed cloud as a point source, a leaf per
// chunk.
#include <viewer/cloud_feed.hpp>
#include <viewer/cloud_feed_source.hpp>

#include <utility>

namespace viewer {

namespace {

/// One chunk of the stream: a leaf, resident from its arrival until evicted.
class FeedLeaf final : public PointNode {
  public:
    explicit FeedLeaf(std::shared_ptr<const NodePoints> points) : points_(std::move(points)) {
        count_ = points_->points.size();
        for (const LodCell& c : points_->cells) bounds_.extend(c.bounds);
    }
    const core::Bounds& bounds() const override { return bounds_; }
    std::size_t pointCount() const override { return count_; }
    std::span<PointNode* const> children() const override { return {}; }
    void request() override {}  // the stream has passed: nothing to read again
    void evict() override { points_.reset(); }
    std::shared_ptr<const NodePoints> points() const override { return points_; }

  private:
    std::shared_ptr<const NodePoints> points_;
    core::Bounds bounds_;
    std::size_t count_ = 0;
};

}  // namespace

CloudFeedSource::~CloudFeedSource() = default;

std::size_t CloudFeedSource::poll() {
    std::size_t added = 0;
    for (FeedChunk& chunk : feed_->take()) {
        if (chunk.points.empty()) continue;
        auto points = std::make_shared<NodePoints>();
        // LOD order once per chunk, at arrival: spatial cells, each shuffled (lod.hpp); done
        // by the producer's thread when the feed has it enabled, else here.
        points->cells = chunk.cells.empty() ? buildLodOrder(chunk.points) : std::move(chunk.cells);
        points->points = std::move(chunk.points);
        nodes_.push_back(std::make_unique<FeedLeaf>(std::move(points)));
        roots_.push_back(nodes_.back().get());
        ++added;
    }
    return added;
}

glm::dvec3 CloudFeedSource::origin() const { return feed_->origin(); }
core::CloudFields CloudFeedSource::fields() const { return feed_->fields(); }
bool CloudFeedSource::fromElsewhere() const { return feed_->fromElsewhere(); }
bool CloudFeedSource::finished() const { return feed_->finished(); }
std::string CloudFeedSource::error() const { return feed_->error(); }
std::size_t CloudFeedSource::pointsArrived() const { return feed_->pointsArrived(); }

}  // namespace viewer
