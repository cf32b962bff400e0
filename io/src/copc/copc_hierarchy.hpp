// io/src/copc/copc_hierarchy.hpp (internal): the hierarchy pages of a COPC file.
//
// Each page is a run of 32-byte entries: the key (level, x, y, z as int32), the offset
// (uint64) and byte size (int32) of the node's chunk, its point count (int32; 0 for a node
// with no points, -1 for an entry that points to a child page, whose offset and size are
// then the page's). Pages hold kLevelsPerPage levels: the root page the nodes of levels
// 0-3, and one child page per node of level 4, 8, 12, ... holding that node's subtree down
// to 3 levels below it (its entry in the page above is the -1 entry). The pages follow one
// another in key order (level first), the root page first, with no gap.
#pragma once
#include <io/copc.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace io::detail {

inline constexpr int kLevelsPerPage = 4;
inline constexpr std::size_t kHierarchyEntryBytes = 32;

struct HierarchyPages {
    std::string bytes;            // every page, the root page first
    std::uint64_t root_size = 0;  // the root page's bytes
};

/// Lays out the pages of `nodes` (one entry per node, each key once, their ancestors
/// present; point_count 0 allowed) for pages that start at file offset `at`.
HierarchyPages encodeHierarchy(std::vector<CopcNode> nodes, std::uint64_t at);

}  // namespace io::detail
