// viewer/copc_source.hpp: a COPC file (io/copc.hpp) as a point source, node by node.
//
// The nodes are the file's octree: every key of the hierarchy that holds points or a child
// page (and the keys above them), its bounds the key's cube, its point count the
// hierarchy's. Opening the file reads the root hierarchy page alone (its levels; the
// writer's pages hold four), so a file of any size opens in a few kilobytes: a node whose
// subtree sits in a child page is unexplored until a selection reaches it, and its page
// is then read by a worker before any node, the subtree joining the tree on the frame
// thread. No point is decoded until a node is
// wanted. Each frame the loop hands select() the last frame's view; the nodes it picks
// (node_selection.hpp) within the point budget, the cache and the renderer's GPU arena are
// queued for the worker threads (CopcSourceOptions::workers), which decode them
// (CopcReader::readNodeEntry) and build their LOD cells (lod.hpp); poll() makes the pages
// and nodes read part of the tree on the frame thread. Resident nodes live in a RAM cache
// bounded by `cache_bytes`: when room is needed, the least recently wanted nodes that the
// last selection did not want are evicted. A frame never waits for the workers: what is
// resident stays drawn (coarse nodes until their children arrive). A node whose chunk
// does not decode is skipped for good with one warning line, and its children are still
// read; a page that does not read leaves its subtree out, with one warning line.
//
// The hierarchy is bounded as the cache is (`hierarchy_bytes`, the viewer's --memory-mb):
// a quarter of it for the pages being read at once (a larger page is refused by the
// reader), the rest for the tree, counted before a page's nodes are made. An entry with no
// points makes no node, and keys below the level whose cells are one coordinate step
// wide (they cannot separate points) are refused. A root page that does not fit refuses
// the file in one line; a child page that does not fit is left out like one that does
// not read.
#pragma once
#include <viewer/point_source.hpp>

#include <cstddef>
#include <filesystem>
#include <memory>

namespace viewer {

/// Workers by default: half the cores, 1 to 4 (one on a 2-core machine, the other core
/// left to the frame loop).
std::size_t defaultCopcWorkers();

struct CopcSourceOptions {
    std::size_t cache_bytes = std::size_t(512) << 20;  // resident node points at most
    /// The hierarchy at most: the tree's nodes and the pages being read (--memory-mb).
    std::size_t hierarchy_bytes = std::size_t(512) << 20;
    bool quiet = false;                          // no warning lines
    std::size_t workers = defaultCopcWorkers();  // threads reading pages and decoding nodes
};

class CopcSource final : public PointSource {
  public:
    /// Opens `file` (io::CopcReader: header, info and the root hierarchy page) and starts
    /// the workers. Throws core::Error naming the file and what is wrong, among it a root
    /// page whose entries or nodes do not fit `hierarchy_bytes` (the count and the bound).
    CopcSource(const std::filesystem::path& file, const CopcSourceOptions& options);
    ~CopcSource() override;
    CopcSource(const CopcSource&) = delete;
    CopcSource& operator=(const CopcSource&) = delete;

    std::size_t poll() override;
    std::span<PointNode* const> roots() const override;
    glm::dvec3 origin() const override;
    /// The header's offsets, read at open: final from the start.
    bool originFinal() const override { return true; }
    /// The file's fields as the first decoded node gives them (the defaults until then); a
    /// file from elsewhere whose colour values decoded so far are all 0 has no colours.
    core::CloudFields fields() const override;
    /// Whether the file is another producer's, as the first decoded node shows it.
    bool fromElsewhere() const override;
    /// True once a selection's pages and nodes have all been read (or skipped), the
    /// "loaded" mark of the frame loop.
    bool finished() const override;
    std::string error() const override { return {}; }
    std::size_t pointsArrived() const override;
    void select(const SourceView& view) override;
    std::optional<SourceStats> stats() const override;
    /// The last selection's nodes, most important first.
    std::span<PointNode* const> wanted() const override;

    /// Nodes in the tree as known so far (with and without points; more as pages arrive).
    std::size_t nodeCount() const;
    /// The points of the file (its header's count).
    std::size_t totalPoints() const;
    /// Unexplored nodes the last selection reached: while not 0, the tree below what is
    /// drawn is still being read.
    std::size_t pagesWanted() const;

    struct Impl;  // copc_source.cpp's (its nodes point back to it)

  private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace viewer
