// io/src/copc/copc_writer.cpp: COPC output (io/copc_writer.hpp), the front over the
// writer's stages in io/src/copc/writer/ (setup.hpp lists them).
//
// The points arrive through append(). Within CopcOptions::memory_bytes they are held in
// memory, and at finish() their octree is built (copc_octree.hpp), its nodes compressed on
// the threads (writer/node_compression.hpp) and handed in depth-first order to the
// assembler (writer/assembler.hpp), which lays out the file. Past the bound they are packed
// into the spill (writer/spill.hpp) and, at finish(), the octree is built a part at a time:
//  1. A histogram of the points over the cells of a fixed level (at most 128^3) gives
//     every upper node's count, hence the top of the tree: the nodes that split (more
//     than the cap) and hold more than a bucket may; their children are the buckets
//     (writer/part_tree.hpp).
//  2. One pass over the spill (or more, 256 buckets at a time) sorts the points into
//     one scratch file per bucket, in input order, each with its input index
//     (writer/bucket_sorter.hpp).
//  3. Each bucket's subtree is built in memory as the in-memory writer builds it; its
//     nodes below its root are compressed into a scratch file of chunks, and its
//     root's points go to a scratch file of sets, in input order, for the top
//     (writer/bucket_builder.hpp).
//  4. The top nodes sample their children's points bottom-up, as in memory, each
//     streaming its children's sets from the scratch file (so memory holds one node's
//     chosen points, never the whole top of the tree) (writer/top_sets.hpp).
//  5. The file is written in the in-memory writer's depth-first order, the buckets'
//     chunks copied from the scratch file: the same file, byte for byte
//     (writer/parts_output.hpp).
// A caller that can give the points twice more (the generator's spool) lets the writer
// learn their bounds and histogram first (prescanPasses), and the points are then sorted
// into the buckets as they are appended (writer/direct_sort.hpp), skipping the spill.
#include "copc_octree.hpp"
#include "format_writer.hpp"
#include "writer/assembler.hpp"
#include "writer/bucket_builder.hpp"
#include "writer/bucket_sorter.hpp"
#include "writer/direct_sort.hpp"
#include "writer/foreign_store.hpp"
#include "writer/node_compression.hpp"
#include "writer/part_tree.hpp"
#include "writer/parts_output.hpp"
#include "writer/setup.hpp"
#include "writer/spill.hpp"
#include "writer/top_sets.hpp"

#include <core/error.hpp>
#include <io/copc_writer.hpp>
#include <io/point_packing.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>
#include <platform/scratch_file.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace io::detail {

using core::CloudPoint;
using core::Error;
using namespace copc_writer;

namespace {

// Integer bounds of some points.
struct Bounds {
    std::array<std::int32_t, 3> lo{}, hi{};
    bool any = false;
    void widen(const std::array<std::int32_t, 3>& xyz) {
        for (std::size_t k = 0; k < 3; ++k) {
            lo[k] = any ? std::min(lo[k], xyz[k]) : xyz[k];
            hi[k] = any ? std::max(hi[k], xyz[k]) : xyz[k];
        }
        any = true;
    }
};

class CopcWriter final : public FormatWriter {
  public:
    CopcWriter(platform::TempFile& file, LasRecord record, const core::CloudFields& fields, const LasOptions& las,
               const CopcOptions& copc)
        : record_(std::move(record)),
          packing_(fields, PointPacking::Position::Quantized),
          file_(file.file()),
          copc_(copc),
          setup_{
              record_,
              packing_,
              std::max(las.threads, 0),
              std::max<std::uint32_t>(copc.max_node_points, 1),
              file.destination().parent_path().empty() ? std::filesystem::path(".") : file.destination().parent_path(),
              file.destination().string(),
              nullptr} {
        if (const core::ForeignHeader* f = record_.foreign()) {
            // The side records take their share of the bound, as much per point as the
            // points' own share (copcBytesPerPoint), so both leave memory at about one count.
            const std::uint64_t stride = f->stride();
            const std::uint64_t share = copc_.memory_bytes * stride / (stride + copcBytesPerPoint());
            foreign_ = std::make_unique<ForeignStore>(setup_.dir, setup_.where, std::size_t(stride), share);
            copc_.memory_bytes -= share;
            setup_.foreign = foreign_.get();
        }
    }

    // A foreign file's points come with their side records, kept apart in input order.
    void appendForeign(std::span<const CloudPoint> points, const unsigned char* records) override {
        if (!foreign_ || !records) {
            append(points);
            return;
        }
        foreign_->append(records, points.size());
        appendPoints(points, records);
    }

    // The points are held in blocks, so that the store never reallocates (a vector that
    // doubles would hold up to three times the points while it grows). Past
    // CopcOptions::memory_bytes they go to a scratch file instead.
    void append(std::span<const CloudPoint> points) override {
        if (foreign_) {
            // Points without side records get empty ones (class 0, no GPS time).
            const std::vector<unsigned char> none(points.size() * foreign_->stride(), 0);
            foreign_->append(none.data(), points.size());
        }
        appendPoints(points);
    }

    // `records`: the points' side records where they came with them (their integer
    // coordinates are then the records'), else null.
    void appendPoints(std::span<const CloudPoint> points, const unsigned char* records = nullptr) {
        if (prescan_ == Prescan::Histogram) startDirect();
        if (prescan_ == Prescan::Direct) {
            direct_->append(points);
            count_ += points.size();
            return;
        }
        if (prescan_ != Prescan::None && prescan_ != Prescan::Declined)
            throw Error(record_.where() + ": points appended before the prescan's two passes ended");
        if (spill_) {
            spillAppend(points, records);
            return;
        }
        while (!points.empty()) {
            if (blocks_.empty() || blocks_.back().size() == kBlockPoints) {
                blocks_.emplace_back();
                blocks_.back().reserve(kBlockPoints);
            }
            std::vector<CloudPoint>& b = blocks_.back();
            const std::size_t n = std::min(points.size(), kBlockPoints - b.size());
            b.insert(b.end(), points.begin(), points.begin() + std::ptrdiff_t(n));
            points = points.subspan(n);
            count_ += n;
        }
        if (copc_.memory_bytes > 0 &&
            count_ * copcBytesPerPoint() + copcFixedBytes(setup_.threads, setup_.cap) > copc_.memory_bytes) {
            spill_ = std::make_unique<Spill>(setup_.dir, setup_.where, spillHeadBytes());
            const std::size_t held = count_;
            count_ = 0;
            for (std::vector<CloudPoint>& b : blocks_) {
                spillAppend(b);
                std::vector<CloudPoint>().swap(b);
            }
            blocks_.clear();
            if (count_ != held) throw Error(record_.where() + ": spilling lost points");
        }
    }

    // Past the bound, a caller that can give the points twice more lets the writer sort
    // them straight into the buckets' files as they are appended, instead of spilling
    // them and reading the spill back twice (its bounds are then known from the first
    // pass, its histogram from the second).
    int prescanPasses(std::uint64_t points, const core::Bounds* positions) override {
        if (prescan_ != Prescan::None || count_ > 0 || spill_ || foreign_) return 0;
        if (copc_.memory_bytes == 0 || points == 0 || points >= std::numeric_limits<std::uint32_t>::max() ||
            points * copcBytesPerPoint() + copcFixedBytes(setup_.threads, setup_.cap) <= copc_.memory_bytes)
            return 0;
        prescan_points_ = points;
        if (positions && !positions->empty()) {
            std::array<std::int32_t, 3> lo{}, hi{};
            try {
                lo = record_.quantize(glm::vec3(positions->lo), 0);
                hi = record_.quantize(glm::vec3(positions->hi), 0);
            } catch (const Error&) {
                return 0;  // a point out of LAS's reach: the usual way names it
            }
            startHistogram(lo, hi);
            return 1;
        }
        prescan_ = Prescan::Bounds;
        return 2;
    }

    void prescan(int pass, std::span<const CloudPoint> points) override {
        if (prescan_ == Prescan::Bounds && pass == prescan_pass_ + 1) {
            if (prescanned_ != prescan_points_)
                throw Error(record_.where() + ": the prescan's first pass gave " + std::to_string(prescanned_) +
                            " points of " + std::to_string(prescan_points_));
            startHistogram(prescan_bounds_.lo, prescan_bounds_.hi);
            prescan_pass_ = pass;
        }
        if (pass != prescan_pass_ || (prescan_ != Prescan::Bounds && prescan_ != Prescan::Histogram))
            throw Error(record_.where() + ": prescan pass " + std::to_string(pass) + " out of order");
        const bool bounds = prescan_ == Prescan::Bounds;
        const OctreeCube cube = enclosingCube(lo_, hi_);
        const std::size_t blocks = (points.size() + kScratchBlock - 1) / kScratchBlock;
        std::vector<Bounds> seen(blocks);
        const std::uint64_t first = prescanned_;
        parallelFor(blocks, setup_.threads, [&](std::size_t b, std::size_t) {
            PartTree::CellCounter counter = tree_.counter();
            Bounds& local = seen[b];
            Bounds mine;  // on the worker's stack: the blocks' bounds share cache lines
            for (std::size_t i = b * kScratchBlock; i < std::min(points.size(), (b + 1) * kScratchBlock); ++i) {
                const std::array<std::int32_t, 3> xyz = record_.quantize(points[i], first + i);
                mine.widen(xyz);
                if (bounds) continue;
                if (!within(xyz))
                    throw Error(record_.where() + ": point " + std::to_string(first + i) +
                                " lies outside the bounds of the points prescanned");
                counter.add(tree_.cell(cube, xyz));
            }
            counter.flush();
            local = mine;
        });
        for (const Bounds& b : seen)
            if (b.any) {
                prescan_bounds_.widen(b.lo);
                prescan_bounds_.widen(b.hi);
            }
        prescanned_ += points.size();
    }

    void finish() override {
        if (count_ >= std::numeric_limits<std::uint32_t>::max())
            throw Error(record_.where() + ": COPC output holds at most 4294967294 points");
        if (prescan_ == Prescan::Histogram) startDirect();  // no point appended
        if (foreign_) foreign_->flush();
        if (prescan_ == Prescan::Bounds)
            throw Error(record_.where() + ": finished after the prescan's first pass alone");
        if (prescan_ == Prescan::Direct)
            finishDirect();
        else if (spill_)
            finishSpilled();
        else
            finishInMemory();
    }

  private:
    static constexpr std::size_t kBlockBits = 20;
    static constexpr std::size_t kBlockPoints = std::size_t(1) << kBlockBits;

    const CloudPoint& point(std::size_t i) const { return blocks_[i >> kBlockBits][i & (kBlockPoints - 1)]; }

    // Packs the points on the threads, a block of kScratchBlock points each, with the
    // integer coordinates their records will hold in place of their positions (what every
    // later pass reads: none converts a position again), and writes
    // each round of blocks to the spill on a thread of its own while the next round is
    // packed. The two rounds' bytes (at most 2 x 2^16 x 39 bytes a thread) fit in what the
    // bound sets aside for the octree's parts, unused until the spill is read back: the
    // points held in memory before the spill take 40 of the 64 bytes counted for each.
    // A foreign point's integer coordinates come from its side record: from `records`
    // (the points', in their order), else from those appended to the store before.
    void spillAppend(std::span<const CloudPoint> points, const unsigned char* records = nullptr) {
        const std::size_t size = packing_.size();
        const std::size_t stride = foreign_ ? foreign_->stride() : 0;
        if (foreign_ && !records) foreign_->flush();
        const std::size_t parts = std::size_t(setup_.threads) + 1;
        while (!points.empty()) {
            const std::size_t n = std::min(points.size(), kScratchBlock * parts);
            const std::size_t blocks = (n + kScratchBlock - 1) / kScratchBlock;
            std::vector<unsigned char>& packed = spill_bytes_[spill_next_];
            packed.resize(n * size);
            std::vector<Bounds> bounds(blocks);
            const std::uint64_t first = count_;
            parallelFor(blocks, setup_.threads, [&](std::size_t b, std::size_t) {
                Bounds local;  // on the worker's stack: the blocks' bounds share cache lines
                for (std::size_t i = b * kScratchBlock; i < std::min(n, (b + 1) * kScratchBlock); ++i) {
                    const unsigned char* side = !foreign_ ? nullptr
                                                : records ? records + i * stride
                                                          : foreign_->record(first + i);
                    const std::array<std::int32_t, 3> xyz = record_.quantize(points[i], first + i, side);
                    local.widen(xyz);
                    packing_.packQuantized(points[i], xyz, packed.data() + i * size);
                }
                bounds[b] = local;
            });
            for (const Bounds& b : bounds) {
                spilled_bounds_.widen(b.lo);
                spilled_bounds_.widen(b.hi);
            }
            count_ += n;
            waitSpillWrite();
            if (setup_.threads == 0)
                spill_->write(packed.data(), packed.size());
            else
                spill_write_ =
                    std::async(std::launch::async, [this, &packed] { spill_->write(packed.data(), packed.size()); });
            spill_next_ ^= 1;
            points = points.subspan(n);
            if (records) records += n * stride;
        }
    }

    // The spilled points' bytes kept in memory: the bound less the fixed part, and less
    // what the histogram (an eighth of the rest at most), the bucket buffers and the
    // rounds of points read back (two being sorted, one a thread for the histogram) take
    // while the spill is read. The memory is freed before the parts are built.
    std::size_t spillHeadBytes() const {
        if (copc_.memory_bytes == 0) return 0;
        const std::uint64_t fixed = copcFixedBytes(setup_.threads, setup_.cap);
        const std::uint64_t room = copc_.memory_bytes > fixed ? copc_.memory_bytes - fixed : 0;
        const std::uint64_t parts = std::uint64_t(setup_.threads) + 1;
        const std::uint64_t reading = room / 8 + kBucketsAtOnce * kBucketBufferBytes +
                                      3 * parts * kScratchBlock * (packing_.size() + sizeof(std::uint32_t));
        return std::size_t(room > reading ? room - reading : 0);
    }

    // Waits for the spill's last round to be written (and rethrows its error).
    void waitSpillWrite() {
        if (spill_write_.valid()) spill_write_.get();
    }

    void finishInMemory() {
        // The points' integer coordinates, as the records will hold them.
        std::vector<std::array<std::int32_t, 3>> xyz(count_);
        for (std::size_t i = 0; i < count_; ++i) {
            xyz[i] = record_.quantize(point(i), i, foreign_ ? foreign_->record(i) : nullptr);
            for (std::size_t k = 0; k < 3; ++k) {
                lo_[k] = i ? std::min(lo_[k], xyz[i][k]) : xyz[i][k];
                hi_[k] = i ? std::max(hi_[k], xyz[i][k]) : xyz[i][k];
            }
        }
        const OctreeCube cube = enclosingCube(lo_, hi_);
        std::vector<OctreeNode> nodes = buildOctree(xyz, cube, setup_.cap, setup_.threads);
        Assembler out(record_, file_);
        compressNodes(
            setup_, nodes,
            [&](std::uint32_t p, laszip_point_struct& q, LasInventory& inventory) {
                record_.fillQuantized(q, point(p), xyz[p], &inventory, foreign_ ? foreign_->record(p) : nullptr);
            },
            [&](const OctreeNode& node, const LaszipFile& f, const LasInventory& inv) {
                if (node.points.empty())
                    out.addEmpty(node.key);
                else
                    out.add(node.key, f, node.points.size(), inv);
            });
        out.finish(cube);
    }

    // Out of core: the points are in spill_ in input order; their bounds are known. The
    // steps 1 to 5 of the file's opening comment.
    void finishSpilled() {
        waitSpillWrite();
        std::vector<unsigned char>().swap(spill_bytes_[0]);
        std::vector<unsigned char>().swap(spill_bytes_[1]);
        lo_ = spilled_bounds_.lo;
        hi_ = spilled_bounds_.hi;
        const OctreeCube cube = enclosingCube(lo_, hi_);
        tree_.plan(setup_, cube, copc_.memory_bytes);
        tree_.countSpill(setup_, *spill_, count_, cube);
        tree_.build(setup_, cube);
        sortSpill(setup_, tree_, *spill_, count_, cube);
        spill_.reset();  // every point is in a bucket now
        finishParts(cube);
    }

    // Once every point is in its bucket's file: the buckets' subtrees, the top and the file.
    void finishParts(const OctreeCube& cube) {
        TopSets sets(setup_);
        platform::ScratchFile chunks = setup_.scratchFile();
        const LasInventory inventory = buildBuckets(setup_, tree_, cube, sets, chunks);
        Marks marks;
        sets.sample(tree_, cube, 0, marks);
        // The file, in depth-first order.
        Assembler out(record_, file_);
        chunks.rewind();
        PartsOutput(setup_, tree_, sets, chunks).write(out);
        out.count(inventory);
        out.finish(cube);
    }

    // The histogram's pass of the prescan begins: the root cube from the points' integer
    // bounds, the parts planned.
    void startHistogram(const std::array<std::int32_t, 3>& lo, const std::array<std::int32_t, 3>& hi) {
        lo_ = lo;
        hi_ = hi;
        tree_.plan(setup_, enclosingCube(lo_, hi_), copc_.memory_bytes);
        prescanned_ = 0;
        prescan_bounds_ = Bounds{};
        prescan_ = Prescan::Histogram;
    }

    // After the prescan: the top of the tree from the histogram, and one file a bucket
    // open for the points as they are appended, or, with more buckets than that, the
    // usual way (the points held, then spilled).
    void startDirect() {
        if (prescanned_ != prescan_points_)
            throw Error(record_.where() + ": the prescan's last pass gave " + std::to_string(prescanned_) +
                        " points of " + std::to_string(prescan_points_));
        if (prescan_bounds_.lo != lo_ || prescan_bounds_.hi != hi_)
            throw Error(record_.where() + ": the bounds given for the prescan are not the points' own");
        tree_.build(setup_, enclosingCube(lo_, hi_));
        if (tree_.buckets.size() > kBucketsAtOnce) {
            tree_.clear();
            prescan_ = Prescan::Declined;
            return;
        }
        direct_ = std::make_unique<DirectSort>(setup_, tree_, lo_, hi_, prescan_points_);
        prescan_ = Prescan::Direct;
    }

    bool within(const std::array<std::int32_t, 3>& xyz) const {
        for (std::size_t k = 0; k < 3; ++k)
            if (xyz[k] < lo_[k] || xyz[k] > hi_[k]) return false;
        return true;
    }

    void finishDirect() {
        direct_->finish();
        direct_.reset();
        finishParts(enclosingCube(lo_, hi_));
    }

    LasRecord record_;
    PointPacking packing_;  // the scratch files' points, quantized
    std::FILE* file_;
    CopcOptions copc_;
    WriterSetup setup_;
    std::vector<std::vector<CloudPoint>> blocks_;
    std::size_t count_ = 0;
    std::array<std::int32_t, 3> lo_{}, hi_{};
    // Out of core.
    std::unique_ptr<Spill> spill_;
    Bounds spilled_bounds_;
    std::array<std::vector<unsigned char>, 2> spill_bytes_;  // rounds packed, being written
    std::size_t spill_next_ = 0;                             // the one to pack into next
    std::future<void> spill_write_;                          // declared after what it writes, so waited for first
    PartTree tree_;
    // The prescan (prescanPasses): its passes, then the points sorted as they come.
    enum class Prescan { None, Bounds, Histogram, Direct, Declined };
    Prescan prescan_ = Prescan::None;
    int prescan_pass_ = 0;  // the pass being given
    std::uint64_t prescan_points_ = 0, prescanned_ = 0;
    Bounds prescan_bounds_;
    std::unique_ptr<DirectSort> direct_;
    std::unique_ptr<ForeignStore> foreign_;  // a foreign file's side records, by input index
};

}  // namespace

std::unique_ptr<FormatWriter> openCopcWriter(platform::TempFile& file, const glm::dvec3& origin,
                                             const core::CloudFields& fields, const LasOptions& las,
                                             const CopcOptions& copc) {
    LasRecord record("output: " + file.destination().string(), origin, fields, las, LasRecord::Scales::One);
    return std::make_unique<CopcWriter>(file, std::move(record), fields, las, copc);
}

}  // namespace io::detail

namespace io {

std::uint64_t copcBytesPerPoint() {
    // The point, its integer coordinates, its index in the octree (split twice over while
    // a node's parts are built) and the sampling's copies.
    return sizeof(core::CloudPoint) + 12 + 3 * sizeof(std::uint32_t);
}

std::uint64_t copcFixedBytes(int threads, std::uint32_t max_node_points) {
    // Per thread: its sampling marks, the bytes of the node it compresses, and its share of
    // the compressed nodes not yet written.
    const std::uint64_t cap = std::max<std::uint32_t>(max_node_points, 1);
    const std::uint64_t per_thread =
        (std::uint64_t(1) << 21) * sizeof(std::uint32_t) +
        (1 + detail::copc_writer::kCapsPerThread) * cap * detail::copc_writer::kCompressedBytesPerPoint;
    return std::uint64_t(std::max(threads, 0) + 1) * per_thread;
}

std::uint64_t copcMinimumBytes(int threads, std::uint32_t max_node_points) {
    const std::uint64_t cap = std::max<std::uint32_t>(max_node_points, 1);
    const std::uint64_t per_point = copcBytesPerPoint() + sizeof(detail::copc_writer::Spilled);
    return copcFixedBytes(threads, max_node_points) + 2 * per_point * (cap + 1) * 8 / 7 + (1u << 20);
}

void writeCopc(const std::filesystem::path& path, const core::PointCloud& cloud, const LasOptions& las,
               const CopcOptions& copc) {
    platform::checkWritableDestination(path);
    if (!std::isfinite(cloud.origin.x) || !std::isfinite(cloud.origin.y) || !std::isfinite(cloud.origin.z))
        throw core::Error("output: " + path.string() + ": the cloud origin is not finite");
    platform::TempFile temp(path);
    {
        // A cloud read with its side records (one a point) writes them back.
        const bool foreign =
            cloud.foreign && cloud.foreign->records.size() == cloud.points.size() * cloud.foreign->header.stride();
        LasOptions with = las;
        if (foreign) with.foreign = std::make_shared<const core::ForeignHeader>(cloud.foreign->header);
        const std::unique_ptr<detail::FormatWriter> writer =
            detail::openCopcWriter(temp, cloud.origin, cloud.fields, with, copc);
        if (foreign)
            writer->appendForeign(cloud.points, cloud.foreign->records.data());
        else
            writer->append(cloud.points);
        try {
            writer->finish();
        } catch (...) {
            temp.discard();
            throw;
        }
    }
    temp.commit();
}

}  // namespace io
