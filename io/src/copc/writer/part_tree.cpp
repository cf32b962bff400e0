// io/src/copc/writer/part_tree.cpp: the histogram and the top of the tree above the
// buckets (part_tree.hpp).
#include "part_tree.hpp"

#include <core/error.hpp>
#include <io/copc_writer.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace io::detail::copc_writer {

namespace {

// Out of core, the upper levels' counts come from a histogram of the points over the
// cells of one level: this one (128^3 cells, 16 MiB of counts) at most, and at most an
// eighth of the memory bound.
constexpr int kHistogramLevel = 7;

}  // namespace

void PartTree::plan(const WriterSetup& setup, const OctreeCube& cube, std::uint64_t memory_bytes) {
    const std::uint64_t fixed = copcFixedBytes(setup.threads, setup.cap);
    const std::uint64_t per_point = copcBytesPerPoint() + sizeof(Spilled);
    const std::uint64_t room = memory_bytes > fixed ? memory_bytes - fixed : 0;
    hist_level_ = 1;
    while (hist_level_ < kHistogramLevel && (std::uint64_t(8) << (3 * (hist_level_ + 1))) <= room / 8) ++hist_level_;
    hist_level_ = std::min(cube.bits, hist_level_);
    const std::uint64_t hist_bytes = std::uint64_t(8) << (3 * hist_level_);
    // Half: the other half holds a top node's chosen points and the set buffers.
    bucket_points_ = (room - std::min(room, hist_bytes)) / per_point / 2;
    if (bucket_points_ <= setup.cap)
        throw core::Error(setup.record.where() + ": a memory bound of " + std::to_string(memory_bytes >> 20) +
                          " MiB leaves no room for a node of " + std::to_string(setup.cap) +
                          " points; allowed at least " +
                          std::to_string(copcMinimumBytes(setup.threads, setup.cap) >> 20) + " MiB");
    hist_.assign(std::size_t(1) << (3 * hist_level_), 0);
}

std::size_t PartTree::cell(const OctreeCube& cube, const std::array<std::int32_t, 3>& xyz) const {
    const int shift = cube.bits - hist_level_;
    std::size_t c = 0;
    for (std::size_t k = 0; k < 3; ++k)
        c |= std::size_t((std::int64_t(xyz[k]) - cube.corner[k]) >> shift) << (std::size_t(hist_level_) * k);
    return c;
}

void PartTree::countSpill(const WriterSetup& setup, Spill& spill, std::uint64_t count, const OctreeCube& cube) {
    spill.flush();
    const std::size_t size = setup.packing.size();
    std::vector<std::vector<unsigned char>> bytes(std::size_t(setup.threads) + 1);
    const std::size_t blocks = std::size_t((count + kScratchBlock - 1) / kScratchBlock);
    parallelFor(blocks, setup.threads, [&](std::size_t block, std::size_t worker) {
        const std::uint64_t first = std::uint64_t(block) * kScratchBlock;
        const std::size_t n = std::size_t(std::min<std::uint64_t>(kScratchBlock, count - first));
        std::vector<unsigned char>& b = bytes[worker];
        b.resize(n * size);
        spill.readAt(b.data(), b.size(), first * size);
        CellCounter counted{hist_};
        for (std::size_t i = 0; i < n; ++i) counted.add(cell(cube, PointPacking::quantized(b.data() + i * size)));
        counted.flush();
    });
}

std::uint64_t PartTree::countOf(const CopcKey& key) const {
    const int up = hist_level_ - key.level;  // key.level <= hist_level_
    std::uint64_t n = 0;
    const int side = 1 << up;
    for (int z = 0; z < side; ++z)
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                const std::size_t cx = std::size_t((key.x << up) + x), cy = std::size_t((key.y << up) + y),
                                  cz = std::size_t((key.z << up) + z);
                const std::size_t h = std::size_t(hist_level_);
                n += hist_[cx | (cy << h) | (cz << (2 * h))];
            }
    return n;
}

void PartTree::build(const WriterSetup& setup, const OctreeCube& cube) { makeTop(setup, cube, CopcKey{}); }

int PartTree::makeTop(const WriterSetup& setup, const OctreeCube& cube, const CopcKey& key) {
    const std::uint64_t n = countOf(key);
    const int index = int(tops.size());
    tops.push_back(Top{key, n, {-1, -1, -1, -1, -1, -1, -1, -1}, -1, 0, 0});
    if (n <= setup.cap || key.level >= cube.bits || n <= bucket_points_) {
        tops[std::size_t(index)].bucket = int(buckets.size());
        buckets.push_back(Bucket{index, std::nullopt, n, 0, {}});
        return index;
    }
    if (key.level >= hist_level_)
        throw core::Error(setup.record.where() + ": " + std::to_string(n) + " points lie within " +
                          std::to_string(std::ldexp(setup.record.scale().x, cube.bits - key.level)) +
                          " m of each other, more than the memory bound lets one part of the octree hold; raise it");
    for (int o = 0; o < 8; ++o) {
        const CopcKey c{key.level + 1, 2 * key.x + (o & 1), 2 * key.y + ((o >> 1) & 1), 2 * key.z + ((o >> 2) & 1)};
        if (countOf(c) == 0) continue;
        const int child = makeTop(setup, cube, c);
        tops[std::size_t(index)].child[std::size_t(o)] = child;
    }
    return index;
}

int PartTree::bucketOf(const OctreeCube& cube, const std::array<std::int32_t, 3>& xyz) const {
    int t = 0;
    for (;;) {
        const Top& top = tops[std::size_t(t)];
        if (top.bucket >= 0) return top.bucket;
        const int shift = cube.bits - top.key.level - 1;
        int o = 0;
        for (std::size_t k = 0; k < 3; ++k) o |= int(((std::int64_t(xyz[k]) - cube.corner[k]) >> shift) & 1) << k;
        t = top.child[std::size_t(o)];
    }
}

void PartTree::clear() {
    tops.clear();
    buckets.clear();
    std::vector<std::uint64_t>().swap(hist_);
}

}  // namespace io::detail::copc_writer
