// viewer/cloud_feed.hpp: a point cloud that arrives in chunks while the viewer already runs.
//
// A producer (a loader thread reading a file, or code handing over a cloud made in memory)
// appends chunks; the viewer takes what has arrived each frame and uploads a bounded amount
// to the GPU, so the first points appear before the whole file is read (issue 4).
#pragma once
#include <engine/point_cloud.hpp>

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

/// Thread-safe chunk queue between one producer and the viewer.
class CloudFeed {
public:
    CloudFeed() = default;
    ~CloudFeed();
    CloudFeed(const CloudFeed&) = delete;
    CloudFeed& operator=(const CloudFeed&) = delete;

    /// Producer side. setOrigin must come before the first append (default origin 0).
    void setOrigin(const glm::dvec3& origin);
    void setFields(const engine::CloudFields& fields);
    void append(std::vector<engine::CloudPoint> chunk);
    /// Marks the end of the stream; `error` non-empty means the producer failed with it.
    void finish(std::string error = {});

    /// Viewer side: moves out every chunk that arrived since the last call.
    std::vector<std::vector<engine::CloudPoint>> take();
    glm::dvec3 origin() const;
    engine::CloudFields fields() const;
    bool finished() const { return finished_.load(); }
    /// The producer's error, if it failed (valid once finished()).
    std::string error() const;
    /// Points appended so far (all chunks, taken or not).
    std::size_t pointsArrived() const { return arrived_.load(); }

    /// Starts a thread that reads `path` (PCD or PLY, via engine::readCloud) and feeds it
    /// in chunks of `chunk_points`. The thread is joined by the destructor.
    void startFileLoader(std::filesystem::path path, std::size_t chunk_points = 262144);
    /// Feeds an in-memory cloud in chunks (no thread; the viewer still uploads gradually).
    void feedCloud(engine::PointCloud cloud, std::size_t chunk_points = 262144);

private:
    mutable std::mutex mutex_;
    glm::dvec3 origin_{0.0};
    engine::CloudFields fields_;
    std::vector<std::vector<engine::CloudPoint>> pending_;
    std::string error_;
    std::atomic<bool> finished_{false};
    std::atomic<std::size_t> arrived_{0};
    std::thread loader_;
};

}  // namespace viewer
