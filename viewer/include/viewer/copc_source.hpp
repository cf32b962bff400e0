// viewer/copc_source.hpp: a COPC file (io/copc.hpp) as a point source, node by node.
//
// The nodes are the file's octree: every key of the hierarchy (and the keys above them),
// its bounds the key's cube, its point count the hierarchy's, so the whole tree is known
// when the file opens and no point is decoded until a node is wanted. Each frame the loop
// hands select() the last frame's view; the nodes it picks (node_selection.hpp) within
// the point budget, the cache and the renderer's GPU arena are queued for one worker thread that decodes them
// (CopcReader::readNode) and builds their LOD cells (lod.hpp); poll() makes the decoded
// ones resident on the frame thread. Resident nodes live in a RAM cache bounded by
// `cache_bytes`: when room is needed, the least recently wanted nodes that the last
// selection did not want are evicted. A frame never waits for the worker: what is resident
// stays drawn (coarse nodes until their children arrive). A node whose chunk does not
// decode is skipped for good with one warning line, and its children are still read.
#pragma once
#include <viewer/point_source.hpp>

#include <cstddef>
#include <filesystem>
#include <memory>

namespace viewer {

struct CopcSourceOptions {
    std::size_t cache_bytes = std::size_t(512) << 20;  // resident node points at most
    bool quiet = false;                                // no warning lines
};

class CopcSource final : public PointSource {
  public:
    /// Opens `file` (io::CopcReader: header, info and the whole hierarchy) and starts the
    /// worker. Throws core::Error naming the file and what is wrong.
    CopcSource(const std::filesystem::path& file, const CopcSourceOptions& options);
    ~CopcSource() override;
    CopcSource(const CopcSource&) = delete;
    CopcSource& operator=(const CopcSource&) = delete;

    std::size_t poll() override;
    std::span<PointNode* const> roots() const override;
    glm::dvec3 origin() const override;
    /// The file's fields as the first decoded node gives them (the defaults until then).
    core::CloudFields fields() const override;
    /// Every node is known from the start; this turns true once the first selection's
    /// nodes have all been decoded (or skipped), the "loaded" mark of the frame loop.
    bool finished() const override;
    std::string error() const override { return {}; }
    std::size_t pointsArrived() const override;
    void select(const SourceView& view) override;
    std::optional<SourceStats> stats() const override;
    /// The last selection's nodes, most important first.
    std::span<PointNode* const> wanted() const override;

    /// Nodes in the tree (with and without points).
    std::size_t nodeCount() const;
    /// Points of every node with points.
    std::size_t totalPoints() const;

    struct Impl;  // copc_source.cpp's (its nodes point back to it)

  private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace viewer
