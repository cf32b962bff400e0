// io/src/copc/copc_parse.hpp (internal): what the COPC validator (copc_check.cpp) and the
// node reader (copc_reader.cpp) share: the layout of a COPC file read and checked without
// decoding any point (the LAS header, the VLRs, the info VLR, the LASzip VLR, the EVLRs,
// every hierarchy page and the variable chunk table), and one node's chunk wrapped as a
// small LAZ file of its own that the LAS reader (or LASzip) decodes.
#pragma once
#include <io/copc.hpp>

#include "../cloud_decode.hpp"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace io::detail {

/// One chunk of the chunk table: where it starts (from the first chunk's place and the
/// sizes before it), its bytes and points.
struct CopcChunk {
    std::uint64_t offset = 0;
    std::uint64_t bytes = 0;
    std::uint64_t points = 0;
};

/// What a COPC file declares, as far as it could be read.
struct CopcLayout {
    std::uint64_t file_size = 0;
    std::string header;  // the first 375 bytes (shorter only when parseCopc returned false)
    unsigned format = 0;
    std::size_t record = 0;
    std::uint64_t data_at = 0;
    std::uint64_t count = 0;  // the 64-bit point count
    std::uint32_t legacy_count = 0;
    std::array<std::uint64_t, 15> by_return{};
    std::array<std::uint32_t, 5> legacy_by_return{};
    glm::dvec3 scale{1.0}, offset{0.0}, min{0.0}, max{0.0};
    bool info_found = false;
    CopcInfo info;
    std::string laszip_vlr;  // the VLR's header and payload, as found
    std::string extra_vlr;   // the extra bytes VLR's header and payload, or empty
    bool table_found = false;
    std::uint64_t table_at = 0;                // the chunk table's place (the chunks end there)
    std::vector<CopcChunk> chunks;             // decoded from the table
    std::vector<CopcNode> nodes;               // every entry with points, in key order
    std::vector<CopcKey> empty_nodes;          // entries with no points
    std::uint64_t hier_at = 0, hier_size = 0;  // the hierarchy record's bytes
    std::vector<CopcPage> pages;               // by page: the root page's child pages, not read
    std::uint64_t page_entries_max = 0;        // by page: a page of more entries is refused (0: no bound)
    std::string page_bound_source;             // what sets page_entries_max, named in the refusal
};

/// Reads the layout of the COPC file in `source` within bounded memory (the hierarchy's
/// entries and the chunk table are the only things held, each bounded by the file's size),
/// appending one finding per broken rule of the header, the VLRs and EVLRs, the info VLR,
/// the hierarchy and the chunk table (docs/formats.md lists the rule names). Returns false
/// when the file is too far from a COPC file for its nodes to be read at all. By page, the
/// chunk table is not decoded and only the root hierarchy page is read: nodes and
/// empty_nodes are its entries, pages its child pages.
bool parseCopc(ByteSource& source, CopcLayout& layout, std::vector<CopcFinding>& findings,
               CopcHierarchy mode = CopcHierarchy::whole);

/// Reads one child page of a layout parseCopc read by page (`page` one of its pages or of
/// an earlier page's), with the rules of a page and its entries. Returns false when the
/// page or one of its entries cannot be used.
bool parseCopcPage(ByteSource& source, const CopcLayout& layout, const CopcPage& page, CopcPageEntries& entries,
                   std::vector<CopcFinding>& findings);

/// The bounds the file's points are framed by: the header's, unless they are not finite
/// or lie more than kFrameSlack outside the info VLR's cube (zeros or stale values that a
/// writer left), when the cube's are taken instead (a usable cube is where every node's
/// points lie). The reader's origin and every node's come from their middle.
void frameBounds(const CopcLayout& layout, glm::dvec3& min, glm::dvec3& max);
/// How far (in the file's units) the header's bounds may lie outside the cube: the LAS
/// reader's slack for a first point outside the bounds, so that the nodes' frames agree.
inline constexpr double kFrameSlack = 1000.0;

/// A LAZ file of one node alone: the file's header (point count, offsets and EVLRs
/// rewritten, the bounds frameBounds'), its LASzip VLR (a fixed chunk size of the node's count) and extra bytes
/// VLR, the node's chunk bytes and a one-chunk table. `node` must be one of layout.nodes
/// and lie inside the file (parseCopc checked both).
std::string nodeLaz(ByteSource& source, const CopcLayout& layout, const CopcNode& node);

/// "level-x-y-z", as COPC and EPT name nodes.
std::string keyName(const CopcKey& key);

/// Whether the info VLR's cube can be computed with: a finite halfsize > 0, and centre +-
/// halfsize within the world coordinates (|c| + halfsize <= core::kMaxWorldCoordinate_m on
/// each axis), so that every node's cube is finite.
bool cubeUsable(const CopcInfo& info);

/// The node's cube in world coordinates: min and max corners (finite when cubeUsable).
void nodeCube(const CopcInfo& info, const CopcKey& key, glm::dvec3& lo, glm::dvec3& hi);

}  // namespace io::detail
