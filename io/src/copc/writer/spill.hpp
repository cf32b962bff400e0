// io/src/copc/writer/spill.hpp (internal): the points a COPC writer holds past its memory
// bound, packed in input order: their first bytes in memory (as many as the bound leaves
// beside the histogram and the sort into parts), the rest in a scratch file. What stays
// in memory is neither written to the disk nor copied back through the kernel.
#pragma once
#include <platform/scratch_file.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace io::detail::copc_writer {

class Spill {
  public:
    /// Keeps the first `head_bytes` in memory; the scratch file, in `dir`, is made when
    /// more come. `where` names the output in messages.
    Spill(const std::filesystem::path& dir, const std::string& where, std::size_t head_bytes);

    /// Appends; one thread at a time, and none reading. Throws as ScratchFile::append.
    void write(const void* data, std::size_t size);
    /// Makes what was written readable by readAt().
    void flush();
    /// Reads `size` bytes at `offset`; several threads may read at once. Throws
    /// Error("output: <where>: ...") past what was written.
    void readAt(void* data, std::size_t size, std::uint64_t offset) const;
    /// Frees [0, end), read for the last time (the memory once all of it is passed; the
    /// file's pages as ScratchFile::discardBefore does). A reader may meanwhile read past `end`.
    void discardBefore(std::uint64_t end);

  private:
    std::filesystem::path dir_;
    std::string where_;
    std::size_t capacity_;
    std::vector<unsigned char> head_;
    std::size_t head_size_ = 0;  // what the head holds (stays when its memory is freed)
    std::optional<platform::ScratchFile> tail_;
};

}  // namespace io::detail::copc_writer
