// platform/src/scratch_file.cpp: the scratch file (platform/scratch_file.hpp), a buffered
// stream on an anonymous file from openScratchFile, read back by pread or sequentially.
#include <core/error.hpp>
#include <platform/safe_file.hpp>
#include <platform/scratch_file.hpp>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <utility>

#include <sys/types.h>
#include <unistd.h>

namespace platform {

using core::Error;

ScratchFile::ScratchFile(const std::filesystem::path& dir, std::string what) : what_(std::move(what)) {
    file_ = openScratchFile(dir, what_);
}

ScratchFile::~ScratchFile() {
    if (file_) std::fclose(file_);
}

ScratchFile::ScratchFile(ScratchFile&& other) noexcept
    : file_(std::exchange(other.file_, nullptr)),
      what_(std::move(other.what_)),
      size_(other.size_),
      discarded_(other.discarded_),
      rewound_(other.rewound_) {}

ScratchFile& ScratchFile::operator=(ScratchFile&& other) noexcept {
    if (this != &other) {
        if (file_) std::fclose(file_);
        file_ = std::exchange(other.file_, nullptr);
        what_ = std::move(other.what_);
        size_ = other.size_;
        discarded_ = other.discarded_;
        rewound_ = other.rewound_;
    }
    return *this;
}

int ScratchFile::tryAppend(const void* data, std::size_t size) noexcept {
    assert(!rewound_ && "a scratch file is appended to before it is rewound");
    if (size == 0) return 0;
    errno = 0;
    const std::size_t n = std::fwrite(data, 1, size, file_);
    if (n != size) return errno != 0 ? errno : EIO;
    size_ += size;
    return 0;
}

void ScratchFile::append(const void* data, std::size_t size) {
    if (const int e = tryAppend(data, size); e != 0)
        throw Error("output: " + what_ + ": writing a scratch file failed: " + std::strerror(e));
}

void ScratchFile::flush() {
    if (std::fflush(file_) != 0)
        throw Error("output: " + what_ + ": writing a scratch file failed: " + std::strerror(errno));
}

void ScratchFile::readAt(void* data, std::size_t size, std::uint64_t offset) const {
    auto* bytes = static_cast<char*>(data);
    while (size > 0) {
        const ssize_t n = ::pread(::fileno(file_), bytes, size, off_t(offset));
        if (n <= 0) throw Error("output: " + what_ + ": reading a scratch file back failed");
        bytes += n;
        size -= std::size_t(n);
        offset += std::uint64_t(n);
    }
}

int ScratchFile::tryRewind() noexcept {
    rewound_ = true;
    if (std::fflush(file_) != 0 || ::fseeko(file_, 0, SEEK_SET) != 0) return errno != 0 ? errno : EIO;
    return 0;
}

void ScratchFile::rewind() {
    if (const int e = tryRewind(); e != 0)
        throw Error("output: " + what_ + ": rewinding a scratch file failed: " + std::strerror(e));
}

void ScratchFile::read(void* data, std::size_t size) {
    if (size > 0 && std::fread(data, 1, size, file_) != size)
        throw Error("output: " + what_ + ": reading a scratch file back failed");
}

std::size_t ScratchFile::readUpTo(void* data, std::size_t size) {
    const std::size_t n = size > 0 ? std::fread(data, 1, size, file_) : 0;
    if (n < size && std::ferror(file_)) throw Error("output: " + what_ + ": reading a scratch file back failed");
    return n;
}

void ScratchFile::discardBefore(std::uint64_t end) { discarded_ = freeScratchBefore(file_, discarded_, end); }

void ScratchFile::discardRead() {
    const off_t at = ::ftello(file_);
    discardBefore(at < 0 ? 0 : std::uint64_t(at));
}

}  // namespace platform
