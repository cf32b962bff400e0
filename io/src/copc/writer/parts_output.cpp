// io/src/copc/writer/parts_output.cpp: the file written from the parts, depth first
// (parts_output.hpp).
#include "parts_output.hpp"

#include "foreign_store.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <string>

namespace io::detail::copc_writer {

void PartsOutput::write(Assembler& out) {
    orderTops(0);
    emit(out, 0);
}

// The upper nodes with points, in emit()'s depth-first order.
void PartsOutput::orderTops(int t) {
    const Top& top = tree_.tops[std::size_t(t)];
    if (top.set_n > 0) top_order_.push_back(t);
    if (top.bucket >= 0) return;
    for (int c : top.child)
        if (c >= 0) orderTops(c);
}

// Compresses the upper nodes top_order_[from ..] on the threads, one a thread, for
// emit() to take in order. A thread holds its node's set and chunk in the room
// copcFixedBytes gives it for compressing the parts' nodes, unused by then.
void PartsOutput::compressTops(std::size_t from) {
    const std::size_t n = std::min(top_order_.size() - from, std::size_t(setup_.threads) + 1);
    top_batch_.assign(n, TopChunk{});
    top_batch_from_ = from;
    sets_.flush();
    parallelFor(n, setup_.threads, [&](std::size_t i, std::size_t) {
        const Top& top = tree_.tops[std::size_t(top_order_[from + i])];
        std::vector<Lifted> set(std::size_t(top.set_n));
        sets_.read(set, top.set_at);
        LaszipMemoryWriter zip(setup_.record, kVariableChunks);
        LasInventory inventory;
        for (const Lifted& p : set) {
            setup_.record.fillQuantized(zip.point(), p.spilled.point, p.xyz, &inventory,
                                        setup_.foreign ? setup_.foreign->record(p.spilled.index) : nullptr);
            zip.write();
        }
        top_batch_[i] = TopChunk{zip.finish(), inventory};
    });
}

// Writes the top node `t` and what lies below it, depth first.
void PartsOutput::emit(Assembler& out, int t) {
    Top& top = tree_.tops[std::size_t(t)];
    if (top.set_n == 0) {
        out.addEmpty(top.key);
    } else {
        // emit() takes the upper nodes in the order orderTops() listed them.
        const std::size_t k = top_next_++;
        if (k >= top_order_.size() || top_order_[k] != t)
            throw core::Error(setup_.record.where() + ": the upper nodes came out of order");
        if (k >= top_batch_from_ + top_batch_.size()) compressTops(k);
        TopChunk& chunk = top_batch_[k - top_batch_from_];
        out.add(top.key, chunk.file, std::size_t(top.set_n), chunk.inventory);
        chunk = TopChunk{};
    }
    if (top.bucket >= 0) {
        Bucket& bucket = tree_.buckets[std::size_t(top.bucket)];
        std::string bytes;
        LasInventory none;
        std::uint64_t read = 0;  // the end of the chunks copied
        for (const Bucket::Chunk& c : bucket.chunks) {
            if (c.points == 0) {
                out.addEmpty(c.key);
                continue;
            }
            bytes.resize(std::size_t(c.size));
            chunks_.read(bytes.data(), bytes.size());
            out.addBytes(c.key, bytes.data(), bytes.size(), std::size_t(c.points), none);
            read = c.at + c.size;
        }
        // The chunks copied are read for the last time: their pages are freed for the
        // file's next ones to take.
        chunks_.discardBefore(read);
        return;
    }
    for (int c : top.child)
        if (c >= 0) emit(out, c);
}

}  // namespace io::detail::copc_writer
