// io/src/copc/writer/bucket_sorter.cpp: the points sorted into the buckets' scratch files
// (bucket_sorter.hpp).
#include "bucket_sorter.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <future>

namespace io::detail::copc_writer {

BucketSorter::BucketSorter(const WriterSetup& setup, PartTree& tree, std::size_t buckets)
    : setup_(setup), tree_(tree), gathered_(buckets) {}

void BucketSorter::gather(const Round& r, std::size_t first, std::size_t last) {
    const std::size_t size = setup_.packing.size(), record = bucketRecordSize(setup_);
    for (std::size_t i = 0; i < r.n; ++i) {
        const std::uint32_t bucket = r.bucket[i];
        if (bucket < first || bucket >= last) continue;
        Gathered& g = gathered_[bucket - first];
        if (g.bytes.empty()) g.bytes.resize(kBucketBufferBytes);
        if (g.used + record > g.bytes.size()) {
            tree_.buckets[bucket].file->append(g.bytes.data(), g.used);
            g.used = 0;
        }
        unsigned char* at = g.bytes.data() + g.used;
        std::memcpy(at, r.bytes.data() + i * size, size);
        const std::uint32_t index = std::uint32_t(r.first + i);
        std::memcpy(at + size, &index, sizeof index);
        g.used += record;
        ++tree_.buckets[bucket].filled;
    }
}

void BucketSorter::close(std::size_t first, std::size_t last) {
    for (std::size_t b = first; b < last; ++b) {
        Gathered& g = gathered_[b - first];
        tree_.buckets[b].file->append(g.bytes.data(), g.used);
        g.used = 0;
        tree_.buckets[b].file->rewind();
    }
}

void sortSpill(const WriterSetup& setup, PartTree& tree, Spill& spill, std::uint64_t count, const OctreeCube& cube) {
    const std::size_t size = setup.packing.size();
    const std::size_t parts = std::size_t(setup.threads) + 1;
    const auto prepare = [&](std::uint64_t first, Round& r) {
        r.first = first;
        r.n = std::size_t(std::min<std::uint64_t>(kScratchBlock * parts, count - first));
        r.bytes.resize(r.n * size);
        r.bucket.resize(r.n);
        spill.readAt(r.bytes.data(), r.bytes.size(), first * size);
        const std::size_t blocks = (r.n + kScratchBlock - 1) / kScratchBlock;
        parallelFor(blocks, setup.threads, [&](std::size_t b, std::size_t) {
            for (std::size_t i = b * kScratchBlock; i < std::min(r.n, (b + 1) * kScratchBlock); ++i) {
                r.bucket[i] = std::uint32_t(tree.bucketOf(cube, PointPacking::quantized(r.bytes.data() + i * size)));
            }
        });
    };
    std::vector<Bucket>& buckets = tree.buckets;
    BucketSorter sorter(setup, tree, std::min(kBucketsAtOnce, buckets.size()));
    spill.flush();
    for (std::size_t first = 0; first < buckets.size(); first += kBucketsAtOnce) {
        const std::size_t last = std::min(buckets.size(), first + kBucketsAtOnce);
        for (std::size_t b = first; b < last; ++b) buckets[b].file.emplace(setup.scratchFile());
        std::array<Round, 2> rounds;
        std::size_t cur = 0;
        if (count > 0) prepare(0, rounds[0]);
        while (rounds[cur].n > 0) {
            Round& r = rounds[cur];
            Round& next = rounds[cur ^ 1];
            const std::uint64_t after = r.first + r.n;
            next.n = 0;
            std::future<void> ahead;
            if (after < count) {
                if (setup.threads == 0)
                    prepare(after, next);
                else
                    ahead = std::async(std::launch::async, [&, after] { prepare(after, next); });
            }
            sorter.gather(r, first, last);
            // One pass sorts every bucket: the spill's bytes up to here are done with.
            if (buckets.size() <= kBucketsAtOnce) spill.discardBefore((r.first + r.n) * size);
            if (ahead.valid()) ahead.get();
            cur ^= 1;
        }
        sorter.close(first, last);
    }
}

}  // namespace io::detail::copc_writer
