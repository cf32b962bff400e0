// io/src/copc/writer/bucket_builder.cpp: each bucket's subtree built and compressed
// (bucket_builder.hpp).
#include "bucket_builder.hpp"

#include "bucket_sorter.hpp"
#include "foreign_store.hpp"
#include "node_compression.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <future>
#include <vector>

namespace io::detail::copc_writer {

namespace {

class BucketBuilder {
  public:
    BucketBuilder(const WriterSetup& setup, PartTree& tree, TopSets& sets, platform::ScratchFile& chunks)
        : setup_(setup), tree_(tree), sets_(sets), chunks_(chunks) {}

    // A bucket read back and its subtree built, its nodes below its root waiting to be
    // compressed.
    struct LoadedBucket {
        std::size_t bucket = 0;
        std::vector<unsigned char> records;  // as in its file: packed point, input index
        std::vector<OctreeNode> nodes;
    };

    void load(const OctreeCube& cube, std::size_t b, LoadedBucket& loaded);
    void compress(LoadedBucket& loaded);
    const LasInventory& inventory() const { return inventory_; }

  private:
    std::uint32_t recordIndex(const unsigned char* record) const {
        std::uint32_t index = 0;
        std::memcpy(&index, record + setup_.packing.size(), sizeof index);
        return index;
    }
    void liftRoot(Top& root, const std::vector<unsigned char>& records, std::vector<std::uint32_t> up);

    const WriterSetup& setup_;
    PartTree& tree_;
    TopSets& sets_;
    platform::ScratchFile& chunks_;
    std::uint64_t chunks_at_ = 0;
    LasInventory inventory_;                        // of the buckets' chunks
    std::vector<std::array<std::int32_t, 3>> xyz_;  // the bucket being loaded's
    std::vector<Marks> marks_;                      // its octree builder's
};

// Loads bucket `b` into `loaded`, whose vectors keep their room from one bucket to the
// next (fresh pages for every bucket cost the kernel more than the copying). The points
// stay packed: the threads that compress a node unpack its points.
void BucketBuilder::load(const OctreeCube& cube, std::size_t b, LoadedBucket& loaded) {
    Bucket& bucket = tree_.buckets[b];
    Top& root = tree_.tops[std::size_t(bucket.top)];
    loaded.bucket = b;
    const std::size_t record = bucketRecordSize(setup_), n = std::size_t(bucket.count);
    std::vector<unsigned char>& records = loaded.records;
    records.resize(n * record);
    bucket.file->read(records.data(), records.size());
    bucket.file.reset();
    std::vector<std::array<std::int32_t, 3>>& xyz = xyz_;
    xyz.resize(n);
    parallelFor((n + kScratchBlock - 1) / kScratchBlock, setup_.threads, [&](std::size_t block, std::size_t) {
        for (std::size_t i = block * kScratchBlock; i < std::min(n, (block + 1) * kScratchBlock); ++i) {
            const unsigned char* r = records.data() + i * record;
            xyz[i] = PointPacking::quantized(r);
        }
    });
    OctreeCube sub;
    sub.bits = cube.bits - root.key.level;
    const int key[3] = {root.key.x, root.key.y, root.key.z};
    for (std::size_t k = 0; k < 3; ++k) sub.corner[k] = cube.corner[k] + (std::int64_t(key[k]) << sub.bits);
    std::vector<OctreeNode>& nodes = loaded.nodes;
    nodes = buildOctree(xyz, sub, setup_.cap, setup_.threads, &marks_);
    // Keys from the bucket's subtree to the whole tree's.
    for (OctreeNode& node : nodes) {
        const int l = node.key.level;
        node.key = {root.key.level + l, (root.key.x << l) + node.key.x, (root.key.y << l) + node.key.y,
                    (root.key.z << l) + node.key.z};
    }
    // The root's points go up to the sets; the others are final.
    liftRoot(root, records, nodes.front().points);
    nodes.erase(nodes.begin());
}

// The bucket's root's points `up`, in input order, as the root's set.
void BucketBuilder::liftRoot(Top& root, const std::vector<unsigned char>& records, std::vector<std::uint32_t> up) {
    const std::size_t record = bucketRecordSize(setup_);
    const auto indexOf = [&](std::uint32_t i) { return recordIndex(records.data() + std::size_t(i) * record); };
    std::sort(up.begin(), up.end(), [&](std::uint32_t a, std::uint32_t c) { return indexOf(a) < indexOf(c); });
    std::vector<Lifted> run;
    run.reserve(up.size());
    for (std::uint32_t i : up)
        run.push_back(
            Lifted{Spilled{setup_.packing.unpack(records.data() + std::size_t(i) * record), indexOf(i)}, xyz_[i]});
    root.set_n = run.size();
    root.set_at = sets_.append(run);
}

// Compresses a loaded bucket's nodes into the scratch file of chunks, in order.
void BucketBuilder::compress(LoadedBucket& loaded) {
    Bucket& bucket = tree_.buckets[loaded.bucket];
    const std::size_t record = bucketRecordSize(setup_);
    const unsigned char* records = loaded.records.data();
    compressNodes(
        setup_, loaded.nodes,
        [&](std::uint32_t p, laszip_point_struct& q, LasInventory& inventory) {
            const unsigned char* r = records + std::size_t(p) * record;
            setup_.record.fillQuantized(q, setup_.packing.unpack(r), PointPacking::quantized(r), &inventory,
                                        setup_.foreign ? setup_.foreign->record(recordIndex(r)) : nullptr);
        },
        [&](const OctreeNode& node, const LaszipFile& f, const LasInventory& inv) {
            Bucket::Chunk c{node.key, chunks_at_, 0, node.points.size()};
            if (!node.points.empty()) {
                const std::size_t begin = f.point_data_at + 8;
                c.size = f.table_at - begin;
                chunks_.append(f.bytes.data() + begin, c.size);
                chunks_at_ += c.size;
                inventory_.merge(inv);
            }
            bucket.chunks.push_back(c);
        });
}

}  // namespace

LasInventory buildBuckets(const WriterSetup& setup, PartTree& tree, const OctreeCube& cube, TopSets& sets,
                          platform::ScratchFile& chunks) {
    BucketBuilder builder(setup, tree, sets, chunks);
    using LoadedBucket = BucketBuilder::LoadedBucket;
    if (setup.threads == 0) {
        LoadedBucket loaded;
        for (std::size_t b = 0; b < tree.buckets.size(); ++b) {
            builder.load(cube, b, loaded);
            builder.compress(loaded);
        }
    } else {
        std::array<LoadedBucket, 2> slots;
        std::future<void> compressed;  // declared last: waited for before the slots go
        for (std::size_t b = 0; b < tree.buckets.size(); ++b) {
            LoadedBucket& loaded = slots[b % 2];  // the other slot may be compressing
            builder.load(cube, b, loaded);
            if (compressed.valid()) compressed.get();
            compressed = std::async(std::launch::async, [&builder, &loaded] { builder.compress(loaded); });
        }
        if (compressed.valid()) compressed.get();
    }
    return builder.inventory();
}

}  // namespace io::detail::copc_writer
