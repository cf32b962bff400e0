// io/src/copc/writer/foreign_store.hpp (internal): the side records of a foreign file's
// points (core::ForeignPoint and its extra bytes) that a COPC writer gives back in its
// records. They stay in input order, apart from the points: every stage that moves the
// points (the octree's sort, the spill, the buckets, the top sets) knows each point's
// input index, and the threads that fill the records look a point's side record up by it.
// Within a bound they are held in memory, past it in a scratch file (the spill's way).
#pragma once
#include "spill.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace io::detail::copc_writer {

class ForeignStore {
  public:
    /// Records of `stride` bytes; the first `memory_bytes` in memory (0: all of them), the
    /// rest in a scratch file in `dir`. `where` names the output in messages.
    ForeignStore(const std::filesystem::path& dir, const std::string& where, std::size_t stride,
                 std::uint64_t memory_bytes);

    std::size_t stride() const { return stride_; }
    /// Appends `count` records; one thread at a time, and none reading.
    void append(const unsigned char* records, std::size_t count);
    /// Makes what was appended readable by record().
    void flush();
    /// The record of the point of input index `index`: valid on this thread until its next
    /// call. Several threads may read at once. Throws Error past what was appended.
    const unsigned char* record(std::uint64_t index) const;

  private:
    std::size_t stride_;
    std::uint64_t count_ = 0;
    std::vector<unsigned char> all_;  // without a bound
    std::unique_ptr<Spill> spill_;    // with one
};

}  // namespace io::detail::copc_writer
