// io/src/copc/writer/bucket_sorter.hpp (internal): out of core, the points sorted into one
// scratch file per bucket of the part tree (part_tree.hpp), in input order, each record the
// packed point and its index in the input. Rounds of points arrive with their buckets
// found; a bucket's records are gathered in a buffer of its own and written when it fills.
#pragma once
#include "../copc_octree.hpp"
#include "part_tree.hpp"
#include "setup.hpp"
#include "spill.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace io::detail::copc_writer {

/// Bytes of records gathered per bucket before they are written, and the buckets filled at
/// once (16 MiB).
inline constexpr std::size_t kBucketBufferBytes = std::size_t(1) << 16;
inline constexpr std::size_t kBucketsAtOnce = 256;

/// A bucket file's record: the packed point, then its index in the input (32 bits: the
/// writer holds fewer than 2^32 points).
inline std::size_t bucketRecordSize(const WriterSetup& setup) { return setup.packing.size() + sizeof(std::uint32_t); }

/// A round of points being sorted into buckets: packed, with their buckets.
struct Round {
    std::uint64_t first = 0;  // the input index of its first point
    std::size_t n = 0;
    std::vector<unsigned char> bytes;
    std::vector<std::uint32_t> bucket;
};

class BucketSorter {
  public:
    /// Buffers for `buckets` buckets at once (the files are the buckets' own, opened by
    /// the caller).
    BucketSorter(const WriterSetup& setup, PartTree& tree, std::size_t buckets);

    /// Appends the points of round `r` that fall in buckets [first, last) to their
    /// buckets' buffers (from bucket `first` on), each with its input index, writing a
    /// buffer out when it fills.
    void gather(const Round& r, std::size_t first, std::size_t last);
    /// Writes what buckets [first, last) still gather and rewinds their files, which stay
    /// until the buckets are built one at a time.
    void close(std::size_t first, std::size_t last);

  private:
    // A bucket's records gathered before they are written to its file.
    struct Gathered {
        std::vector<unsigned char> bytes;
        std::size_t used = 0;
    };

    const WriterSetup& setup_;
    PartTree& tree_;
    std::vector<Gathered> gathered_;
};

/// Sorts the `count` points of `spill` into their buckets' files, in input order, opening
/// the files: a round of blocks is read and its points' buckets found on the threads while
/// this thread gathers the round before (two rounds held at once, in the room the parts
/// are built in later). With more than kBucketsAtOnce buckets the spill is read once per
/// kBucketsAtOnce; with fewer, its pages are freed as they are sorted.
void sortSpill(const WriterSetup& setup, PartTree& tree, Spill& spill, std::uint64_t count, const OctreeCube& cube);

}  // namespace io::detail::copc_writer
