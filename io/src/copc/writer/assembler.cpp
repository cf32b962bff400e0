// io/src/copc/writer/assembler.cpp: the COPC file around its chunks (assembler.hpp).
#include "assembler.hpp"

#include "../copc_hierarchy.hpp"
#include "setup.hpp"
#include "../../las/laz_chunk_table.hpp"

#include <core/error.hpp>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace io::detail::copc_writer {

using core::Error;

namespace {

constexpr std::size_t kHeaderSize = 375;
constexpr std::size_t kVlrHeaderSize = 54;
constexpr std::size_t kEvlrHeaderSize = 60;
constexpr std::size_t kInfoSize = 160;

template <typename T>
void put(std::string& s, T v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);  // x86-64 and aarch64 are little-endian, as LAS is
    s.append(b, sizeof v);
}

void patch(std::string& s, std::size_t at, std::uint32_t v) { std::memcpy(s.data() + at, &v, 4); }

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

}  // namespace

Assembler::Assembler(const LasRecord& record, std::FILE* file) : record_(record), file_(file) {
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

void Assembler::add(const CopcKey& key, const LaszipFile& f, std::size_t points, const LasInventory& inventory) {
    const std::size_t begin = f.point_data_at + 8;
    if (f.bytes.compare(0, begin - 8, laszip_header_) != 0)
        throw Error(record_.where() + ": LASzip wrote a chunk under a different header");
    addBytes(key, f.bytes.data() + begin, f.table_at - begin, points, inventory);
}

void Assembler::addBytes(const CopcKey& key, const char* data, std::size_t size, std::size_t points,
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

void Assembler::finish(const OctreeCube& cube) {
    const std::uint64_t table_at = at_;
    const std::string table = chunk_bytes_.empty() ? empty_table_ : lazVariableChunkTable(chunk_points_, chunk_bytes_);
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
    // The cube in the records' units: one scale on every axis (LasRecord::Scales::One),
    // from the records' offset (the origin for a cloud we generated).
    const double step = record_.scale().x;
    const double halfsize_m = step * std::ldexp(1.0, cube.bits - 1);
    const glm::dvec3& o = record_.offset();
    for (std::size_t k = 0; k < 3; ++k) put(info, o[int(k)] + step * (double(cube.corner[k]) - 0.5) + halfsize_m);
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

void Assembler::pwriteAll(int fd, const void* data, std::size_t size, std::uint64_t at) const {
    if (::pwrite(fd, data, size, off_t(at)) != ssize_t(size))
        throw Error(record_.where() + ": write failed: " + std::strerror(errno));
}

void Assembler::write(const void* data, std::size_t size) {
    if (size > 0 && std::fwrite(data, 1, size, file_) != size)
        throw Error(record_.where() + ": write failed: " + std::strerror(errno));
}

}  // namespace io::detail::copc_writer
