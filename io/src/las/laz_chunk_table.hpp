// io/src/las/laz_chunk_table.hpp (internal): the chunk table at the end of a LAZ file.
//
// A LAZ file's points are compressed in chunks that decode independently; the table
// after the last chunk lists each chunk's size in bytes so that a reader can seek. LASzip
// writes it as a 32-bit version (0), a 32-bit chunk count, then the sizes coded by its
// adaptive arithmetic coder: each size as the difference from the previous one, through
// an integer corrector (the bucket of the difference's magnitude, then its low bits).
// A file of variable-size chunks also codes each chunk's point count, before its size.
// The LAZ writer compresses chunks on several threads with LASzip and joins them itself,
// so it needs this table without LASzip's writer: this file codes it, bit for bit as
// LASzip does (the LAZ tests check the joined file against one written by LASzip alone).
#pragma once
#include <cstdint>
#include <span>
#include <string>

namespace io::detail {

/// The table of a file whose chunks all hold the same number of points (the last one may
/// hold fewer), `chunk_bytes[i]` being the compressed size of chunk i, each < 2^31:
/// version, count and coded sizes, to be written right after the last chunk.
std::string lazChunkTable(std::span<const std::uint32_t> chunk_bytes);

/// The table of a file of variable-size chunks (LASzip's chunk size UINT32_MAX, as COPC
/// has): for each chunk its point count `chunk_points[i]` and then its byte count, both
/// coded as differences from the previous chunk's (point counts in the coder's context 0,
/// byte counts in context 1), as LASzip writes it. Both spans have one entry per chunk,
/// each < 2^31. Throws Error when the spans differ in length.
std::string lazVariableChunkTable(std::span<const std::uint32_t> chunk_points,
                                  std::span<const std::uint32_t> chunk_bytes);

}  // namespace io::detail
