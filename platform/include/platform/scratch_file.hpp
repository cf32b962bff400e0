// platform/scratch_file.hpp: the one scratch-file type: bytes a stage writes now and reads
// back later (a writer's spilled points, its sorted buckets, a generator's spool).
//
// The file is anonymous (platform::openScratchFile: O_TMPFILE, or an O_EXCL|O_NOFOLLOW
// ".ladarvr-tmp-" name unlinked before any data goes in), in the folder the caller
// chooses (the output's, so the data stays on the output's file system). Having no name,
// nothing of it is left behind by a stopped or killed run: the kernel frees it when the
// last descriptor closes, on destruction or at the process's end, signal or not.
//
// Two ways to read: sequentially from the start after rewind(), or at offsets with
// readAt() (pread, so several threads may read while the stream keeps its place).
// Messages name the output the file serves: "output: <what>: ...".
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace platform {

class ScratchFile {
  public:
    /// An empty scratch file in `dir`; `what` (the output it serves) names it in messages.
    /// Throws Error("output: <what>: cannot create a scratch file in '<dir>': <reason>").
    ScratchFile(const std::filesystem::path& dir, std::string what);
    ~ScratchFile();
    ScratchFile(ScratchFile&& other) noexcept;
    ScratchFile& operator=(ScratchFile&& other) noexcept;
    ScratchFile(const ScratchFile&) = delete;
    ScratchFile& operator=(const ScratchFile&) = delete;

    /// The output named in messages.
    const std::string& what() const { return what_; }
    /// Bytes appended so far.
    std::uint64_t size() const { return size_; }

    /// Appends `size` bytes (buffered), before any rewind(). Throws
    /// Error("output: <what>: writing a scratch file failed: <reason>").
    void append(const void* data, std::size_t size);
    /// As append(), returning 0, or errno where the write failed, for a caller that words
    /// its own message; size() then counts only what was written whole.
    int tryAppend(const void* data, std::size_t size) noexcept;
    /// Makes what was appended readable by readAt(). Throws as append().
    void flush();

    /// Reads exactly `size` bytes at `offset` without moving the sequential position;
    /// several threads may read at once (none appending). Throws
    /// Error("output: <what>: reading a scratch file back failed") past the end or on error.
    void readAt(void* data, std::size_t size, std::uint64_t offset) const;

    /// Flushes and moves the sequential position to the start, for read() and readUpTo();
    /// appending ends here. Throws Error("output: <what>: rewinding a scratch file failed: <reason>").
    void rewind();
    /// As rewind(), returning 0, or errno where it failed.
    int tryRewind() noexcept;
    /// Reads exactly `size` bytes from the sequential position. Throws
    /// Error("output: <what>: reading a scratch file back failed") past the end or on error.
    void read(void* data, std::size_t size);
    /// Reads at most `size` bytes from the sequential position; returns how many, fewer
    /// only at the end. Throws as read() on a read error.
    std::size_t readUpTo(void* data, std::size_t size);

    /// Frees the whole pages of [0, end), read for the last time: their bytes need not
    /// reach the disk, and their memory serves other writes at once (platform::
    /// freeScratchBefore). Bytes past `end` stay readable.
    void discardBefore(std::uint64_t end);
    /// discardBefore(the sequential position): what read() has passed.
    void discardRead();

  private:
    std::FILE* file_ = nullptr;
    std::string what_;
    std::uint64_t size_ = 0;       // bytes appended
    std::uint64_t discarded_ = 0;  // freed up to here
    bool rewound_ = false;         // appending has ended
};

}  // namespace platform
