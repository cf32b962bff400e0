// io/src/copc/writer/spill.cpp: the spilled points, in memory then in a scratch file
// (spill.hpp).
#include "spill.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <cstring>

namespace io::detail::copc_writer {

Spill::Spill(const std::filesystem::path& dir, const std::string& where, std::size_t head_bytes)
    : dir_(dir), where_(where), capacity_(head_bytes) {
    head_.reserve(capacity_);  // address space only: pages are taken as they are written
}

void Spill::write(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    const std::size_t here = std::min(size, capacity_ - head_.size());
    head_.insert(head_.end(), bytes, bytes + here);
    head_size_ = head_.size();
    if (size == here) return;
    if (!tail_) tail_.emplace(dir_, where_);
    tail_->append(bytes + here, size - here);
}

void Spill::flush() {
    if (tail_) tail_->flush();
}

void Spill::readAt(void* data, std::size_t size, std::uint64_t offset) const {
    auto* bytes = static_cast<unsigned char*>(data);
    const std::uint64_t head = head_size_;
    if (offset < head) {
        const std::size_t n = std::size_t(std::min<std::uint64_t>(size, head - offset));
        std::memcpy(bytes, head_.data() + offset, n);
        bytes += n;
        size -= n;
        offset += n;
    }
    if (size > 0) {
        if (!tail_) throw core::Error("output: " + where_ + ": reading past the spilled points");
        tail_->readAt(bytes, size, offset - head);
    }
}

void Spill::discardBefore(std::uint64_t end) {
    const std::uint64_t head = head_size_;
    if (tail_ && end > head) tail_->discardBefore(end - head);
    if (end >= head) std::vector<unsigned char>().swap(head_);  // readers past `end` read the tail
}

}  // namespace io::detail::copc_writer
