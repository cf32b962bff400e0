// viewer/point_source.hpp: where the viewer's points come from, as a tree of nodes.
//
// A node knows its bounds and point count before its points are in memory, has children
// (none for a leaf), and loads or drops its points on request() / evict(), as the nodes
// of Potree's octree and of a COPC file's hierarchy do. The frame loop polls the source
// once per frame; the renderer draws the points of resident nodes and the pointer picks
// per node, so a new kind of source (an octree file read node by node) adds a class here
// and changes neither the loop nor the renderer.
//
// A source that chooses which nodes to hold (CopcSource, copc_source.hpp) is told the last
// frame's view through select(); a stream ignores it.
//
// CloudFeedSource (cloud_feed_source.hpp) is the first one: a streamed file or in-memory
// cloud (cloud_feed.hpp), each chunk a leaf under no parent, resident from its arrival.
#pragma once
#include <core/point_cloud.hpp>
#include <viewer/lod.hpp>

#include <render/orbit_camera.hpp>

#include <glm/vec3.hpp>

#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace viewer {

/// A resident node's points in LOD order and their cells (lod.hpp). Shared, so a worker
/// that indexes them keeps them alive if the node is evicted meanwhile.
struct NodePoints {
    std::vector<core::CloudPoint> points;
    std::vector<LodCell> cells;
};

class PointNode {
  public:
    virtual ~PointNode() = default;
    /// Local-frame bounds of all the node's points (known whether resident or not).
    virtual const core::Bounds& bounds() const = 0;
    virtual std::size_t pointCount() const = 0;
    /// Empty for a leaf.
    virtual std::span<PointNode* const> children() const = 0;
    /// True while the node's subtree is not known yet (a COPC hierarchy page not read):
    /// its point count reads 0 and it has no children until the source reads it, which
    /// it does once a selection reaches the node (NodeSelection::unexplored).
    virtual bool unexplored() const { return false; }
    /// Asks for the points; they may arrive later (resident() turns true). Never throws.
    virtual void request() = 0;
    /// Drops the points from memory (points() becomes null). Never throws.
    virtual void evict() = 0;
    bool resident() const { return points() != nullptr; }
    /// The points while resident, else null.
    virtual std::shared_ptr<const NodePoints> points() const = 0;
};

/// What the last frame drew from: the union of the eyes' frusta (widened by the predicted
/// head motion, motion_prediction.hpp), the eyes' mean position (local frame), the point
/// budget per eye (0 = unlimited) and the GPU arena's bound in bytes (0 = unlimited): what
/// is drawn is what is on the GPU, so a source wants no more than the arena holds. The
/// focus (lod.hpp) is what the operator works on: its nodes come first, whatever the budget.
struct SourceView {
    std::vector<render::Frustum> frusta;
    glm::dvec3 eye_local{0.0};
    std::size_t point_budget = 0;
    std::size_t gpu_bytes = 0;
    LodFocus focus{};
};

/// The memory a source that holds nodes by choice reports (the run log's "source").
struct SourceStats {
    std::string kind;                // "copc"
    std::size_t nodes = 0;           // in the tree
    std::size_t nodes_resident = 0;  // now
    std::size_t nodes_loaded = 0;    // decoded so far
    std::size_t nodes_evicted = 0;   // dropped so far
    std::size_t nodes_failed = 0;    // unreadable, skipped
    std::size_t wanted_points = 0;   // by the last selection
    std::size_t cache_bytes = 0;     // the bound on resident bytes
    std::size_t resident_bytes = 0;  // now
    std::size_t resident_bytes_peak = 0;
    std::size_t hierarchy_bytes = 0;  // held for the tree (its nodes, bounds, counts, links)
    std::size_t pages_read = 0;       // hierarchy pages read so far (the root page included)
    std::size_t pages_unread = 0;     // hierarchy pages known and not read
    std::size_t pages_failed = 0;     // hierarchy pages that did not read (their subtrees skipped)
};

class PointSource {
  public:
    virtual ~PointSource() = default;
    /// Takes what arrived since the last call (the frame loop calls it once per frame).
    /// Returns the number of nodes added. Never throws.
    virtual std::size_t poll() = 0;
    /// The top-level nodes known so far, in arrival order (grows while a source streams).
    virtual std::span<PointNode* const> roots() const = 0;
    /// World coordinates of the local frame the nodes' points are in.
    virtual glm::dvec3 origin() const = 0;
    /// origin() will not change: world positions (candidate boxes, aims) can be placed in
    /// the local frame. A stream knows it at its end; a file with a header at once.
    virtual bool originFinal() const { return finished(); }
    virtual core::CloudFields fields() const = 0;
    /// The points come from another producer's file: their label is their class's (class 2
    /// ground) and their colours are the file's own, not the generator's whitened ground.
    virtual bool fromElsewhere() const { return false; }
    /// Every node is known: the stream ended (or failed, see error()).
    virtual bool finished() const = 0;
    /// The producer's error, if it failed (valid once finished()).
    virtual std::string error() const = 0;
    /// Points that arrived so far, taken by poll() or not.
    virtual std::size_t pointsArrived() const = 0;
    /// Chooses what to hold for `view` (the frame loop calls it before poll()); a source
    /// that holds everything it has ignores it. Never throws.
    virtual void select(const SourceView& view) { (void)view; }
    /// The cache's figures, for a source that has one.
    virtual std::optional<SourceStats> stats() const { return std::nullopt; }
    /// A source that chooses its nodes: the nodes the last select() wanted, most important
    /// first (the order the renderer uploads them in). Empty for a source that holds all.
    virtual std::span<PointNode* const> wanted() const { return {}; }
};

/// Every node under `source`'s roots, parents before their children.
std::vector<PointNode*> allNodes(const PointSource& source);

/// Every node's level: its depth below the roots (a root 0, its children 1, ...), which
/// for a COPC file is the key's level (the hierarchy's keys are filled in above their
/// descendants).
std::map<const PointNode*, int> nodeLevels(const PointSource& source);

}  // namespace viewer
