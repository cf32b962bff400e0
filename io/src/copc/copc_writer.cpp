// io/src/copc/copc_writer.cpp: COPC output (io/copc_writer.hpp).
//
// The layout: the 375-byte LAS 1.4 header; the `copc` info VLR (record 1, 160 bytes) at
// offset 375; LASzip's VLRs (the LASzip VLR with chunk size UINT32_MAX, the extra bytes
// VLR when there are extra bytes); the 8-byte position of the chunk table; one LAZ chunk
// per node with points, in the octree's depth-first order; the variable chunk table
// (point and byte counts, laz_chunk_table.cpp); the `copc` hierarchy EVLR (record 1000)
// holding every hierarchy page (copc_hierarchy.hpp), the root page first. The header
// and the VLRs LASzip makes come from a file LASzip writes with no points; each node's
// chunk is cut out of a file LASzip writes for that node alone, in memory, on a worker.
#include "copc_hierarchy.hpp"
#include "copc_octree.hpp"
#include "format_writer.hpp"
#include "las/laz_chunk_table.hpp"
#include "las/laz_compress.hpp"

#include <core/error.hpp>
#include <io/copc_writer.hpp>
#include <io/point_packing.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>
#include <platform/scratch_file.hpp>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <span>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace io::detail {

using core::CloudPoint;
using core::Error;

namespace {

constexpr std::size_t kHeaderSize = 375;
constexpr std::size_t kVlrHeaderSize = 54;
constexpr std::size_t kEvlrHeaderSize = 60;
constexpr std::size_t kInfoSize = 160;
constexpr double kScale_m = 0.001;
constexpr laszip_U32 kVariableChunks = std::numeric_limits<laszip_U32>::max();
// Bytes of records gathered per bucket before they are written, and the buckets filled at
// once (16 MiB).
constexpr std::size_t kBucketBufferBytes = std::size_t(1) << 16;
constexpr std::size_t kBucketsAtOnce = 256;
// Nodes compressed at once per thread before they are written in order (nodes a caller
// of CopcNodeWriter made).
constexpr std::size_t kNodesPerThread = 4;
// The nodes the writer makes: per thread, the compressed bytes of this many nodes of the
// cap's points at most (kCompressedBytesPerPoint) are held at once, besides the nodes
// being compressed.
constexpr std::size_t kCapsPerThread = 2;
// A compressed node's bytes per point, at most (as the LAZ writer's chunks).
constexpr std::uint64_t kCompressedBytesPerPoint = 24;
// Out of core, the upper levels' counts come from a histogram of the points over the
// cells of one level: this one (128^3 cells, 16 MiB of counts) at most, and at most an
// eighth of the memory bound.
constexpr int kHistogramLevel = 7;

template <typename T>
void put(std::string& s, T v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);  // x86-64 and aarch64 are little-endian, as LAS is
    s.append(b, sizeof v);
}

// A VLR or EVLR header: reserved, user id "copc", record id, length, description.
std::string recordHeader(std::uint16_t record_id, std::uint64_t length, const char* description, bool extended) {
    std::string h;
    put(h, std::uint16_t(0));
    char user[16] = "copc";
    h.append(user, sizeof user);
    put(h, record_id);
    if (extended)
        put(h, length);
    else
        put(h, std::uint16_t(length));
    char text[32] = {};
    std::memcpy(text, description, std::min<std::size_t>(std::strlen(description), 31));
    h.append(text, sizeof text);
    return h;
}

// Writes the file around the chunks handed to it in file order: the header and VLRs at
// construction, each chunk as it comes, then the table, the hierarchy and the header fields.
class Assembler {
  public:
    Assembler(const LasRecord& record, std::FILE* file, const glm::dvec3& origin)
        : record_(record), file_(file), origin_(origin) {
        // The header and VLRs: LASzip's, with the info VLR first.
        LasInventory none;
        const LaszipFile empty = compressWithLaszip(record_, {}, 0, none, kVariableChunks);
        laszip_header_ = empty.bytes.substr(0, empty.point_data_at);
        empty_table_ = empty.bytes.substr(empty.point_data_at + 8);  // LASzip's table of no chunks
        if (laszip_header_.size() < kHeaderSize)
            throw Error(record_.where() + ": LASzip wrote a LAZ layout this writer does not know");
        header_ = laszip_header_.substr(0, kHeaderSize);
        header_ += recordHeader(1, kInfoSize, "copc info", false);
        header_.append(kInfoSize, '\0');  // filled in at the end
        header_ += laszip_header_.substr(kHeaderSize);
        patch(header_, 96, std::uint32_t(header_.size()));  // offset to point data
        std::uint32_t vlrs = 0;
        std::memcpy(&vlrs, header_.data() + 100, 4);
        patch(header_, 100, vlrs + 1);
        write(header_.data(), header_.size());
        const std::int64_t placeholder = 0;  // the chunk table's position
        write(&placeholder, 8);
        at_ = header_.size() + 8;
    }

    /// The chunk of one node cut out of the file LASzip wrote for it.
    void add(const CopcKey& key, const LaszipFile& f, std::size_t points, const LasInventory& inventory) {
        const std::size_t begin = f.point_data_at + 8;
        if (f.bytes.compare(0, begin - 8, laszip_header_) != 0)
            throw Error(record_.where() + ": LASzip wrote a chunk under a different header");
        addBytes(key, f.bytes.data() + begin, f.table_at - begin, points, inventory);
    }

    void addBytes(const CopcKey& key, const char* data, std::size_t size, std::size_t points,
                  const LasInventory& inventory) {
        if (size >= 0x80000000u || points >= 0x80000000u)
            throw Error(record_.where() + ": a COPC node of 2 GiB or 2^31 points or more");
        write(data, size);
        entries_.push_back({key, at_, std::int32_t(size), std::int32_t(points)});
        at_ += size;
        chunk_points_.push_back(std::uint32_t(points));
        chunk_bytes_.push_back(std::uint32_t(size));
        inventory_.merge(inventory);
    }

    /// Counts records whose chunks came through addBytes() uncounted.
    void count(const LasInventory& inventory) { inventory_.merge(inventory); }

    /// A node whose points all went to its ancestors.
    void addEmpty(const CopcKey& key) { entries_.push_back({key, 0, 0, 0}); }

    void finish(const OctreeCube& cube) {
        const std::uint64_t table_at = at_;
        const std::string table =
            chunk_bytes_.empty() ? empty_table_ : lazVariableChunkTable(chunk_points_, chunk_bytes_);
        write(table.data(), table.size());
        at_ += table.size();
        // The hierarchy EVLR.
        const std::uint64_t evlr_at = at_;
        const HierarchyPages pages = encodeHierarchy(std::move(entries_), evlr_at + kEvlrHeaderSize);
        const std::string evlr = recordHeader(1000, pages.bytes.size(), "copc hierarchy", true);
        write(evlr.data(), evlr.size());
        write(pages.bytes.data(), pages.bytes.size());
        // The info VLR, the table's position, the EVLR's place, the counts and bounds.
        std::string info;
        const double halfsize_m = kScale_m * std::ldexp(1.0, cube.bits - 1);
        const double o[3] = {origin_.x, origin_.y, origin_.z};
        for (std::size_t k = 0; k < 3; ++k) put(info, o[k] + kScale_m * (double(cube.corner[k]) - 0.5) + halfsize_m);
        put(info, halfsize_m);
        put(info, 2.0 * halfsize_m / 128.0);
        put(info, evlr_at + kEvlrHeaderSize);
        put(info, pages.root_size);
        put(info, inventory_.gps_min_s);
        put(info, inventory_.gps_max_s);
        info.append(kInfoSize - info.size(), '\0');
        if (std::fflush(file_) != 0) throw Error(record_.where() + ": write failed: " + std::strerror(errno));
        const int fd = fileno(file_);
        pwriteAll(fd, info.data(), info.size(), kHeaderSize + kVlrHeaderSize);
        const std::int64_t position = std::int64_t(table_at);
        pwriteAll(fd, &position, 8, header_.size());
        std::string evlr_fields;
        put(evlr_fields, evlr_at);
        put(evlr_fields, std::uint32_t(1));
        pwriteAll(fd, evlr_fields.data(), evlr_fields.size(), 235);
        record_.patchHeader(fd, inventory_);
    }

  private:
    static void patch(std::string& s, std::size_t at, std::uint32_t v) { std::memcpy(s.data() + at, &v, 4); }

    void pwriteAll(int fd, const void* data, std::size_t size, std::uint64_t at) const {
        if (::pwrite(fd, data, size, off_t(at)) != ssize_t(size))
            throw Error(record_.where() + ": write failed: " + std::strerror(errno));
    }

    void write(const void* data, std::size_t size) {
        if (size > 0 && std::fwrite(data, 1, size, file_) != size)
            throw Error(record_.where() + ": write failed: " + std::strerror(errno));
    }

    const LasRecord& record_;
    std::FILE* file_;
    glm::dvec3 origin_;
    std::string laszip_header_, empty_table_, header_;
    std::uint64_t at_ = 0;
    std::vector<CopcNode> entries_;
    std::vector<std::uint32_t> chunk_points_, chunk_bytes_;
    LasInventory inventory_;
};

// The spilled points: their first bytes in memory (as many as the bound leaves beside the
// histogram and the sort into parts), the rest in a scratch file. What stays in memory
// is neither written to the disk nor copied back through the kernel.
class Spill {
  public:
    Spill(const std::filesystem::path& dir, const std::string& where, std::size_t head_bytes)
        : dir_(dir), where_(where), capacity_(head_bytes) {
        head_.reserve(capacity_);  // address space only: pages are taken as they are written
    }
    // Appends; one thread at a time, and none reading.
    void write(const void* data, std::size_t size) {
        const auto* bytes = static_cast<const unsigned char*>(data);
        const std::size_t here = std::min(size, capacity_ - head_.size());
        head_.insert(head_.end(), bytes, bytes + here);
        head_size_ = head_.size();
        if (size == here) return;
        if (!tail_) tail_ = std::make_unique<platform::ScratchFile>(dir_, where_);
        tail_->append(bytes + here, size - here);
    }
    // Makes what was written readable by readAt().
    void flush() {
        if (tail_) tail_->flush();
    }
    // Reads `size` bytes at `offset`; several threads may read at once.
    void readAt(void* data, std::size_t size, std::uint64_t offset) {
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
            if (!tail_) throw Error("output: " + where_ + ": reading past the spilled points");
            tail_->readAt(bytes, size, offset - head);
        }
    }
    // Frees [0, end), read for the last time (the memory once all of it is passed; the
    // file's pages as ScratchFile::discardBefore does). A reader may meanwhile read past `end`.
    void discardBefore(std::uint64_t end) {
        const std::uint64_t head = head_size_;
        if (tail_ && end > head) tail_->discardBefore(end - head);
        if (end >= head) std::vector<unsigned char>().swap(head_);  // readers past `end` read the tail
    }

  private:
    std::filesystem::path dir_;
    std::string where_;
    std::size_t capacity_;
    std::vector<unsigned char> head_;
    std::size_t head_size_ = 0;  // what the head holds (stays when its memory is freed)
    std::unique_ptr<platform::ScratchFile> tail_;
};

// A point spilled to a bucket: the point and its index in the input.
struct Spilled {
    CloudPoint point;
    std::uint64_t index;
};

// A point of an upper node's set, kept in a scratch file: the point (its position left at
// its default: the integer coordinates stand for it), its index in the input and its
// integer coordinates.
struct Lifted {
    Spilled spilled;
    std::array<std::int32_t, 3> xyz;
};

class CopcWriter final : public FormatWriter {
  public:
    CopcWriter(platform::TempFile& file, LasRecord record, const glm::dvec3& origin, const core::CloudFields& fields,
               const LasOptions& las, const CopcOptions& copc)
        : record_(std::move(record)),
          packing_(fields, PointPacking::Position::Quantized),
          file_(file.file()),
          dir_(file.destination().parent_path().empty() ? std::filesystem::path(".")
                                                        : file.destination().parent_path()),
          where_(file.destination().string()),
          origin_(origin),
          las_(las),
          copc_(copc) {
        threads_ = std::max(las_.threads, 0);
        cap_ = std::max<std::uint32_t>(copc_.max_node_points, 1);
    }

    // The points are held in blocks, so that the store never reallocates (a vector that
    // doubles would hold up to three times the points while it grows). Past
    // CopcOptions::memory_bytes they go to a scratch file instead.
    void append(std::span<const CloudPoint> points) override {
        if (prescan_ == Prescan::Histogram) startDirect();
        if (prescan_ == Prescan::Direct) {
            directAppend(points);
            return;
        }
        if (prescan_ != Prescan::None && prescan_ != Prescan::Declined)
            throw Error(record_.where() + ": points appended before the prescan's two passes ended");
        if (spill_) {
            spillAppend(points);
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
            count_ * copcBytesPerPoint() + copcFixedBytes(threads_, cap_) > copc_.memory_bytes) {
            spill_ = std::make_unique<Spill>(dir_, where_, spillHeadBytes());
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
        if (prescan_ != Prescan::None || count_ > 0 || spill_) return 0;
        if (copc_.memory_bytes == 0 || points == 0 || points >= std::numeric_limits<std::uint32_t>::max() ||
            points * copcBytesPerPoint() + copcFixedBytes(threads_, cap_) <= copc_.memory_bytes)
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
        parallelFor(blocks, threads_, [&](std::size_t b, std::size_t) {
            CellCounter counter{hist_};
            Bounds& local = seen[b];
            Bounds mine;  // on the worker's stack: the blocks' bounds share cache lines
            for (std::size_t i = b * kScratchBlock; i < std::min(points.size(), (b + 1) * kScratchBlock); ++i) {
                const std::array<std::int32_t, 3> xyz = record_.quantize(points[i], first + i);
                mine.widen(xyz);
                if (bounds) continue;
                if (!within(xyz))
                    throw Error(record_.where() + ": point " + std::to_string(first + i) +
                                " lies outside the bounds of the points prescanned");
                counter.add(histCell(cube, xyz));
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
    // Points a scratch file is read or written by at once.
    static constexpr std::size_t kScratchBlock = std::size_t(1) << 16;
    static constexpr std::size_t kBlockPoints = std::size_t(1) << kBlockBits;

    const CloudPoint& point(std::size_t i) const { return blocks_[i >> kBlockBits][i & (kBlockPoints - 1)]; }

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

    // Packs the points on the threads, a block of kScratchBlock points each, with the
    // integer coordinates their records will hold in place of their positions (what every
    // later pass reads: none converts a position again), and writes
    // each round of blocks to the spill on a thread of its own while the next round is
    // packed. The two rounds' bytes (at most 2 x 2^16 x 39 bytes a thread) fit in what the
    // bound sets aside for the octree's parts, unused until the spill is read back: the
    // points held in memory before the spill take 40 of the 64 bytes counted for each.
    void spillAppend(std::span<const CloudPoint> points) {
        const std::size_t size = packing_.size();
        const std::size_t parts = std::size_t(threads_) + 1;
        while (!points.empty()) {
            const std::size_t n = std::min(points.size(), kScratchBlock * parts);
            const std::size_t blocks = (n + kScratchBlock - 1) / kScratchBlock;
            std::vector<unsigned char>& packed = spill_bytes_[spill_next_];
            packed.resize(n * size);
            std::vector<Bounds> bounds(blocks);
            const std::uint64_t first = count_;
            parallelFor(blocks, threads_, [&](std::size_t b, std::size_t) {
                Bounds local;  // on the worker's stack: the blocks' bounds share cache lines
                for (std::size_t i = b * kScratchBlock; i < std::min(n, (b + 1) * kScratchBlock); ++i) {
                    const std::array<std::int32_t, 3> xyz = record_.quantize(points[i], first + i);
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
            if (threads_ == 0)
                spill_->write(packed.data(), packed.size());
            else
                spill_write_ =
                    std::async(std::launch::async, [this, &packed] { spill_->write(packed.data(), packed.size()); });
            spill_next_ ^= 1;
            points = points.subspan(n);
        }
    }

    // The spilled points' bytes kept in memory: the bound less the fixed part, and less
    // what the histogram (an eighth of the rest at most), the bucket buffers and the
    // rounds of points read back (two being sorted, one a thread for the histogram) take
    // while the spill is read. The memory is freed before the parts are built.
    std::size_t spillHeadBytes() const {
        if (copc_.memory_bytes == 0) return 0;
        const std::uint64_t fixed = copcFixedBytes(threads_, cap_);
        const std::uint64_t room = copc_.memory_bytes > fixed ? copc_.memory_bytes - fixed : 0;
        const std::uint64_t parts = std::uint64_t(threads_) + 1;
        const std::uint64_t reading = room / 8 + kBucketsAtOnce * kBucketBufferBytes +
                                      3 * parts * kScratchBlock * (packing_.size() + sizeof(std::uint32_t));
        return std::size_t(room > reading ? room - reading : 0);
    }

    // Waits for the spill's last round to be written (and rethrows its error).
    void waitSpillWrite() {
        if (spill_write_.valid()) spill_write_.get();
    }

    // Compresses `nodes` on the threads, handing each to `done` in order on the calling
    // thread; `fillRecord(p, q, inventory)` fills LASzip's record `q` with point `p` and
    // counts it. A node being compressed holds at most kCompressedBytesPerPoint a point
    // (its records are filled one at a time); once compressed, its bytes until it is handed
    // on. Together they stay within the threads' share of copcFixedBytes.
    template <typename FillRecord, typename Done>
    void compressNodes(std::vector<OctreeNode>& nodes, FillRecord fillRecord, Done done) {
        const std::size_t per_point = kCompressedBytesPerPoint;
        const std::size_t window =
            (1 + kCapsPerThread) * kCompressedBytesPerPoint * std::size_t(cap_) * std::size_t(threads_ + 1);
        std::vector<LaszipFile> files(nodes.size());
        std::vector<LasInventory> counted(nodes.size());
        orderedParallel(
            nodes.size(), threads_, window,
            [&](std::size_t i) {
                const OctreeNode& node = nodes[i];
                if (node.points.empty()) return;
                LaszipMemoryWriter zip(record_, kVariableChunks);
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

    void finishInMemory() {
        // The points' integer coordinates, as the records will hold them.
        std::vector<std::array<std::int32_t, 3>> xyz(count_);
        for (std::size_t i = 0; i < count_; ++i) {
            xyz[i] = record_.quantize(point(i), i);
            for (std::size_t k = 0; k < 3; ++k) {
                lo_[k] = i ? std::min(lo_[k], xyz[i][k]) : xyz[i][k];
                hi_[k] = i ? std::max(hi_[k], xyz[i][k]) : xyz[i][k];
            }
        }
        const OctreeCube cube = enclosingCube(lo_, hi_);
        std::vector<OctreeNode> nodes = buildOctree(xyz, cube, cap_, threads_);
        Assembler out(record_, file_, origin_);
        compressNodes(
            nodes,
            [&](std::uint32_t p, laszip_point_struct& q, LasInventory& inventory) {
                record_.fillQuantized(q, point(p), xyz[p], &inventory);
            },
            [&](const OctreeNode& node, const LaszipFile& f, const LasInventory& inv) {
                if (node.points.empty())
                    out.addEmpty(node.key);
                else
                    out.add(node.key, f, node.points.size(), inv);
            });
        out.finish(cube);
    }

    // The top of the tree, above the buckets that are built in memory one at a time.
    struct Top {
        CopcKey key;
        std::uint64_t count = 0;
        std::array<int, 8> child{-1, -1, -1, -1, -1, -1, -1, -1};  // into tops_
        int bucket = -1;                                           // a bucket's root, else -1
        // Its points: a run of Lifted records in sets_, ascending by input index.
        std::uint64_t set_at = 0, set_n = 0;
    };
    struct Bucket {
        int top = -1;  // its node in tops_
        std::unique_ptr<platform::ScratchFile> file;
        std::uint64_t count = 0;   // from the histogram
        std::uint64_t filled = 0;  // points sorted into its file
        // Its nodes below its root, compressed: key, place in chunks_, size, points.
        struct Chunk {
            CopcKey key;
            std::uint64_t at = 0, size = 0, points = 0;
        };
        std::vector<Chunk> chunks;
    };

    // Out of core: the points are in spill_ in input order; their bounds are known.
    //  1. A histogram of the points over the cells of a fixed level (at most 128^3) gives
    //     every upper node's count, hence the top of the tree: the nodes that split (more
    //     than the cap) and hold more than a bucket may; their children are the buckets.
    //  2. One pass over the spill (or more, 256 buckets at a time) sorts the points into
    //     one scratch file per bucket, in input order, each with its input index.
    //  3. Each bucket's subtree is built in memory as the in-memory writer builds it; its
    //     nodes below its root are compressed into a scratch file of chunks, and its
    //     root's points go to a scratch file of sets, in input order, for the top.
    //  4. The top nodes sample their children's points bottom-up, as in memory, each
    //     streaming its children's sets from the scratch file (so memory holds one node's
    //     chosen points, never the whole top of the tree).
    //  5. The file is written in the in-memory writer's depth-first order, the buckets'
    //     chunks copied from the scratch file: the same file, byte for byte.
    void finishSpilled() {
        waitSpillWrite();
        std::vector<unsigned char>().swap(spill_bytes_[0]);
        std::vector<unsigned char>().swap(spill_bytes_[1]);
        lo_ = spilled_bounds_.lo;
        hi_ = spilled_bounds_.hi;
        const OctreeCube cube = enclosingCube(lo_, hi_);
        planParts(cube);
        histogram(cube);
        makeTop(cube, CopcKey{});
        distribute(cube);
        finishParts(cube);
    }

    // The histogram's level and the buckets' size, from the bound; throws when the bound
    // leaves no room for a bucket of one node.
    void planParts(const OctreeCube& cube) {
        const std::uint64_t fixed = copcFixedBytes(threads_, cap_);
        const std::uint64_t per_point = copcBytesPerPoint() + sizeof(Spilled);
        const std::uint64_t room = copc_.memory_bytes > fixed ? copc_.memory_bytes - fixed : 0;
        hist_level_ = 1;
        while (hist_level_ < kHistogramLevel && (std::uint64_t(8) << (3 * (hist_level_ + 1))) <= room / 8)
            ++hist_level_;
        hist_level_ = std::min(cube.bits, hist_level_);
        const std::uint64_t hist_bytes = std::uint64_t(8) << (3 * hist_level_);
        // Half: the other half holds a top node's chosen points and the set buffers.
        bucket_points_ = (room - std::min(room, hist_bytes)) / per_point / 2;
        if (bucket_points_ <= cap_)
            throw Error(record_.where() + ": a memory bound of " + std::to_string(copc_.memory_bytes >> 20) +
                        " MiB leaves no room for a node of " + std::to_string(cap_) + " points; allowed at least " +
                        std::to_string(copcMinimumBytes(threads_, cap_) >> 20) + " MiB");
    }

    // Once every point is in its bucket's file: the buckets' subtrees, the top and the file.
    void finishParts(const OctreeCube& cube) {
        sets_ = std::make_unique<platform::ScratchFile>(dir_, where_);
        buildBuckets(cube);
        Marks marks;
        sampleTop(cube, 0, marks);
        // The file, in depth-first order.
        Assembler out(record_, file_, origin_);
        chunks_->rewind();
        orderTops(0);
        emit(out, 0);
        out.count(inventory_);
        out.finish(cube);
    }

    // Counts a thread's points into the histogram. Points in scan order fall in the same
    // cell for long runs: one atomic add a run.
    struct CellCounter {
        std::vector<std::uint64_t>& hist;
        std::size_t cell = 0;
        std::uint64_t run = 0;
        void add(std::size_t c) {
            if (run > 0 && c != cell) flush();
            cell = c;
            ++run;
        }
        void flush() {
            if (run > 0) std::atomic_ref<std::uint64_t>(hist[cell]).fetch_add(run, std::memory_order_relaxed);
            run = 0;
        }
    };

    std::size_t histCell(const OctreeCube& cube, const std::array<std::int32_t, 3>& xyz) const {
        const int shift = cube.bits - hist_level_;
        std::size_t cell = 0;
        for (std::size_t k = 0; k < 3; ++k)
            cell |= std::size_t((std::int64_t(xyz[k]) - cube.corner[k]) >> shift) << (std::size_t(hist_level_) * k);
        return cell;
    }

    // Counts the points per cell of the histogram's level, the spill's blocks shared among
    // the threads.
    void histogram(const OctreeCube& cube) {
        hist_.assign(std::size_t(1) << (3 * hist_level_), 0);
        spill_->flush();
        const std::size_t size = packing_.size();
        std::vector<std::vector<unsigned char>> bytes(std::size_t(threads_) + 1);
        const std::size_t blocks = std::size_t((count_ + kScratchBlock - 1) / kScratchBlock);
        parallelFor(blocks, threads_, [&](std::size_t block, std::size_t worker) {
            const std::uint64_t first = std::uint64_t(block) * kScratchBlock;
            const std::size_t n = std::size_t(std::min<std::uint64_t>(kScratchBlock, count_ - first));
            std::vector<unsigned char>& b = bytes[worker];
            b.resize(n * size);
            spill_->readAt(b.data(), b.size(), first * size);
            CellCounter counter{hist_};
            for (std::size_t i = 0; i < n; ++i)
                counter.add(histCell(cube, PointPacking::quantized(b.data() + i * size)));
            counter.flush();
        });
    }

    std::uint64_t countOf(const CopcKey& key) const {
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

    int makeTop(const OctreeCube& cube, const CopcKey& key) {
        const std::uint64_t n = countOf(key);
        const int index = int(tops_.size());
        tops_.push_back(Top{key, n, {-1, -1, -1, -1, -1, -1, -1, -1}, -1, 0, 0});
        if (n <= cap_ || key.level >= cube.bits || n <= bucket_points_) {
            tops_[std::size_t(index)].bucket = int(buckets_.size());
            buckets_.push_back(Bucket{index, nullptr, n, 0, {}});
            return index;
        }
        if (key.level >= hist_level_)
            throw Error(record_.where() + ": " + std::to_string(n) + " points lie within " +
                        std::to_string(std::ldexp(kScale_m, cube.bits - key.level)) +
                        " m of each other, more than the memory bound lets one part of the octree hold; raise it");
        for (int o = 0; o < 8; ++o) {
            const CopcKey c{key.level + 1, 2 * key.x + (o & 1), 2 * key.y + ((o >> 1) & 1), 2 * key.z + ((o >> 2) & 1)};
            if (countOf(c) == 0) continue;
            const int child = makeTop(cube, c);
            tops_[std::size_t(index)].child[std::size_t(o)] = child;
        }
        return index;
    }

    // The bucket a point goes to: down the top from the root by its histogram cell.
    int bucketOf(const OctreeCube& cube, const std::array<std::int32_t, 3>& xyz) const {
        int t = 0;
        for (;;) {
            const Top& top = tops_[std::size_t(t)];
            if (top.bucket >= 0) return top.bucket;
            const int shift = cube.bits - top.key.level - 1;
            int o = 0;
            for (std::size_t k = 0; k < 3; ++k) o |= int(((std::int64_t(xyz[k]) - cube.corner[k]) >> shift) & 1) << k;
            t = top.child[std::size_t(o)];
        }
    }

    // A bucket file's record: the packed point, then its index in the input (32 bits: the
    // writer holds fewer than 2^32 points).
    std::size_t bucketRecordSize() const { return packing_.size() + sizeof(std::uint32_t); }

    // Sorts the spill's points into their buckets' files, in input order. A round of
    // blocks is read and its points' buckets found on the threads while this thread
    // gathers the round before into the buckets' buffers and writes them out (two rounds
    // held at once, in the room the parts are built in later).
    void distribute(const OctreeCube& cube) {
        const std::size_t size = packing_.size();
        const std::size_t parts = std::size_t(threads_) + 1;
        const auto prepare = [&](std::uint64_t first, Round& r) {
            r.first = first;
            r.n = std::size_t(std::min<std::uint64_t>(kScratchBlock * parts, count_ - first));
            r.bytes.resize(r.n * size);
            r.bucket.resize(r.n);
            spill_->readAt(r.bytes.data(), r.bytes.size(), first * size);
            const std::size_t blocks = (r.n + kScratchBlock - 1) / kScratchBlock;
            parallelFor(blocks, threads_, [&](std::size_t b, std::size_t) {
                for (std::size_t i = b * kScratchBlock; i < std::min(r.n, (b + 1) * kScratchBlock); ++i) {
                    r.bucket[i] = std::uint32_t(bucketOf(cube, PointPacking::quantized(r.bytes.data() + i * size)));
                }
            });
        };
        std::vector<Gathered> gathered(std::min(kBucketsAtOnce, buckets_.size()));
        spill_->flush();
        for (std::size_t first = 0; first < buckets_.size(); first += kBucketsAtOnce) {
            const std::size_t last = std::min(buckets_.size(), first + kBucketsAtOnce);
            for (std::size_t b = first; b < last; ++b)
                buckets_[b].file = std::make_unique<platform::ScratchFile>(dir_, where_);
            std::array<Round, 2> rounds;
            std::size_t cur = 0;
            if (count_ > 0) prepare(0, rounds[0]);
            while (rounds[cur].n > 0) {
                Round& r = rounds[cur];
                Round& next = rounds[cur ^ 1];
                const std::uint64_t after = r.first + r.n;
                next.n = 0;
                std::future<void> ahead;
                if (after < count_) {
                    if (threads_ == 0)
                        prepare(after, next);
                    else
                        ahead = std::async(std::launch::async, [&, after] { prepare(after, next); });
                }
                gather(r, first, last, gathered);
                // One pass sorts every bucket: the spill's bytes up to here are done with.
                if (buckets_.size() <= kBucketsAtOnce) spill_->discardBefore((r.first + r.n) * size);
                if (ahead.valid()) ahead.get();
                cur ^= 1;
            }
            closeGathered(first, last, gathered);
        }
        spill_.reset();  // every point is in a bucket now
    }

    // A round of points being sorted into buckets: packed, with their buckets.
    struct Round {
        std::uint64_t first = 0;  // the input index of its first point
        std::size_t n = 0;
        std::vector<unsigned char> bytes;
        std::vector<std::uint32_t> bucket;
    };
    // A bucket's records gathered before they are written to its file.
    struct Gathered {
        std::vector<unsigned char> bytes;
        std::size_t used = 0;
    };

    // Appends the points of round `r` that fall in buckets [first, last) to their
    // buckets' buffers (`gathered`, from bucket `first` on), each with its input index,
    // writing a buffer out when it fills.
    void gather(const Round& r, std::size_t first, std::size_t last, std::vector<Gathered>& gathered) {
        const std::size_t size = packing_.size(), record = bucketRecordSize();
        for (std::size_t i = 0; i < r.n; ++i) {
            const std::uint32_t bucket = r.bucket[i];
            if (bucket < first || bucket >= last) continue;
            Gathered& g = gathered[bucket - first];
            if (g.bytes.empty()) g.bytes.resize(kBucketBufferBytes);
            if (g.used + record > g.bytes.size()) {
                buckets_[bucket].file->append(g.bytes.data(), g.used);
                g.used = 0;
            }
            unsigned char* at = g.bytes.data() + g.used;
            std::memcpy(at, r.bytes.data() + i * size, size);
            const std::uint32_t index = std::uint32_t(r.first + i);
            std::memcpy(at + size, &index, sizeof index);
            g.used += record;
            ++buckets_[bucket].filled;
        }
    }

    // Writes what buckets [first, last) still gather and rewinds their files, which stay
    // until the buckets are built one at a time.
    void closeGathered(std::size_t first, std::size_t last, std::vector<Gathered>& gathered) {
        for (std::size_t b = first; b < last; ++b) {
            Gathered& g = gathered[b - first];
            buckets_[b].file->append(g.bytes.data(), g.used);
            g.used = 0;
            buckets_[b].file->rewind();
        }
    }

    // After the prescan: the top of the tree from the histogram, and one file a bucket
    // open for the points as they are appended, or, with more buckets than that, the
    // usual way (the points held, then spilled).
    // The histogram's pass of the prescan begins: the root cube from the points' integer
    // bounds, the parts planned.
    void startHistogram(const std::array<std::int32_t, 3>& lo, const std::array<std::int32_t, 3>& hi) {
        lo_ = lo;
        hi_ = hi;
        planParts(enclosingCube(lo_, hi_));
        hist_.assign(std::size_t(1) << (3 * hist_level_), 0);
        prescanned_ = 0;
        prescan_bounds_ = Bounds{};
        prescan_ = Prescan::Histogram;
    }

    void startDirect() {
        if (prescanned_ != prescan_points_)
            throw Error(record_.where() + ": the prescan's last pass gave " + std::to_string(prescanned_) +
                        " points of " + std::to_string(prescan_points_));
        if (prescan_bounds_.lo != lo_ || prescan_bounds_.hi != hi_)
            throw Error(record_.where() + ": the bounds given for the prescan are not the points' own");
        makeTop(enclosingCube(lo_, hi_), CopcKey{});
        if (buckets_.size() > kBucketsAtOnce) {
            tops_.clear();
            buckets_.clear();
            std::vector<std::uint64_t>().swap(hist_);
            prescan_ = Prescan::Declined;
            return;
        }
        for (Bucket& b : buckets_) b.file = std::make_unique<platform::ScratchFile>(dir_, where_);
        gathered_.resize(buckets_.size());
        prescan_ = Prescan::Direct;
    }

    bool within(const std::array<std::int32_t, 3>& xyz) const {
        for (std::size_t k = 0; k < 3; ++k)
            if (xyz[k] < lo_[k] || xyz[k] > hi_[k]) return false;
        return true;
    }

    // Packs the points on the threads with their buckets, a round of kScratchBlock points
    // a thread, and gathers each round into the buckets' files on a thread of its own
    // while the caller makes the next points (two rounds held at once, as when the spill
    // is sorted).
    void directAppend(std::span<const CloudPoint> points) {
        const OctreeCube cube = enclosingCube(lo_, hi_);
        const std::size_t size = packing_.size();
        const std::size_t parts = std::size_t(threads_) + 1;
        while (!points.empty()) {
            const std::size_t n = std::min(points.size(), kScratchBlock * parts);
            if (count_ + n > prescan_points_)
                throw Error(record_.where() + ": more points appended than the " + std::to_string(prescan_points_) +
                            " prescanned");
            Round& r = direct_rounds_[direct_next_];  // the other may be being gathered
            r.first = count_;
            r.n = n;
            r.bytes.resize(n * size);
            r.bucket.resize(n);
            const std::size_t blocks = (n + kScratchBlock - 1) / kScratchBlock;
            parallelFor(blocks, threads_, [&](std::size_t b, std::size_t) {
                for (std::size_t i = b * kScratchBlock; i < std::min(n, (b + 1) * kScratchBlock); ++i) {
                    const std::array<std::int32_t, 3> xyz = record_.quantize(points[i], r.first + i);
                    if (!within(xyz))
                        throw Error(record_.where() + ": point " + std::to_string(r.first + i) +
                                    " lies outside the bounds of the points prescanned");
                    r.bucket[i] = std::uint32_t(bucketOf(cube, xyz));
                    packing_.packQuantized(points[i], xyz, r.bytes.data() + i * size);
                }
            });
            count_ += n;
            waitGather();
            if (threads_ == 0)
                gather(r, 0, buckets_.size(), gathered_);
            else
                gather_ = std::async(std::launch::async, [this, &r] { gather(r, 0, buckets_.size(), gathered_); });
            direct_next_ ^= 1;
            points = points.subspan(n);
        }
    }

    // Waits for the last round to be gathered (and rethrows its error).
    void waitGather() {
        if (gather_.valid()) gather_.get();
    }

    void finishDirect() {
        waitGather();
        if (count_ != prescan_points_)
            throw Error(record_.where() + ": " + std::to_string(count_) + " points appended of the " +
                        std::to_string(prescan_points_) + " prescanned");
        closeGathered(0, buckets_.size(), gathered_);
        std::vector<Gathered>().swap(gathered_);
        for (Round& r : direct_rounds_) r = Round{};
        for (const Bucket& b : buckets_)
            if (b.filled != b.count)
                throw Error(record_.where() + ": the points appended are not the points prescanned");
        finishParts(enclosingCube(lo_, hi_));
    }

    // A bucket read back and its subtree built, its nodes below its root waiting to be
    // compressed.
    struct LoadedBucket {
        std::size_t bucket = 0;
        std::vector<unsigned char> records;  // as in its file: packed point, input index
        std::vector<OctreeNode> nodes;
    };

    std::uint32_t recordIndex(const unsigned char* record) const {
        std::uint32_t index = 0;
        std::memcpy(&index, record + packing_.size(), sizeof index);
        return index;
    }

    // Loads bucket `b` into `loaded`, whose vectors keep their room from one bucket to the
    // next (fresh pages for every bucket cost the kernel more than the copying). The
    // points stay packed: the threads that compress a node unpack its points.
    void loadBucket(const OctreeCube& cube, std::size_t b, LoadedBucket& loaded) {
        Bucket& bucket = buckets_[b];
        Top& root = tops_[std::size_t(bucket.top)];
        loaded.bucket = b;
        const std::size_t record = bucketRecordSize(), n = std::size_t(bucket.count);
        std::vector<unsigned char>& records = loaded.records;
        records.resize(n * record);
        bucket.file->read(records.data(), records.size());
        bucket.file.reset();
        std::vector<std::array<std::int32_t, 3>>& xyz = bucket_xyz_;
        xyz.resize(n);
        parallelFor((n + kScratchBlock - 1) / kScratchBlock, threads_, [&](std::size_t block, std::size_t) {
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
        nodes = buildOctree(xyz, sub, cap_, threads_, &bucket_marks_);
        // Keys from the bucket's subtree to the whole tree's.
        for (OctreeNode& node : nodes) {
            const int l = node.key.level;
            node.key = {root.key.level + l, (root.key.x << l) + node.key.x, (root.key.y << l) + node.key.y,
                        (root.key.z << l) + node.key.z};
        }
        // The root's points go up, in input order, to the sets file; the others are final.
        {
            std::vector<std::uint32_t> up = nodes.front().points;
            const auto indexOf = [&](std::uint32_t i) { return recordIndex(records.data() + std::size_t(i) * record); };
            std::sort(up.begin(), up.end(), [&](std::uint32_t a, std::uint32_t c) { return indexOf(a) < indexOf(c); });
            std::vector<Lifted> run;
            run.reserve(up.size());
            for (std::uint32_t i : up)
                run.push_back(
                    Lifted{Spilled{packing_.unpack(records.data() + std::size_t(i) * record), indexOf(i)}, xyz[i]});
            root.set_at = sets_end_;
            root.set_n = run.size();
            appendSet(run);
        }
        nodes.erase(nodes.begin());
    }

    // Compresses a loaded bucket's nodes into the scratch file of chunks, in order.
    void compressBucket(LoadedBucket& loaded) {
        Bucket& bucket = buckets_[loaded.bucket];
        const std::size_t record = bucketRecordSize();
        const unsigned char* records = loaded.records.data();
        compressNodes(
            loaded.nodes,
            [&](std::uint32_t p, laszip_point_struct& q, LasInventory& inventory) {
                const unsigned char* r = records + std::size_t(p) * record;
                record_.fillQuantized(q, packing_.unpack(r), PointPacking::quantized(r), &inventory);
            },
            [&](const OctreeNode& node, const LaszipFile& f, const LasInventory& inv) {
                Bucket::Chunk c{node.key, chunks_at_, 0, node.points.size()};
                if (!node.points.empty()) {
                    const std::size_t begin = f.point_data_at + 8;
                    c.size = f.table_at - begin;
                    chunks_->append(f.bytes.data() + begin, c.size);
                    chunks_at_ += c.size;
                    inventory_.merge(inv);
                }
                bucket.chunks.push_back(c);
            });
    }

    // Every bucket, in order: with threads, one bucket's nodes are compressed on a thread
    // of their own while the next bucket is read back and built. Two buckets are then held
    // at once: the one being built in the half of the bound it was sized for, the one
    // being compressed (its points and their indices) in the other half, which the top of
    // the tree uses only once every bucket is done.
    void buildBuckets(const OctreeCube& cube) {
        chunks_ = std::make_unique<platform::ScratchFile>(dir_, where_);
        if (threads_ == 0) {
            LoadedBucket loaded;
            for (std::size_t b = 0; b < buckets_.size(); ++b) {
                loadBucket(cube, b, loaded);
                compressBucket(loaded);
            }
        } else {
            std::array<LoadedBucket, 2> slots;
            std::future<void> compressed;  // declared last: waited for before the slots go
            for (std::size_t b = 0; b < buckets_.size(); ++b) {
                LoadedBucket& loaded = slots[b % 2];  // the other slot may be compressing
                loadBucket(cube, b, loaded);
                if (compressed.valid()) compressed.get();
                compressed = std::async(std::launch::async, [this, &loaded] { compressBucket(loaded); });
            }
            if (compressed.valid()) compressed.get();
        }
        std::vector<std::array<std::int32_t, 3>>().swap(bucket_xyz_);
        std::vector<Marks>().swap(bucket_marks_);
    }

    void appendSet(std::span<const Lifted> run) {
        sets_->append(run.data(), run.size_bytes());
        sets_end_ += run.size_bytes();
    }

    // Streams the sets of `tops` (each ascending by input index) merged into one ascending
    // sequence, a buffer of records per set, and hands each record to `fn` with the
    // position of its set; stops early when `fn` returns false.
    template <typename Fn>
    void mergeSets(std::span<const int> tops, Fn fn) {
        constexpr std::size_t kBuffer = 4096;
        struct Cursor {
            std::uint64_t at = 0, left = 0;
            std::vector<Lifted> buf;
            std::size_t next = 0;
        };
        std::vector<Cursor> cur(tops.size());
        sets_->flush();
        const auto fill = [&](Cursor& c) {
            const std::size_t n = std::size_t(std::min<std::uint64_t>(kBuffer, c.left));
            c.buf.resize(n);
            sets_->readAt(c.buf.data(), n * sizeof(Lifted), c.at);
            c.at += n * sizeof(Lifted);
            c.left -= n;
            c.next = 0;
        };
        for (std::size_t i = 0; i < tops.size(); ++i) {
            const Top& t = tops_[std::size_t(tops[i])];
            cur[i].at = t.set_at;
            cur[i].left = t.set_n;
            fill(cur[i]);
        }
        for (;;) {
            std::size_t best = cur.size();
            for (std::size_t i = 0; i < cur.size(); ++i) {
                if (cur[i].next == cur[i].buf.size()) continue;
                if (best == cur.size() ||
                    cur[i].buf[cur[i].next].spilled.index < cur[best].buf[cur[best].next].spilled.index)
                    best = i;
            }
            if (best == cur.size()) return;
            Cursor& c = cur[best];
            if (!fn(c.buf[c.next], best)) return;
            if (++c.next == c.buf.size() && c.left > 0) fill(c);
        }
    }

    // The grid sample of an upper node, as gridSample() makes it in memory, over its
    // children's sets streamed from the scratch file: per occupied cell the point of the
    // lowest input index, the grid coarsened until at most the cap are kept. The chosen
    // points leave the children (whose sets are written anew) and become the node's set.
    void sampleTop(const OctreeCube& cube, int t, Marks& marks) {
        if (tops_[std::size_t(t)].bucket >= 0) return;
        std::vector<int> children;
        for (int c : tops_[std::size_t(t)].child)
            if (c >= 0) {
                sampleTop(cube, c, marks);
                children.push_back(c);
            }
        const CopcKey key = tops_[std::size_t(t)].key;
        const int node_bits = cube.bits - key.level;
        constexpr std::int64_t kMask = (std::int64_t(1) << kGridBits) - 1;
        std::vector<std::uint64_t> chosen;  // input indices, ascending
        for (int shift = std::max(0, node_bits - kGridBits); shift <= node_bits; ++shift) {
            marks.reset();
            chosen.clear();
            mergeSets(children, [&](const Lifted& p, std::size_t) {
                std::size_t cell = 0;
                for (std::size_t k = 0; k < 3; ++k)
                    cell |= std::size_t(((std::int64_t(p.xyz[k]) - cube.corner[k]) >> shift) & kMask)
                            << (kGridBits * k);
                if (marks.cell[cell] == marks.generation) return true;
                marks.cell[cell] = marks.generation;
                chosen.push_back(p.spilled.index);
                return chosen.size() <= cap_;  // past the cap this grid is too fine
            });
            if (chosen.size() <= cap_) break;
        }
        // Each child's set without the chosen points, then the node's own set.
        std::vector<Lifted> mine;
        mine.reserve(chosen.size());
        std::vector<Lifted> rest;
        for (int c : children) {
            Top& child = tops_[std::size_t(c)];
            const std::uint64_t at = sets_end_;
            std::uint64_t kept = 0;
            rest.clear();
            const int one[1] = {c};
            mergeSets(one, [&](const Lifted& p, std::size_t) {
                if (std::binary_search(chosen.begin(), chosen.end(), p.spilled.index)) {
                    mine.push_back(p);
                } else {
                    rest.push_back(p);
                    ++kept;
                    if (rest.size() == 4096) {
                        appendSet(rest);
                        rest.clear();
                    }
                }
                return true;
            });
            appendSet(rest);
            child.set_at = at;
            child.set_n = kept;
        }
        std::sort(mine.begin(), mine.end(),
                  [](const Lifted& a, const Lifted& b) { return a.spilled.index < b.spilled.index; });
        Top& top = tops_[std::size_t(t)];
        top.set_at = sets_end_;
        top.set_n = mine.size();
        appendSet(mine);
    }

    // Writes the top node `t` and what lies below it, depth first.
    void emit(Assembler& out, int t) {
        Top& top = tops_[std::size_t(t)];
        if (top.set_n == 0) {
            out.addEmpty(top.key);
        } else {
            // emit() takes the upper nodes in the order orderTops() listed them.
            const std::size_t k = top_next_++;
            if (k >= top_order_.size() || top_order_[k] != t)
                throw Error(record_.where() + ": the upper nodes came out of order");
            if (k >= top_batch_from_ + top_batch_.size()) compressTops(k);
            TopChunk& chunk = top_batch_[k - top_batch_from_];
            out.add(top.key, chunk.file, std::size_t(top.set_n), chunk.inventory);
            chunk = TopChunk{};
        }
        if (top.bucket >= 0) {
            Bucket& bucket = buckets_[std::size_t(top.bucket)];
            std::string bytes;
            LasInventory none;
            std::uint64_t read = 0;  // the end of the chunks copied
            for (const Bucket::Chunk& c : bucket.chunks) {
                if (c.points == 0) {
                    out.addEmpty(c.key);
                    continue;
                }
                bytes.resize(std::size_t(c.size));
                chunks_->read(bytes.data(), bytes.size());
                out.addBytes(c.key, bytes.data(), bytes.size(), std::size_t(c.points), none);
                read = c.at + c.size;
            }
            // The chunks copied are read for the last time: their pages are freed for the
            // file's next ones to take.
            chunks_->discardBefore(read);
            return;
        }
        for (int c : top.child)
            if (c >= 0) emit(out, c);
    }

    // The upper nodes with points, in emit()'s depth-first order.
    void orderTops(int t) {
        const Top& top = tops_[std::size_t(t)];
        if (top.set_n > 0) top_order_.push_back(t);
        if (top.bucket >= 0) return;
        for (int c : top.child)
            if (c >= 0) orderTops(c);
    }

    // Compresses the upper nodes top_order_[from ..] on the threads, one a thread, for
    // emit() to take in order. A thread holds its node's set and chunk in the room
    // copcFixedBytes gives it for compressing the parts' nodes, unused by then.
    void compressTops(std::size_t from) {
        const std::size_t n = std::min(top_order_.size() - from, std::size_t(threads_) + 1);
        top_batch_.assign(n, TopChunk{});
        top_batch_from_ = from;
        sets_->flush();
        parallelFor(n, threads_, [&](std::size_t i, std::size_t) {
            const Top& top = tops_[std::size_t(top_order_[from + i])];
            std::vector<Lifted> set(std::size_t(top.set_n));
            sets_->readAt(set.data(), set.size() * sizeof(Lifted), top.set_at);
            LaszipMemoryWriter zip(record_, kVariableChunks);
            LasInventory inventory;
            for (const Lifted& p : set) {
                record_.fillQuantized(zip.point(), p.spilled.point, p.xyz, &inventory);
                zip.write();
            }
            top_batch_[i] = TopChunk{zip.finish(), inventory};
        });
    }

    LasRecord record_;
    PointPacking packing_;  // the scratch files' points, quantized
    std::FILE* file_;
    std::filesystem::path dir_;
    std::string where_;
    glm::dvec3 origin_;
    LasOptions las_;
    CopcOptions copc_;
    int threads_ = 0;
    std::uint32_t cap_ = 1;
    std::vector<std::vector<CloudPoint>> blocks_;
    std::size_t count_ = 0;
    std::array<std::int32_t, 3> lo_{}, hi_{};
    // Out of core.
    std::unique_ptr<Spill> spill_;
    Bounds spilled_bounds_;
    std::array<std::vector<unsigned char>, 2> spill_bytes_;  // rounds packed, being written
    std::size_t spill_next_ = 0;                             // the one to pack into next
    std::future<void> spill_write_;                          // declared after what it writes, so waited for first
    std::uint64_t bucket_points_ = 0;
    std::vector<std::array<std::int32_t, 3>> bucket_xyz_;  // the bucket being loaded's
    std::vector<Marks> bucket_marks_;                      // its octree builder's
    int hist_level_ = 0;
    std::vector<std::uint64_t> hist_;
    std::vector<Top> tops_;
    std::vector<Bucket> buckets_;
    std::unique_ptr<platform::ScratchFile> sets_;  // the upper nodes' sets (Lifted runs)
    std::uint64_t sets_end_ = 0;
    std::unique_ptr<platform::ScratchFile> chunks_;
    std::uint64_t chunks_at_ = 0;
    // The upper nodes' chunks, compressed a batch at a time (compressTops).
    struct TopChunk {
        LaszipFile file;
        LasInventory inventory;
    };
    std::vector<int> top_order_;
    std::size_t top_next_ = 0, top_batch_from_ = 0;
    std::vector<TopChunk> top_batch_;
    LasInventory inventory_;  // of the buckets' chunks
    // The prescan (prescanPasses): its passes, then the points sorted as they come.
    enum class Prescan { None, Bounds, Histogram, Direct, Declined };
    Prescan prescan_ = Prescan::None;
    int prescan_pass_ = 0;  // the pass being given
    std::uint64_t prescan_points_ = 0, prescanned_ = 0;
    Bounds prescan_bounds_;
    std::vector<Gathered> gathered_;
    std::array<Round, 2> direct_rounds_;
    std::size_t direct_next_ = 0;
    std::future<void> gather_;  // declared after what it writes, so waited for first
};

}  // namespace

std::unique_ptr<FormatWriter> openCopcWriter(platform::TempFile& file, const glm::dvec3& origin,
                                             const core::CloudFields& fields, const LasOptions& las,
                                             const CopcOptions& copc) {
    LasRecord record("output: " + file.destination().string(), origin, fields, las);
    return std::make_unique<CopcWriter>(file, std::move(record), origin, fields, las, copc);
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
    const std::uint64_t per_thread = (std::uint64_t(1) << 21) * sizeof(std::uint32_t) +
                                     (1 + detail::kCapsPerThread) * cap * detail::kCompressedBytesPerPoint;
    return std::uint64_t(std::max(threads, 0) + 1) * per_thread;
}

std::uint64_t copcMinimumBytes(int threads, std::uint32_t max_node_points) {
    const std::uint64_t cap = std::max<std::uint32_t>(max_node_points, 1);
    const std::uint64_t per_point = copcBytesPerPoint() + sizeof(detail::Spilled);
    return copcFixedBytes(threads, max_node_points) + 2 * per_point * (cap + 1) * 8 / 7 + (1u << 20);
}

struct CopcNodeWriter::Impl {
    platform::TempFile temp;
    detail::LasRecord record;
    detail::OctreeCube cube;
    int threads = 0;
    std::set<CopcKey> added;
    std::unique_ptr<detail::Assembler> out;
    bool committed = false;

    Impl(const std::filesystem::path& path, const glm::dvec3& origin, const core::CloudFields& fields, int bits,
         const LasOptions& las)
        : temp(path), record("output: " + path.string(), origin, fields, las), threads(std::max(las.threads, 0)) {
        if (bits < 1 || bits > 31)
            throw core::Error("output: " + path.string() + ": a COPC cube of 2^" + std::to_string(bits) +
                              " mm; allowed bits 1 to 31");
        cube.bits = bits;
        cube.corner.fill(-(std::int64_t(1) << (bits - 1)));
        out = std::make_unique<detail::Assembler>(record, temp.file(), origin);
    }

    // One line naming the node and what is allowed.
    std::string nodeName(const CopcKey& k) const {
        return "node " + std::to_string(k.level) + "-" + std::to_string(k.x) + "-" + std::to_string(k.y) + "-" +
               std::to_string(k.z);
    }

    void checkNode(const Node& node) {
        const CopcKey& k = node.key;
        const std::int64_t side = k.level >= 0 && k.level <= cube.bits ? std::int64_t(1) << k.level : 0;
        if (side == 0 || k.x < 0 || k.y < 0 || k.z < 0 || k.x >= side || k.y >= side || k.z >= side)
            throw core::Error(record.where() + ": " + nodeName(k) + " is outside the octree; allowed levels 0 to " +
                              std::to_string(cube.bits) + " and x, y, z in [0, 2^level)");
        if (!added.insert(k).second) throw core::Error(record.where() + ": " + nodeName(k) + " was added before");
        const int shift = cube.bits - k.level;
        const std::int64_t key[3] = {k.x, k.y, k.z};
        for (std::size_t i = 0; i < node.points.size(); ++i) {
            const std::array<std::int32_t, 3> xyz = record.quantize(node.points[i], i);
            for (std::size_t a = 0; a < 3; ++a)
                if (((std::int64_t(xyz[a]) - cube.corner[a]) >> shift) != key[a])
                    throw core::Error(record.where() + ": point " + std::to_string(i) + " of " + nodeName(k) +
                                      " lies outside its cube");
        }
    }
};

CopcNodeWriter::CopcNodeWriter(const std::filesystem::path& path, const glm::dvec3& origin,
                               const core::CloudFields& fields, int bits, const LasOptions& las) {
    platform::checkWritableDestination(path);
    impl_ = std::make_unique<Impl>(path, origin, fields, bits, las);
}

CopcNodeWriter::~CopcNodeWriter() {
    if (impl_ && !impl_->committed) impl_->temp.discard();
}

void CopcNodeWriter::add(std::span<const Node> nodes) {
    Impl& m = *impl_;
    for (const Node& n : nodes) m.checkNode(n);
    std::vector<detail::LaszipFile> files(nodes.size());
    std::vector<detail::LasInventory> counted(nodes.size());
    detail::orderedParallel(
        nodes.size(), m.threads, detail::kNodesPerThread * std::size_t(m.threads + 1),
        [&](std::size_t i) {
            if (!nodes[i].points.empty())
                files[i] =
                    detail::compressWithLaszip(m.record, nodes[i].points, 0, counted[i], detail::kVariableChunks);
        },
        [&](std::size_t i) {
            if (nodes[i].points.empty())
                m.out->addEmpty(nodes[i].key);
            else
                m.out->add(nodes[i].key, files[i], nodes[i].points.size(), counted[i]);
            files[i] = detail::LaszipFile{};
        });
}

void CopcNodeWriter::commit() {
    Impl& m = *impl_;
    // Every ancestor of a node is in the hierarchy, empty where it was never added.
    std::set<CopcKey> missing;
    for (const CopcKey& k : m.added)
        for (CopcKey a = k; a.level > 0;) {
            a = {a.level - 1, a.x >> 1, a.y >> 1, a.z >> 1};
            if (m.added.count(a) || !missing.insert(a).second) break;
        }
    if (m.added.empty()) missing.insert(CopcKey{});
    for (const CopcKey& a : missing) m.out->addEmpty(a);
    m.out->finish(m.cube);
    m.temp.commit();
    m.committed = true;
}

void writeCopc(const std::filesystem::path& path, const core::PointCloud& cloud, const LasOptions& las,
               const CopcOptions& copc) {
    platform::checkWritableDestination(path);
    if (!std::isfinite(cloud.origin.x) || !std::isfinite(cloud.origin.y) || !std::isfinite(cloud.origin.z))
        throw core::Error("output: " + path.string() + ": the cloud origin is not finite");
    platform::TempFile temp(path);
    {
        const std::unique_ptr<detail::FormatWriter> writer =
            detail::openCopcWriter(temp, cloud.origin, cloud.fields, las, copc);
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
