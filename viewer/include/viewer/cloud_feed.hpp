// viewer/cloud_feed.hpp: a point cloud that arrives in chunks while the viewer already runs.
//
// A producer (a loader thread reading a file, or code handing over a cloud made in memory)
// appends chunks; the viewer takes what has arrived each frame and uploads a bounded amount
// to the GPU, so the first points appear before the whole file is read.
#pragma once
#include <core/point_cloud.hpp>
#include <viewer/lod.hpp>

#include <atomic>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace viewer {

/// One chunk as it arrived; `cells` is filled (and `points` in LOD order) when the feed
/// builds the LOD order on the producer's thread (enableLodOrder), else empty.
struct FeedChunk {
    std::vector<core::CloudPoint> points;
    std::vector<LodCell> cells;
};

/// Thread-safe chunk queue between one producer and the viewer.
class CloudFeed {
  public:
    CloudFeed() = default;
    ~CloudFeed();
    CloudFeed(const CloudFeed&) = delete;
    CloudFeed& operator=(const CloudFeed&) = delete;

    /// From now on, append() puts every chunk in LOD order (buildLodOrder) on the producer's
    /// thread, so the frame loop does not pay for it. Call before the producer starts.
    void enableLodOrder(const LodOptions& options = {});
    /// Producer side. setOrigin must come before the first append (default origin 0).
    void setOrigin(const glm::dvec3& origin);
    /// `from_elsewhere`: the points come from another producer's file (PointSource::fromElsewhere).
    void setFields(const core::CloudFields& fields, bool from_elsewhere = false);
    void append(std::vector<core::CloudPoint> chunk);
    /// Marks the end of the stream; `error` non-empty means the producer failed with it.
    void finish(std::string error = {});

    /// Viewer side: moves out every chunk that arrived since the last call.
    std::vector<FeedChunk> take();
    glm::dvec3 origin() const;
    /// The fields set, except that a file from elsewhere whose colour values read so far
    /// are all 0 has no colours (rgb false): its fields hold nothing to show.
    core::CloudFields fields() const;
    bool fromElsewhere() const;
    bool finished() const { return finished_.load(); }
    /// Blocks until finished() (the loader notifies when it ends).
    void waitFinished() const { finished_.wait(false); }
    /// The producer's error, if it failed (valid once finished()).
    std::string error() const;
    /// Points appended so far (all chunks, taken or not).
    std::size_t pointsArrived() const { return arrived_.load(); }

    /// Reads `path` (PCD, PLY, LAS or LAZ) with io::CloudReader chunk by chunk, appending each
    /// chunk of `chunk_points` as it is decoded, and finishes the feed: with the reader's
    /// error if the file is bad (its header is checked before the first point), or with
    /// "<pcd|ply|las>: <file>: holds no points to show" if no point remains. Non-finite points
    /// are dropped with one warning line on stderr.
    void feedFile(const std::filesystem::path& path, std::size_t chunk_points = 262144);
    /// feedFile on a thread, which the destructor joins.
    void startFileLoader(std::filesystem::path path, std::size_t chunk_points = 262144);
    /// Feeds an in-memory cloud in chunks (no thread; the viewer still uploads gradually).
    /// On a cloud without heights above ground (fields), feedFile and feedCloud put each
    /// point's packed class, intensity and returns in its height_above_ground_m instead
    /// (viewer/src/points/point_attributes.hpp: what the class, intensity and return colours read).
    void feedCloud(core::PointCloud cloud, std::size_t chunk_points = 262144);

  private:
    mutable std::mutex mutex_;
    glm::dvec3 origin_{0.0};
    core::CloudFields fields_;
    bool from_elsewhere_ = false;
    bool colours_zero_ = false;  // a file from elsewhere's colour values read so far are all 0
    std::vector<FeedChunk> pending_;
    bool lod_order_ = false;
    LodOptions lod_options_;
    std::string error_;
    std::atomic<bool> finished_{false};
    std::atomic<std::size_t> arrived_{0};
    std::thread loader_;
};

}  // namespace viewer
