// io/src/copc/writer/part_tree.hpp (internal): out of core, the octree is built a part at a
// time. A histogram of the points over the cells of one level (at most 128^3) gives every
// upper node's count, hence the top of the tree: the nodes that split (more than the cap)
// and hold more than a bucket may. Their children that hold few enough are the buckets,
// each a subtree built in memory on its own (bucket_builder.hpp).
#pragma once
#include "../copc_octree.hpp"
#include "setup.hpp"
#include "spill.hpp"

#include <io/copc.hpp>

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace io::detail::copc_writer {

/// A node of the top of the tree, above the buckets that are built in memory one at a time.
struct Top {
    CopcKey key;
    std::uint64_t count = 0;
    std::array<int, 8> child{-1, -1, -1, -1, -1, -1, -1, -1};  // into PartTree::tops
    int bucket = -1;                                           // a bucket's root, else -1
    // Its points: a run of Lifted records in the sets' file (top_sets.hpp), ascending by
    // input index.
    std::uint64_t set_at = 0, set_n = 0;
};

/// A subtree built in memory: its points' scratch file until it is built, then its
/// compressed nodes' places in the chunks' file.
struct Bucket {
    int top = -1;  // its node in PartTree::tops
    std::optional<platform::ScratchFile> file;
    std::uint64_t count = 0;   // from the histogram
    std::uint64_t filled = 0;  // points sorted into its file
    // Its nodes below its root, compressed: key, place in the chunks' file, size, points.
    struct Chunk {
        CopcKey key;
        std::uint64_t at = 0, size = 0, points = 0;
    };
    std::vector<Chunk> chunks;
};

class PartTree {
  public:
    std::vector<Top> tops;  // the root first
    std::vector<Bucket> buckets;

    /// The histogram's level and the buckets' size for `cube` within `memory_bytes`, and
    /// the histogram cleared. Throws Error("<output>: a memory bound of N MiB leaves no
    /// room for a node of C points; allowed at least M MiB").
    void plan(const WriterSetup& setup, const OctreeCube& cube, std::uint64_t memory_bytes);

    /// The histogram's cell of the point at `xyz`.
    std::size_t cell(const OctreeCube& cube, const std::array<std::int32_t, 3>& xyz) const;

    /// Counts a thread's points into the histogram. Points in scan order fall in the same
    /// cell for long runs: one atomic add a run.
    struct CellCounter {
        std::vector<std::uint64_t>& hist;
        std::size_t cell = 0;
        std::uint64_t run = 0;
        void add(std::size_t c) {
            if (run > 0 && c != cell) flush();
            cell = c;
            ++run;
        }
        void flush() {
            if (run > 0) std::atomic_ref<std::uint64_t>(hist[cell]).fetch_add(run, std::memory_order_relaxed);
            run = 0;
        }
    };
    CellCounter counter() { return CellCounter{hist_}; }

    /// Counts the `count` points of `spill` (packed by setup.packing) per cell, its blocks
    /// shared among the threads (the spill flushed first).
    void countSpill(const WriterSetup& setup, Spill& spill, std::uint64_t count, const OctreeCube& cube);

    /// The top of the tree from the histogram, from the root down to the buckets. Throws
    /// Error("<output>: N points lie within D m of each other, more than ...") when the
    /// histogram's cells are too coarse to part them.
    void build(const WriterSetup& setup, const OctreeCube& cube);

    /// The bucket the point at `xyz` goes to: down the top from the root by its cell.
    int bucketOf(const OctreeCube& cube, const std::array<std::int32_t, 3>& xyz) const;

    /// Forgets the top and its buckets and frees the histogram.
    void clear();

  private:
    std::uint64_t countOf(const CopcKey& key) const;
    int makeTop(const WriterSetup& setup, const OctreeCube& cube, const CopcKey& key);

    int hist_level_ = 0;
    std::vector<std::uint64_t> hist_;
    std::uint64_t bucket_points_ = 0;  // the most points a bucket holds
};

}  // namespace io::detail::copc_writer
