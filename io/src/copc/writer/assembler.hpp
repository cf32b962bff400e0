// io/src/copc/writer/assembler.hpp (internal): the COPC file around its chunks.
//
// The layout: the 375-byte LAS 1.4 header; the `copc` info VLR (record 1, 160 bytes) at
// offset 375; LASzip's VLRs (the LASzip VLR with chunk size UINT32_MAX, the extra bytes
// VLR when there are extra bytes); the 8-byte position of the chunk table; one LAZ chunk
// per node with points, in the octree's depth-first order; the variable chunk table
// (point and byte counts, las/laz_chunk_table.cpp); the `copc` hierarchy EVLR (record
// 1000) holding every hierarchy page (copc_hierarchy.hpp), the root page first. The
// header and the VLRs LASzip makes come from a file LASzip writes with no points; each
// node's chunk is cut out of a file LASzip writes for that node alone.
#pragma once
#include "../copc_octree.hpp"
#include "../../las/las_record.hpp"
#include "../../las/laz_compress.hpp"

#include <io/copc.hpp>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace io::detail::copc_writer {

/// Writes the file around the chunks handed to it in file order: the header and VLRs at
/// construction, each chunk as it comes, then the table, the hierarchy and the header
/// fields. Every write that fails throws Error(record.where() + ": write failed: ...").
class Assembler {
  public:
    /// Writes the header and the VLRs to `file` (positioned at its start); the octree's
    /// cube is placed by the record's scale and offset.
    Assembler(const LasRecord& record, std::FILE* file);

    /// The chunk of one node cut out of the file LASzip wrote for it; `inventory` counts
    /// its records.
    void add(const CopcKey& key, const LaszipFile& f, std::size_t points, const LasInventory& inventory);
    /// A node's chunk as bytes (cut out as add() cuts them). Throws at 2 GiB or 2^31 points.
    void addBytes(const CopcKey& key, const char* data, std::size_t size, std::size_t points,
                  const LasInventory& inventory);
    /// Counts records whose chunks came through addBytes() uncounted.
    void count(const LasInventory& inventory) { inventory_.merge(inventory); }
    /// A node whose points all went to its ancestors.
    void addEmpty(const CopcKey& key) { entries_.push_back({key, 0, 0, 0}); }

    /// The chunk table, the hierarchy, then the info VLR and the header's fields for the
    /// octree's `cube`.
    void finish(const OctreeCube& cube);

  private:
    void pwriteAll(int fd, const void* data, std::size_t size, std::uint64_t at) const;
    void write(const void* data, std::size_t size);

    const LasRecord& record_;
    std::FILE* file_;
    std::string laszip_header_, empty_table_, header_;
    std::uint64_t at_ = 0;
    std::vector<CopcNode> entries_;
    std::vector<std::uint32_t> chunk_points_, chunk_bytes_;
    LasInventory inventory_;
};

}  // namespace io::detail::copc_writer
