// io/src/copc/writer/direct_sort.hpp (internal): past the memory bound, after the prescan
// (FormatWriter::prescanPasses) gave the points' bounds and histogram, the points are
// sorted straight into their buckets' files as they are appended, instead of being
// spilled and read back twice.
#pragma once
#include "../copc_octree.hpp"
#include "bucket_sorter.hpp"
#include "part_tree.hpp"
#include "setup.hpp"

#include <core/point_cloud.hpp>

#include <array>
#include <cstdint>
#include <future>
#include <span>

namespace io::detail::copc_writer {

class DirectSort {
  public:
    /// Opens a scratch file for each of the buckets of `tree` (at most kBucketsAtOnce) for
    /// the `points` points prescanned, whose integer coordinates lie in [lo, hi].
    DirectSort(const WriterSetup& setup, PartTree& tree, const std::array<std::int32_t, 3>& lo,
               const std::array<std::int32_t, 3>& hi, std::uint64_t points);
    DirectSort(const DirectSort&) = delete;
    DirectSort& operator=(const DirectSort&) = delete;

    /// Packs the points on the threads with their buckets, a round of kScratchBlock points
    /// a thread, and gathers each round into the buckets' files on a thread of its own
    /// while the caller makes the next points (two rounds held at once, as when the spill
    /// is sorted). Throws Error("<output>: ...") for a point outside the bounds
    /// prescanned, or more points than were.
    void append(std::span<const core::CloudPoint> points);
    /// Writes what the buckets still gather and rewinds their files. Throws when the
    /// points appended are not those prescanned (in count, or per bucket).
    void finish();

  private:
    bool within(const std::array<std::int32_t, 3>& xyz) const;
    // Waits for the last round to be gathered (and rethrows its error).
    void waitGather();

    const WriterSetup& setup_;
    PartTree& tree_;
    std::array<std::int32_t, 3> lo_, hi_;
    OctreeCube cube_;
    std::uint64_t points_ = 0;  // prescanned
    std::uint64_t count_ = 0;   // appended
    BucketSorter sorter_;
    std::array<Round, 2> rounds_;
    std::size_t next_ = 0;      // the round to pack into next
    std::future<void> gather_;  // declared after what it writes, so waited for first
};

}  // namespace io::detail::copc_writer
