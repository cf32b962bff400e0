// io/src/copc/writer/setup.hpp (internal): what every stage of the COPC writer shares:
// the record, the packing of the scratch files' points, the threads, the node cap, the
// folder of the scratch files, and the limits that size what the stages hold.
//
// The stages, in the order a file past the memory bound goes through them
// (io/src/copc/copc_writer.cpp is the front that runs them):
//   spill.hpp           the points as they arrive, in memory then in a scratch file;
//   part_tree.hpp       a histogram of the points, and from it the top of the tree and
//                       its buckets (the parts built in memory one at a time);
//   bucket_sorter.hpp   the points sorted into one scratch file per bucket;
//   bucket_builder.hpp  each bucket's subtree built and compressed;
//   top_sets.hpp        the nodes above the buckets sampled bottom-up from their sets;
//   parts_output.hpp    the file written depth-first through the assembler.
// A cloud within the bound skips them all: its octree is built in memory
// (copc_octree.hpp) and compressed (node_compression.hpp) straight into the assembler.
#pragma once
#include "../../las/las_record.hpp"

#include <io/point_packing.hpp>
#include <platform/scratch_file.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>

namespace io::detail::copc_writer {

/// LASzip's chunk size for variable chunks: a node is one chunk.
inline constexpr laszip_U32 kVariableChunks = std::numeric_limits<laszip_U32>::max();
/// Points a scratch file is read or written by at once (and a thread's block of work).
inline constexpr std::size_t kScratchBlock = std::size_t(1) << 16;
/// The nodes the writer makes: per thread, the compressed bytes of this many nodes of the
/// cap's points at most (kCompressedBytesPerPoint) are held at once, besides the nodes
/// being compressed.
inline constexpr std::size_t kCapsPerThread = 2;
/// A compressed node's bytes per point, at most (as the LAZ writer's chunks).
inline constexpr std::uint64_t kCompressedBytesPerPoint = 24;

class ForeignStore;

struct WriterSetup {
    const LasRecord& record;
    const PointPacking& packing;  // the scratch files' points, quantized
    int threads = 0;              // besides the caller's
    std::uint32_t cap = 1;        // the most points a node holds
    std::filesystem::path dir;    // where scratch files go: the output's folder
    std::string where;            // the output, as messages name it
    /// A foreign file's side records by input index, or null (foreign_store.hpp).
    const ForeignStore* foreign = nullptr;

    /// A new scratch file in the output's folder.
    platform::ScratchFile scratchFile() const { return platform::ScratchFile(dir, where); }
};

/// A point spilled to a bucket: the point and its index in the input.
struct Spilled {
    core::CloudPoint point;
    std::uint64_t index;
};

/// A point of an upper node's set, kept in a scratch file: the point (its position left at
/// its default: the integer coordinates stand for it), its index in the input and its
/// integer coordinates.
struct Lifted {
    Spilled spilled;
    std::array<std::int32_t, 3> xyz;
};

}  // namespace io::detail::copc_writer
