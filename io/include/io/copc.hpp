// io/copc.hpp: COPC 1.0 (Cloud Optimized Point Cloud) files: the octree they describe,
// node-by-node reading, and the validator.
//
// A COPC file is a LAZ 1.4 file (point format 6, 7 or 8) whose variable-size LAZ chunks are
// the nodes of an octree. The 160-byte `info` VLR (user "copc", record 1) comes first, right
// after the 375-byte header, and gives the root cube (centre and half size), the root's point
// spacing, the root hierarchy page and the GPS time range. The hierarchy (an EVLR, user
// "copc", record 1000) is a set of pages of 32-byte entries: a node key (level, x, y, z), the
// offset and byte size of its chunk, and its point count (-1 for an entry that points to a
// child page, 0 for a node with no points).
#pragma once
#include <core/point_cloud.hpp>
#include <io/cloud_reader.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace io {

/// A node of the octree: level d (0 the root) and its cell (x, y, z), each in [0, 2^d).
struct CopcKey {
    std::int32_t level = 0;
    std::int32_t x = 0;
    std::int32_t y = 0;
    std::int32_t z = 0;
    friend bool operator==(const CopcKey&, const CopcKey&) = default;
    friend auto operator<=>(const CopcKey&, const CopcKey&) = default;
};

/// The info VLR's fields (its 88 reserved bytes are zero).
struct CopcInfo {
    std::array<double, 3> center_m{};
    double halfsize_m = 0.0;
    double spacing_m = 0.0;
    std::uint64_t root_hier_offset = 0;
    std::uint64_t root_hier_size = 0;
    double gpstime_minimum = 0.0;
    double gpstime_maximum = 0.0;
};

/// A node that holds points: where its chunk is and how many points it has.
struct CopcNode {
    CopcKey key;
    std::uint64_t offset = 0;      // of its LAZ chunk in the file
    std::int32_t byte_size = 0;    // of its LAZ chunk
    std::int32_t point_count = 0;  // > 0
};

/// A hierarchy page: the key whose subtree it lists, and its bytes in the file.
struct CopcPage {
    CopcKey key;
    std::uint64_t offset = 0;
    std::uint64_t bytes = 0;
};

/// The entries of one hierarchy page.
struct CopcPageEntries {
    std::vector<CopcNode> nodes;       // with points, in key order
    std::vector<CopcKey> empty_nodes;  // with no points, in key order
    std::vector<CopcPage> pages;       // child pages (entries of point count -1)
};

/// How much of the hierarchy a reader reads when it opens a file: all of it, or the root
/// page alone, the child pages then read one by one as a client needs them.
enum class CopcHierarchy { whole, by_page };

/// One broken rule of a COPC file: a short rule name ("info-vlr", "hierarchy", "bounds", ...)
/// and one line saying what is wrong, naming the field, node or point.
struct CopcFinding {
    std::string rule;
    std::string message;
};

/// Applies the COPC rules to `file` and returns every one it breaks (empty: a valid COPC
/// file). Reads within bounded memory; a file that is not even a LAS file gives one finding.
std::vector<CopcFinding> checkCopc(const std::filesystem::path& file);

/// True when `file` is a regular file that starts as a COPC file does: a LAS header whose
/// first VLR (right after the 375-byte LAS 1.4 header) is COPC's info record (user "copc",
/// record 1). Reads 395 bytes at most and never throws; a shorter, unreadable or special
/// file is not COPC (its reader then says what is wrong). This is the one place that tells
/// a COPC file from another cloud file.
bool isCopcFile(const std::filesystem::path& file);

/// Node-by-node access to a COPC file: its info, its nodes with points, and one node's
/// points decoded on demand (the LAZ chunk of that node, reached through the variable chunk
/// table), so that a reader never holds more than the nodes it asked for. By page, the
/// hierarchy too is read a page at a time, so that opening a file of any size reads a
/// few kilobytes of it. readPage, readNode and readNodeEntry may be called from several
/// threads at once (the file's bytes are read one call at a time, decoded in parallel).
class CopcReader {
  public:
    /// Opens and validates the header, the info VLR and the hierarchy (all of it, or by
    /// page the root page); throws core::Error naming the file and what is wrong. By page,
    /// `page_entries_max` (0: no bound) bounds what one page read holds: a page of more
    /// entries is refused (the root page here, a child page by readPage), naming its
    /// entries, the bound and `page_bound_source`: what sets the bound, in the words of
    /// the caller's user (e.g. the option that sizes it).
    explicit CopcReader(const std::filesystem::path& file, CopcHierarchy hierarchy = CopcHierarchy::whole,
                        std::uint64_t page_entries_max = 0,
                        std::string page_bound_source = "this reader's memory bound");
    ~CopcReader();
    CopcReader(const CopcReader&) = delete;
    CopcReader& operator=(const CopcReader&) = delete;

    const CopcInfo& info() const;
    /// Every node with points, in key order (by page: those of the root page).
    const std::vector<CopcNode>& nodes() const;
    /// By page: the root page's entries with no points and its child pages (whole: the
    /// empty nodes of every page, no child page).
    const std::vector<CopcKey>& emptyNodes() const;
    const std::vector<CopcPage>& pages() const;
    /// Reads and checks one child page (one of pages() or of an earlier readPage's); throws
    /// core::Error naming the file, the page and what is wrong.
    CopcPageEntries readPage(const CopcPage& page) const;
    /// The header's scale factors: the step of the coordinates, metres.
    glm::dvec3 scale() const;
    /// The points in the file's header (known without reading a hierarchy page).
    std::uint64_t pointCount() const;
    /// The local frame readNode's points come in (the LAS reader's: whole metres near the
    /// middle of the header's bounds, or of the info VLR's cube when the bounds lie far
    /// outside it), known without decoding a node.
    glm::dvec3 origin() const;
    /// The points of one node, as the LAS reader gives them (world coordinates through the
    /// cloud's origin, roles from the classes, view from the point source id).
    core::PointCloud readNode(const CopcKey& key) const;
    /// The same for a node entry of nodes() or of a page readPage returned (by page, the
    /// nodes below the root page are reached that way).
    core::PointCloud readNodeEntry(const CopcNode& node) const;
    /// The same; with SideRecords::Keep, a file made by another producer gives each point's
    /// side record too (cloud.foreign, as CloudReader gives them).
    core::PointCloud readNodeEntry(const CopcNode& node, SideRecords side) const;
    /// The same, decoding what `fields` asks for (CloudReader's PointFields).
    core::PointCloud readNodeEntry(const CopcNode& node, SideRecords side, PointFields fields) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace io
