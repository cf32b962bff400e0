// io/src/las/laz_compress.hpp (internal): LASzip compressing points into a LAZ file in
// memory, the unit both the LAZ writer (laz_writer.cpp, one chunk per file) and the COPC
// writer (copc/, one octree node per file) cut their chunks from.
#pragma once
#include "las_record.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <sstream>
#include <string>

namespace io::detail {

/// A file LASzip wrote into memory: its header and VLRs, the 8-byte position of its
/// chunk table, its chunks, its table.
struct LaszipFile {
    std::string bytes;
    std::size_t point_data_at = 0;  // offset_to_point_data
    std::size_t table_at = 0;       // where the chunk table starts
};

/// LASzip writing one file into memory, a record at a time: fill point() (as
/// LasRecord::fill does), write() it, and finish() once every record is written. Throws
/// Error(record.where() + ": ...").
class LaszipMemoryWriter {
  public:
    /// LAZ chunks of `chunk_size` points (UINT32_MAX: variable chunks, here one).
    LaszipMemoryWriter(const LasRecord& record, laszip_U32 chunk_size);
    ~LaszipMemoryWriter();
    LaszipMemoryWriter(const LaszipMemoryWriter&) = delete;
    LaszipMemoryWriter& operator=(const LaszipMemoryWriter&) = delete;

    laszip_point_struct& point() { return *point_; }
    void write();
    LaszipFile finish();

  private:
    const LasRecord& record_;
    // Before LASzip's writer: a writer closed on an error still writes into it.
    std::ostringstream out_;
    laszip_POINTER zip_ = nullptr;
    bool open_ = false;
    laszip_point_struct* point_ = nullptr;
};

/// LASzip compresses `points` (`first_index` the first one's index in the whole file, for
/// messages) with LAZ chunks of `chunk_size` points (UINT32_MAX: variable chunks, here
/// one), and counts them into `inventory`. Throws Error(record.where() + ": ...").
/// `foreign`: the points' side records where the record takes them (else null).
LaszipFile compressWithLaszip(const LasRecord& record, std::span<const core::CloudPoint> points,
                              std::uint64_t first_index, LasInventory& inventory, laszip_U32 chunk_size,
                              const unsigned char* foreign = nullptr);

}  // namespace io::detail
