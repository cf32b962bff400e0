// io/src/copc/writer/foreign_store.cpp: a foreign file's side records by input index
// (foreign_store.hpp).
#include "foreign_store.hpp"

#include <core/error.hpp>

namespace io::detail::copc_writer {

ForeignStore::ForeignStore(const std::filesystem::path& dir, const std::string& where, std::size_t stride,
                           std::uint64_t memory_bytes)
    : stride_(stride) {
    if (memory_bytes > 0) spill_ = std::make_unique<Spill>(dir, where, std::size_t(memory_bytes / stride * stride));
}

void ForeignStore::append(const unsigned char* records, std::size_t count) {
    if (spill_)
        spill_->write(records, count * stride_);
    else
        all_.insert(all_.end(), records, records + count * stride_);
    count_ += count;
}

void ForeignStore::flush() {
    if (spill_) spill_->flush();
}

const unsigned char* ForeignStore::record(std::uint64_t index) const {
    if (index >= count_) throw core::Error("output: a point's side record was never appended");
    if (!spill_) return all_.data() + index * stride_;
    thread_local std::vector<unsigned char> buffer;
    buffer.resize(stride_);
    spill_->readAt(buffer.data(), stride_, index * stride_);
    return buffer.data();
}

}  // namespace io::detail::copc_writer
