// las_reader: LAS 1.0-1.4 and LAZ through LASzip, behind io::CloudReader. The header
// and the VLRs are checked here first, bounded by the bytes present (LASzip trusts
// them), then LASzip decodes the points from a stream over the ByteSource, a chunk at a
// time. Coordinates are computed in double and moved onto a double origin (whole metres
// near the middle of the header's bounds) before the cast to float. Classes map to roles
// (roleForClass), unless the file has our `label` extra bytes (docs/formats.md).
#include "cloud_decode.hpp"


#include <core/error.hpp>

#include <laszip/laszip_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <istream>
#include <streambuf>

namespace io::detail {

using core::Error;
using core::Role;
using core::CloudPoint;
using core::CloudFields;
using core::packRgb;

namespace {

// Bytes of the fixed fields of point formats 0..10.
constexpr std::array<std::size_t, 11> kMinRecord = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
constexpr std::size_t kVlrHeader = 54;
constexpr std::size_t kExtraBytesDescriptor = 192;

template <typename T>
T le(std::string_view bytes, std::size_t at) {
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
}

/// A read-only, seekable std::streambuf over a ByteSource (LASzip reads through an
/// istream and seeks to LAZ's chunk table).
class SourceBuf final : public std::streambuf {
public:
    explicit SourceBuf(ByteSource& source) : source_(source) {}

protected:
    int_type underflow() override {
        if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
        const std::uint64_t at = base_ + std::uint64_t(egptr() - eback());
        if (at >= source_.size()) return traits_type::eof();
        const std::size_t n = std::size_t(std::min<std::uint64_t>(kBlock, source_.size() - at));
        const std::string_view v = source_.view(at, n);
        block_.assign(v.begin(), v.end());
        base_ = at;
        setg(block_.data(), block_.data(), block_.data() + block_.size());
        return traits_type::to_int_type(*gptr());
    }

    std::streamsize xsgetn(char* out, std::streamsize n) override {
        std::streamsize done = 0;
        while (done < n) {
            if (gptr() == egptr() && underflow() == traits_type::eof()) break;
            const std::streamsize take = std::min<std::streamsize>(n - done, egptr() - gptr());
            std::memcpy(out + done, gptr(), std::size_t(take));
            gbump(int(take));
            done += take;
        }
        return done;
    }

    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        const std::int64_t here = std::int64_t(base_) + (gptr() - eback());
        const std::int64_t from = dir == std::ios_base::beg ? 0 : dir == std::ios_base::cur ? here
                                                                   : std::int64_t(source_.size());
        return seekpos(pos_type(off_type(from + off)), std::ios_base::in);
    }

    pos_type seekpos(pos_type pos, std::ios_base::openmode) override {
        const std::int64_t at = std::int64_t(pos);
        if (at < 0 || std::uint64_t(at) > source_.size()) return pos_type(off_type(-1));
        base_ = std::uint64_t(at);
        block_.clear();
        setg(nullptr, nullptr, nullptr);
        return pos;
    }

private:
    static constexpr std::size_t kBlock = 1u << 16;
    ByteSource& source_;
    std::vector<char> block_;
    std::uint64_t base_ = 0;  // file offset of eback()
};

struct ExtraField {
    bool present = false;
    int type = 0;          // LAS data type 1..10
    std::size_t offset = 0;
};

double extraValue(const unsigned char* bytes, const ExtraField& f) {
    switch (f.type) {
        case 1: return bytes[f.offset];
        case 2: return std::int8_t(bytes[f.offset]);
        case 3: { std::uint16_t v; std::memcpy(&v, bytes + f.offset, 2); return v; }
        case 4: { std::int16_t v; std::memcpy(&v, bytes + f.offset, 2); return v; }
        case 5: { std::uint32_t v; std::memcpy(&v, bytes + f.offset, 4); return v; }
        case 6: { std::int32_t v; std::memcpy(&v, bytes + f.offset, 4); return v; }
        case 7: { std::uint64_t v; std::memcpy(&v, bytes + f.offset, 8); return double(v); }
        case 8: { std::int64_t v; std::memcpy(&v, bytes + f.offset, 8); return double(v); }
        case 9: { float v; std::memcpy(&v, bytes + f.offset, 4); return v; }
        default: { double v; std::memcpy(&v, bytes + f.offset, 8); return v; }
    }
}

class LasReader final : public FormatReader {
public:
    LasReader(ByteSource& source, const std::string& prefix)
        : source_(source), prefix_(prefix), buf_(source), stream_(&buf_) {
        checkHeader();
        if (laszip_create(&zip_) != 0 || !zip_) throw Error(prefix_ + ": LASzip could not be started");
        laszip_BOOL compressed = 0;
        check(laszip_open_reader_stream(zip_, stream_, &compressed), "cannot open");
        open_ = true;
        check(laszip_get_point_pointer(zip_, &point_), "cannot read");
    }

    ~LasReader() override {
        if (open_) laszip_close_reader(zip_);
        if (zip_) laszip_destroy(zip_);
    }
    LasReader(const LasReader&) = delete;
    LasReader& operator=(const LasReader&) = delete;

    std::size_t next(std::vector<CloudPoint>& out, std::size_t max_points) override {
        const std::size_t n = std::min(max_points, declared - done_);
        out.reserve(out.size() + n);
        const laszip_point_struct& q = *point_;
        for (std::size_t k = 0; k < n; ++k) {
            if (laszip_read_point(zip_) != 0) check(1, ("point " + std::to_string(done_ + k)).c_str());
            CloudPoint p;
            p.position = glm::vec3(float(double(q.X) * scale_.x + offset_.x - origin.x),
                                   float(double(q.Y) * scale_.y + offset_.y - origin.y),
                                   float(double(q.Z) * scale_.z + offset_.z - origin.z));
            p.intensity = q.intensity;
            p.view = q.point_source_ID;
            if (extended_) {
                p.return_number = q.extended_return_number;
                p.returns = q.extended_number_of_returns;
                p.scan_angle_deg = float(q.extended_scan_angle * 0.006);
            } else {
                p.return_number = q.return_number;
                p.returns = q.number_of_returns;
                p.scan_angle_deg = float(q.scan_angle_rank);
            }
            if (fields.rgb)
                p.rgb = packRgb(std::uint8_t(q.rgb[0] >> 8), std::uint8_t(q.rgb[1] >> 8), std::uint8_t(q.rgb[2] >> 8));
            const unsigned char* extra = q.num_extra_bytes >= int(extra_size_) ? q.extra_bytes : nullptr;
            if (label_.present && extra) {
                const double v = extraValue(extra, label_);
                if (!(v == 0.0 || v == 1.0 || v == 2.0)) {
                    char shown_v[32];  // %g: any double (a float extra byte may hold 1e31 or NaN)
                    std::snprintf(shown_v, sizeof shown_v, "%g", v);
                    throw Error(prefix_ + ": point " + std::to_string(done_ + k) + ": label " + shown_v +
                                " is not 0 (ground), 1 (environment) or 2 (target)");
                }
                p.label = Role(std::uint8_t(v));
            } else {
                const unsigned cls = extended_ ? q.extended_classification : q.classification;
                bool known = true;
                p.label = roleForClass(cls, known);
                if (!known && stats.unknown_classes++ == 0) stats.first_unknown = cls;
            }
            if (extra) {
                if (range_.present) p.range_m = float(extraValue(extra, range_));
                if (incidence_.present) p.incidence_deg = float(extraValue(extra, incidence_));
                if (height_.present) p.height_above_ground_m = float(extraValue(extra, height_));
            }
            out.push_back(p);
        }
        done_ += n;
        return n;
    }

private:
    void check(laszip_I32 rc, const char* what) {
        if (rc == 0) return;
        laszip_CHAR* message = nullptr;
        if (zip_) laszip_get_error(zip_, &message);
        throw Error(prefix_ + ": " + what + ": " + (message ? core::printable(message, 160, false) : std::string("LASzip failed")));
    }

    // The public header block and the VLRs, checked against the file's size before
    // LASzip sees them.
    void checkHeader() {
        const std::uint64_t size = source_.size();
        if (size < 227) throw Error(prefix_ + ": truncated: a LAS header needs 227 bytes, the file has " + std::to_string(size));
        const std::string_view h = source_.view(0, std::size_t(std::min<std::uint64_t>(size, 375)));
        const std::string head(h);  // the view changes with the next read
        const int major = std::uint8_t(head[24]), minor = std::uint8_t(head[25]);
        if (major != 1 || minor > 4)
            throw Error(prefix_ + ": LAS version " + std::to_string(major) + "." + std::to_string(minor) +
                        " is not one of 1.0 to 1.4");
        const std::size_t header_size = le<std::uint16_t>(head, 94);
        const std::uint64_t data_at = le<std::uint32_t>(head, 96);
        const std::uint32_t vlrs = le<std::uint32_t>(head, 100);
        const unsigned raw_format = std::uint8_t(head[104]);
        const unsigned format = raw_format & 0x3Fu;
        const bool compressed = (raw_format & 0xC0u) != 0;  // LASzip marks LAZ with bit 7 (or 6)
        const std::size_t record = le<std::uint16_t>(head, 105);
        const std::size_t min_header = minor >= 4 ? 375 : minor == 3 ? 235 : 227;
        if (header_size < min_header || header_size > data_at || data_at > size)
            throw Error(prefix_ + ": header size " + std::to_string(header_size) + " and point data offset " +
                        std::to_string(data_at) + " do not fit a LAS 1." + std::to_string(minor) + " file of " +
                        std::to_string(size) + " bytes");
        if (format >= kMinRecord.size())
            throw Error(prefix_ + ": point data format " + std::to_string(format) + " is not one of 0 to 10");
        if (record < kMinRecord[format])
            throw Error(prefix_ + ": point records of " + std::to_string(record) + " bytes are too short for format " +
                        std::to_string(format) + " (" + std::to_string(kMinRecord[format]) + " bytes)");
        for (int k = 0; k < 3; ++k) {
            scale_[k] = le<double>(head, 131 + 8 * std::size_t(k));
            offset_[k] = le<double>(head, 155 + 8 * std::size_t(k));
            if (!std::isfinite(scale_[k]) || scale_[k] == 0.0 || !std::isfinite(offset_[k]))
                throw Error(prefix_ + ": the scale and offset of " + "xyz"[k] + " must be finite and the scale non-zero");
        }
        std::uint64_t count = le<std::uint32_t>(head, 107);
        if (minor >= 4 && count == 0) count = le<std::uint64_t>(head, 247);
        // VLRs: each header and payload inside the space before the points.
        std::uint64_t at = header_size;
        if (vlrs > (data_at - header_size) / kVlrHeader)
            throw Error(prefix_ + ": " + std::to_string(vlrs) + " VLRs cannot fit before the point data");
        std::size_t extra_declared = 0;
        bool laszip_vlr = false;
        for (std::uint32_t v = 0; v < vlrs; ++v) {
            if (data_at - at < kVlrHeader) throw Error(prefix_ + ": VLR " + std::to_string(v) + " runs into the point data");
            const std::string vh(source_.view(at, kVlrHeader));
            const std::uint16_t length = le<std::uint16_t>(vh, 20);
            if (data_at - at - kVlrHeader < length)
                throw Error(prefix_ + ": VLR " + std::to_string(v) + " runs into the point data");
            const std::string user(vh.data() + 2, strnlen(vh.data() + 2, 16));
            if (user == "LASF_Spec" && le<std::uint16_t>(vh, 18) == 4)
                extra_declared = readExtraBytes(std::string(source_.view(at + kVlrHeader, length)));
            if (user == "laszip encoded" && le<std::uint16_t>(vh, 18) == 22204) {
                checkLaszipVlr(std::string(source_.view(at + kVlrHeader, length)));
                laszip_vlr = true;
            }
            at += kVlrHeader + length;
        }
        // LASzip leaks its reader when it refuses a LAZ file (its header checks do not free
        // what they allocated), so what it would refuse is refused here first.
        if (compressed && !laszip_vlr)
            throw Error(prefix_ + ": the point format marks compressed (LAZ) data but there is no LASzip VLR");
        if (extra_declared > record - kMinRecord[format])
            throw Error(prefix_ + ": the extra bytes VLR describes " + std::to_string(extra_declared) +
                        " bytes but the records have " + std::to_string(record - kMinRecord[format]));
        extra_size_ = extra_declared;
        const std::uint64_t remaining = size - data_at;
        if (!compressed && count > remaining / record)
            throw Error(prefix_ + ": truncated: the header says " + std::to_string(count) + " points of " +
                        std::to_string(record) + " bytes but only " + std::to_string(remaining) +
                        " bytes of point data follow");
        if (compressed && count > 0 && remaining == 0)
            throw Error(prefix_ + ": truncated: no compressed point data follow the header");
        declared = std::size_t(count);
        // LAZ: at least one byte per point is a safe amount to reserve (the real count
        // needs its memory anyway; a hostile count on a small file gets the file size).
        bound = compressed ? std::size_t(std::min<std::uint64_t>(count, remaining)) : declared;
        extended_ = format >= 6;
        // The local frame: whole metres near the middle of the bounds.
        const glm::dvec3 max{le<double>(head, 179), le<double>(head, 195), le<double>(head, 211)};
        const glm::dvec3 min{le<double>(head, 187), le<double>(head, 203), le<double>(head, 219)};
        origin = shiftFor(0.5 * (min + max));
        fields = CloudFields{};
        fields.rgb = format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
        fields.label = true;
        fields.view = true;
        fields.range = range_.present;
        fields.intensity = true;
        fields.returns = true;
        fields.scan_angle = true;
        fields.incidence = incidence_.present;
        fields.height_above_ground = height_.present;
    }

    // The LASzip VLR: compressor 0..3 (none, pointwise, chunked, layered), the arithmetic
    // coder, and as many 6-byte item descriptions as it says.
    void checkLaszipVlr(const std::string& payload) {
        if (payload.size() < 34) throw Error(prefix_ + ": the LASzip VLR is shorter than 34 bytes");
        const unsigned compressor = le<std::uint16_t>(payload, 0), coder = le<std::uint16_t>(payload, 2);
        const std::size_t items = le<std::uint16_t>(payload, 32);
        if (compressor > 3 || coder != 0 || payload.size() != 34 + 6 * items || items == 0)
            throw Error(prefix_ + ": the LASzip VLR is not one this reader knows (compressor " +
                        std::to_string(compressor) + ", coder " + std::to_string(coder) + ", " +
                        std::to_string(items) + " items in " + std::to_string(payload.size()) + " bytes)");
    }

    // LAS 1.4 extra bytes descriptors: our fields by name; returns the bytes they cover.
    std::size_t readExtraBytes(const std::string& payload) {
        static constexpr std::array<std::size_t, 11> kTypeSize = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
        std::size_t offset = 0;
        for (std::size_t d = 0; d + kExtraBytesDescriptor <= payload.size(); d += kExtraBytesDescriptor) {
            const int type = std::uint8_t(payload[d + 2]);
            const std::size_t size = type == 0 ? std::uint8_t(payload[d + 3]) : type < 11 ? kTypeSize[std::size_t(type)] : 0;
            if (type >= 11) break;  // deprecated array types: the offsets after them are unknown
            const std::string name(payload.data() + d + 4, strnlen(payload.data() + d + 4, 32));
            ExtraField f{true, type, offset};
            if (type != 0) {
                if (name == "range") range_ = f;
                else if (name == "label") label_ = f;
                else if (name == "incidence_deg") incidence_ = f;
                else if (name == "height_above_ground_m") height_ = f;
            }
            offset += size;
        }
        return offset;
    }

    ByteSource& source_;
    std::string prefix_;
    SourceBuf buf_;
    std::istream stream_;
    laszip_POINTER zip_ = nullptr;
    laszip_point_struct* point_ = nullptr;
    bool open_ = false;
    bool extended_ = false;
    glm::dvec3 scale_{1.0}, offset_{0.0};
    ExtraField range_, label_, incidence_, height_;
    std::size_t extra_size_ = 0;
    std::size_t done_ = 0;
};

}  // namespace

std::unique_ptr<FormatReader> openLas(ByteSource& source, const std::string& prefix) {
    return std::make_unique<LasReader>(source, prefix);
}

}  // namespace io::detail
