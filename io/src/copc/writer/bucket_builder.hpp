// io/src/copc/writer/bucket_builder.hpp (internal): out of core, each bucket read back from
// its scratch file and its subtree built in memory as the in-memory writer builds the whole
// tree (copc_octree.hpp). Its nodes below its root are compressed into one scratch file of
// chunks, in the file's depth-first order; its root's points go up to the sets of the top
// (top_sets.hpp), to be sampled with the nodes above.
#pragma once
#include "../copc_octree.hpp"
#include "part_tree.hpp"
#include "setup.hpp"
#include "top_sets.hpp"
#include "../../las/las_record.hpp"

#include <platform/scratch_file.hpp>

namespace io::detail::copc_writer {

/// Builds every bucket of `tree`, in order, each bucket's file read and closed: its chunks
/// appended to `chunks` and listed in Bucket::chunks, its root's set appended to `sets`.
/// With threads, one bucket's nodes are compressed on a thread of their own while the next
/// bucket is read back and built. Two buckets are then held at once: the one being built
/// in the half of the bound it was sized for, the one being compressed (its points and
/// their indices) in the other half, which the top of the tree uses only once every bucket
/// is done. Returns the count of the chunks' records.
LasInventory buildBuckets(const WriterSetup& setup, PartTree& tree, const OctreeCube& cube, TopSets& sets,
                          platform::ScratchFile& chunks);

}  // namespace io::detail::copc_writer
