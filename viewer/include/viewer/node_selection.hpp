// viewer/node_selection.hpp: which nodes of a point source's tree a frame wants, chosen by
// projected size against a point budget, coarse to fine, in one traversal for both eyes
// (the union of their frusta), as Potree's and CLOD's renderers choose octree nodes.
//
// The traversal starts at the roots and always takes the node of largest screen
// importance (lod.hpp's screenImportance, seen from the eyes' mean position) among those
// whose parent was taken; a node that does not fit the remaining budget is passed over
// with its whole subtree. So parents come before their children, nearer and larger nodes
// before farther and smaller ones, and the total never exceeds the budget (points, RAM
// bytes and GPU bytes: what is drawn is what is on the GPU). Only the taken nodes and
// their children are looked at, never the rest of the tree, so a frame's cost follows
// what it draws, not the size of the file (which nodes leave the cache is the source's
// business: it knows what it holds). Pure maths on the nodes' bounds and counts: no GL,
// no I/O.
#pragma once
#include <viewer/point_source.hpp>

#include <render/orbit_camera.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace viewer {

struct SelectionBudget {
    std::size_t points = 0;     // points of the wanted nodes at most; 0 = unlimited
    std::size_t bytes = 0;      // nodeBytes() of the wanted nodes at most (the RAM cache); 0 = unlimited
    std::size_t gpu_bytes = 0;  // gpuBytes() of the wanted nodes at most (the GPU arena); 0 = unlimited
};

struct NodeSelection {
    std::vector<PointNode*> wanted;      // in traversal order: parents first, most important first
    std::size_t points = 0;              // of the wanted nodes
    std::size_t focus_points = 0;        // of the wanted nodes touching the focus
    std::size_t bytes = 0;               // nodeBytes() of the wanted nodes
    std::size_t gpu_bytes = 0;           // gpuBytes() of the wanted nodes
    std::vector<PointNode*> unexplored;  // reached and unexplored(): the source reads them next
};

/// Memory a node's points take once resident (NodePoints: the points and at most as many
/// LOD cells as buildLodOrder makes for `point_count` points), an upper bound known before
/// the points are read.
std::size_t nodeBytes(std::size_t point_count);

/// GPU memory a node's points take once uploaded: exactly what render::PointChunks
/// allocates for them (one render::GpuPoint each).
std::size_t gpuBytes(std::size_t point_count);

/// Picks the nodes under `roots` seen by any of `frusta` (all of them when `frusta` is
/// empty), by importance seen from `eye_local`, within `budget`. Nodes with no points
/// (empty or unreadable) cost nothing and are walked through to their children; an
/// unexplored node reached that way is listed, most important first, for its source to read.
/// Nodes touching `focus` come first, down to the leaves, and the point budget does not
/// bound them (the RAM and GPU bounds do); the other nodes share what they leave of it.
NodeSelection selectNodes(std::span<PointNode* const> roots, std::span<const render::Frustum> frusta,
                          const glm::dvec3& eye_local, const SelectionBudget& budget, const LodFocus& focus = {});

}  // namespace viewer
