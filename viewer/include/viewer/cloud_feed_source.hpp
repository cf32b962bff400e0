// viewer/cloud_feed_source.hpp: a streamed file or in-memory cloud (cloud_feed.hpp) as a
// point source (point_source.hpp): each chunk a leaf under no parent, resident from its
// arrival (the LOD order of lod.hpp already built).
#pragma once
#include <viewer/point_source.hpp>

#include <memory>
#include <vector>

namespace viewer {

class CloudFeed;

/// A CloudFeed seen as a point source: each chunk becomes a leaf when poll() takes it
/// (its LOD order built there unless the feed built it on the producer's thread). A
/// stream cannot be read twice: an evicted chunk stays known (bounds, count) but a later
/// request() cannot bring its points back.
class CloudFeedSource final : public PointSource {
  public:
    explicit CloudFeedSource(CloudFeed& feed) : feed_(&feed) {}
    ~CloudFeedSource() override;
    std::size_t poll() override;
    std::span<PointNode* const> roots() const override { return roots_; }
    glm::dvec3 origin() const override;
    core::CloudFields fields() const override;
    bool fromElsewhere() const override;
    bool finished() const override;
    std::string error() const override;
    std::size_t pointsArrived() const override;

  private:
    CloudFeed* feed_;
    std::vector<std::unique_ptr<PointNode>> nodes_;
    std::vector<PointNode*> roots_;
};

}  // namespace viewer
