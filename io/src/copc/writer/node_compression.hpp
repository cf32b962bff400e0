// io/src/copc/writer/node_compression.hpp (internal): octree nodes compressed on the
// threads, each as one LAZ chunk, and handed on in order: the step the in-memory writer
// and each bucket of the out-of-core one share.
#pragma once
#include "../copc_octree.hpp"
#include "setup.hpp"
#include "../../las/laz_compress.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace io::detail::copc_writer {

/// Compresses `nodes` on the threads, handing each to `done(node, file, inventory)` in
/// order on the calling thread; `fillRecord(p, q, inventory)` fills LASzip's record `q`
/// with point `p` and counts it. A node being compressed holds at most
/// kCompressedBytesPerPoint a point (its records are filled one at a time); once
/// compressed, its bytes until it is handed on. Together they stay within the threads'
/// share of copcFixedBytes. Each node's points are freed once it is handed on.
template <typename FillRecord, typename Done>
void compressNodes(const WriterSetup& setup, std::vector<OctreeNode>& nodes, FillRecord fillRecord, Done done) {
    const std::size_t per_point = kCompressedBytesPerPoint;
    const std::size_t window =
        (1 + kCapsPerThread) * kCompressedBytesPerPoint * std::size_t(setup.cap) * std::size_t(setup.threads + 1);
    std::vector<LaszipFile> files(nodes.size());
    std::vector<LasInventory> counted(nodes.size());
    orderedParallel(
        nodes.size(), setup.threads, window,
        [&](std::size_t i) {
            const OctreeNode& node = nodes[i];
            if (node.points.empty()) return;
            LaszipMemoryWriter zip(setup.record, kVariableChunks);
            LasInventory inventory;  // on this thread's stack (see compressWithLaszip)
            for (std::uint32_t p : node.points) {
                fillRecord(p, zip.point(), inventory);
                zip.write();
            }
            files[i] = zip.finish();
            counted[i] = inventory;
        },
        [&](std::size_t i) {
            done(nodes[i], files[i], counted[i]);
            std::vector<std::uint32_t>().swap(nodes[i].points);
            files[i] = LaszipFile{};
        },
        [&](std::size_t i, bool compressed) {
            return compressed ? files[i].bytes.capacity() : nodes[i].points.size() * per_point;
        });
}

}  // namespace io::detail::copc_writer
