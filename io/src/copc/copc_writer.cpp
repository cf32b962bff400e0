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
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>

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
// Nodes compressed at once per thread before they are written in order.
constexpr std::size_t kNodesPerThread = 4;
// A compressed node's bytes per point, at most (as the LAZ writer's chunks).
constexpr std::uint64_t kCompressedBytesPerPoint = 24;

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

class CopcWriter final : public FormatWriter {
  public:
    CopcWriter(platform::TempFile& file, LasRecord record, const glm::dvec3& origin, const LasOptions& las,
               const CopcOptions& copc)
        : record_(std::move(record)), file_(file.file()), origin_(origin), las_(las), copc_(copc) {}

    // The points are held in blocks, so that the store never reallocates (a vector that
    // doubles would hold up to three times the points while it grows).
    void append(std::span<const CloudPoint> points) override {
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
    }

    void finish() override {
        if (count_ >= std::numeric_limits<std::uint32_t>::max())
            throw Error(record_.where() + ": COPC output holds at most 4294967294 points");
        // The points' integer coordinates, as the records will hold them.
        std::vector<std::array<std::int32_t, 3>> xyz(count_);
        std::array<std::int32_t, 3> lo{}, hi{};
        for (std::size_t i = 0; i < count_; ++i) {
            xyz[i] = record_.quantize(point(i), i);
            for (std::size_t k = 0; k < 3; ++k) {
                lo[k] = i ? std::min(lo[k], xyz[i][k]) : xyz[i][k];
                hi[k] = i ? std::max(hi[k], xyz[i][k]) : xyz[i][k];
            }
        }
        const OctreeCube cube = enclosingCube(lo, hi);
        std::vector<OctreeNode> nodes = buildOctree(xyz, cube, copc_.max_node_points, std::max(las_.threads, 0));
        std::vector<std::array<std::int32_t, 3>>().swap(xyz);

        // The header and VLRs: LASzip's, with the info VLR first.
        LasInventory none;
        const LaszipFile empty = compressWithLaszip(record_, {}, 0, none, kVariableChunks);
        const std::string laszip_header = empty.bytes.substr(0, empty.point_data_at);
        if (laszip_header.size() < kHeaderSize)
            throw Error(record_.where() + ": LASzip wrote a LAZ layout this writer does not know");
        std::string header = laszip_header.substr(0, kHeaderSize);
        header += recordHeader(1, kInfoSize, "copc info", false);
        header.append(kInfoSize, '\0');  // filled in at the end
        header += laszip_header.substr(kHeaderSize);
        patch(header, 96, std::uint32_t(header.size()));  // offset to point data
        std::uint32_t vlrs = 0;
        std::memcpy(&vlrs, header.data() + 100, 4);
        patch(header, 100, vlrs + 1);
        write(header.data(), header.size());
        const std::int64_t placeholder = 0;  // the chunk table's position
        write(&placeholder, 8);

        // The nodes' chunks, compressed a batch at a time and written in order.
        std::uint64_t at = header.size() + 8;
        std::vector<CopcNode> entries;
        std::vector<std::uint32_t> chunk_points, chunk_bytes;
        LasInventory inventory;
        const int threads = std::max(las_.threads, 0);
        const std::size_t batch = kNodesPerThread * std::size_t(threads + 1);
        for (std::size_t first = 0; first < nodes.size(); first += batch) {
            const std::size_t n = std::min(batch, nodes.size() - first);
            std::vector<LaszipFile> done(n);
            std::vector<LasInventory> counted(n);
            parallelFor(n, threads, [&](std::size_t i, std::size_t) {
                const OctreeNode& node = nodes[first + i];
                if (node.points.empty()) return;
                std::vector<CloudPoint> pts;
                pts.reserve(node.points.size());
                for (std::uint32_t p : node.points) pts.push_back(point(p));
                done[i] = compressWithLaszip(record_, pts, 0, counted[i], kVariableChunks);
            });
            for (std::size_t i = 0; i < n; ++i) {
                OctreeNode& node = nodes[first + i];
                CopcNode entry{node.key, 0, 0, 0};
                if (!node.points.empty()) {
                    const LaszipFile& f = done[i];
                    const std::size_t begin = f.point_data_at + 8;
                    if (f.bytes.compare(0, begin - 8, laszip_header) != 0)
                        throw Error(record_.where() + ": LASzip wrote a chunk under a different header");
                    const std::size_t size = f.table_at - begin;
                    if (size >= 0x80000000u || node.points.size() >= 0x80000000u)
                        throw Error(record_.where() + ": a COPC node of 2 GiB or 2^31 points or more");
                    write(f.bytes.data() + begin, size);
                    entry = {node.key, at, std::int32_t(size), std::int32_t(node.points.size())};
                    at += size;
                    chunk_points.push_back(std::uint32_t(node.points.size()));
                    chunk_bytes.push_back(std::uint32_t(size));
                    inventory.merge(counted[i]);
                }
                entries.push_back(entry);
                std::vector<std::uint32_t>().swap(node.points);
            }
        }
        const std::uint64_t table_at = at;
        const std::string table = chunk_bytes.empty()
                                      ? empty.bytes.substr(empty.point_data_at + 8)  // LASzip's table of no chunks
                                      : lazVariableChunkTable(chunk_points, chunk_bytes);
        write(table.data(), table.size());
        at += table.size();

        // The hierarchy EVLR.
        const std::uint64_t evlr_at = at;
        const HierarchyPages pages = encodeHierarchy(std::move(entries), evlr_at + kEvlrHeaderSize);
        const std::string evlr = recordHeader(1000, pages.bytes.size(), "copc hierarchy", true);
        write(evlr.data(), evlr.size());
        write(pages.bytes.data(), pages.bytes.size());

        // The info VLR, the table's position, the EVLR's place, the counts and bounds.
        const glm::dvec3& offsets = origin_;
        std::string info;
        const double halfsize_m = kScale_m * std::ldexp(1.0, cube.bits - 1);
        const double o[3] = {offsets.x, offsets.y, offsets.z};
        for (std::size_t k = 0; k < 3; ++k) put(info, o[k] + kScale_m * (double(cube.corner[k]) - 0.5) + halfsize_m);
        put(info, halfsize_m);
        put(info, 2.0 * halfsize_m / 128.0);
        put(info, evlr_at + kEvlrHeaderSize);
        put(info, pages.root_size);
        put(info, inventory.gps_min_s);
        put(info, inventory.gps_max_s);
        info.append(kInfoSize - info.size(), '\0');
        if (std::fflush(file_) != 0) throw Error(record_.where() + ": write failed: " + std::strerror(errno));
        const int fd = fileno(file_);
        pwriteAll(fd, info.data(), info.size(), kHeaderSize + kVlrHeaderSize);
        const std::int64_t position = std::int64_t(table_at);
        pwriteAll(fd, &position, 8, header.size());
        std::string evlr_fields;
        put(evlr_fields, evlr_at);
        put(evlr_fields, std::uint32_t(1));
        pwriteAll(fd, evlr_fields.data(), evlr_fields.size(), 235);
        record_.patchHeader(fd, inventory);
    }

  private:
    static constexpr std::size_t kBlockBits = 20;
    static constexpr std::size_t kBlockPoints = std::size_t(1) << kBlockBits;

    const CloudPoint& point(std::size_t i) const { return blocks_[i >> kBlockBits][i & (kBlockPoints - 1)]; }

    static void patch(std::string& s, std::size_t at, std::uint32_t v) { std::memcpy(s.data() + at, &v, 4); }

    void pwriteAll(int fd, const void* data, std::size_t size, std::uint64_t at) const {
        if (::pwrite(fd, data, size, off_t(at)) != ssize_t(size))
            throw Error(record_.where() + ": write failed: " + std::strerror(errno));
    }

    void write(const void* data, std::size_t size) {
        if (size > 0 && std::fwrite(data, 1, size, file_) != size)
            throw Error(record_.where() + ": write failed: " + std::strerror(errno));
    }

    LasRecord record_;
    std::FILE* file_;
    glm::dvec3 origin_;
    LasOptions las_;
    CopcOptions copc_;
    std::vector<std::vector<CloudPoint>> blocks_;
    std::size_t count_ = 0;
};

}  // namespace

std::unique_ptr<FormatWriter> openCopcWriter(platform::TempFile& file, const glm::dvec3& origin,
                                             const core::CloudFields& fields, const LasOptions& las,
                                             const CopcOptions& copc) {
    LasRecord record("output: " + file.destination().string(), origin, fields, las);
    return std::make_unique<CopcWriter>(file, std::move(record), origin, las, copc);
}

}  // namespace io::detail

namespace io {

std::uint64_t copcBytesPerPoint() {
    // The point, its integer coordinates, its index in the octree (split twice over while
    // a node's parts are built) and the sampling's copies.
    return sizeof(core::CloudPoint) + 12 + 3 * sizeof(std::uint32_t);
}

std::uint64_t copcFixedBytes(int threads) {
    const std::uint64_t per_thread = (std::uint64_t(1) << 21) * sizeof(std::uint32_t) +
                                     detail::kNodesPerThread * CopcOptions{}.max_node_points *
                                         (sizeof(core::CloudPoint) + detail::kCompressedBytesPerPoint);
    return std::uint64_t(std::max(threads, 0) + 1) * per_thread;
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
