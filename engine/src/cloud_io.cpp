// cloud_io: PCD v0.7 and PLY 1.0, written in a stream through a temporary file. We keep
// our own PCD/PLY codec rather than PCL's because it streams and writes about 4.5x
// faster than PCL's writer. The readers live in pcd_reader.cpp and ply_reader.cpp
// behind engine::CloudReader (cloud_reader.cpp).
#include <engine/atomic_file.hpp>
#include <engine/cloud_io.hpp>
#include <engine/error.hpp>
#include <engine/safe_file.hpp>

#include "las_sink.hpp"
#include "text.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <system_error>
#include <vector>

namespace engine {

static_assert(std::endian::native == std::endian::little,
              "cloud_io writes little-endian records with memcpy");

// ---------------------------------------------------------------------------------
// Formats
// ---------------------------------------------------------------------------------

CloudFormat parseCloudFormat(std::string_view name, std::string_view parameter) {
    for (CloudFormat f : {CloudFormat::PcdBinary, CloudFormat::PcdAscii, CloudFormat::PlyBinary,
                          CloudFormat::PlyAscii, CloudFormat::Las, CloudFormat::Laz})
        if (name == cloudFormatName(f)) return f;
    throw Error(std::string(parameter) + ": format '" + detail::shown(name) +
                "' is not one of pcd, pcd-ascii, ply, ply-ascii, las, laz");
}

const char* cloudFormatName(CloudFormat format) {
    switch (format) {
        case CloudFormat::PcdBinary: return "pcd";
        case CloudFormat::PcdAscii: return "pcd-ascii";
        case CloudFormat::PlyBinary: return "ply";
        case CloudFormat::PlyAscii: return "ply-ascii";
        case CloudFormat::Las: return "las";
        case CloudFormat::Laz: return "laz";
    }
    return "pcd";
}

CloudFormat formatForPath(const std::filesystem::path& path, std::string_view parameter) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext.empty() || ext == ".pcd") return CloudFormat::PcdBinary;
    if (ext == ".ply") return CloudFormat::PlyBinary;
    if (ext == ".las") return CloudFormat::Las;
    if (ext == ".laz") return CloudFormat::Laz;
    throw Error(std::string(parameter) + ": " + detail::shown(path.string(), 200, true) + ": extension '" +
                detail::shown(ext, 40, true) + "' is not one of .pcd, .ply, .las, .laz");
}

namespace {

// The point count fields of the header are written zero-padded to this many digits
// so commit() can overwrite them in place; PCL, Open3D (rply) and Python parse the
// leading zeros as decimal. (Trailing spaces would break PCL's strict PLY parser.)
constexpr int kCountDigits = 12;
constexpr std::size_t kFlushBytes = 8u << 20;

bool isPly(CloudFormat f) { return f == CloudFormat::PlyBinary || f == CloudFormat::PlyAscii; }
bool isAscii(CloudFormat f) { return f == CloudFormat::PcdAscii || f == CloudFormat::PlyAscii; }

std::string originText(const glm::dvec3& o) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", o.x, o.y, o.z);
    return buf;
}

std::string paddedCount(std::size_t n) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%0*zu", kCountDigits, n);
    return buf;
}

// One optional field after x y z and rgb: its names and types in PCD and PLY. PLY names
// start with "scalar_" and use uchar, int or float, the property types that both
// CloudCompare (which keeps only one unknown property unless it is named scalar_*) and
// Open3D (which drops char, short, ushort and uint) keep.
struct FieldSpec {
    const char* pcd_name;
    char pcd_type;      // U or F
    int pcd_size;
    const char* ply_name;
    const char* ply_type;  // uchar, int, float
    int ply_size;
};

constexpr FieldSpec kLabel{"label", 'U', 1, "scalar_label", "uchar", 1};
constexpr FieldSpec kView{"view", 'U', 2, "scalar_view", "int", 4};
constexpr FieldSpec kRange{"range", 'F', 4, "scalar_range", "float", 4};
constexpr FieldSpec kIntensity{"intensity", 'U', 2, "scalar_intensity", "int", 4};
constexpr FieldSpec kReturnNumber{"return_number", 'U', 1, "scalar_return_number", "uchar", 1};
constexpr FieldSpec kReturns{"number_of_returns", 'U', 1, "scalar_number_of_returns", "uchar", 1};
constexpr FieldSpec kIncidence{"incidence_deg", 'F', 4, "scalar_incidence_deg", "float", 4};
constexpr FieldSpec kScanAngle{"scan_angle_deg", 'F', 4, "scalar_scan_angle_deg", "float", 4};
constexpr FieldSpec kHeight{"height_above_ground_m", 'F', 4, "scalar_height_above_ground_m", "float", 4};

// The optional fields `fields` turns on, in file order.
std::vector<const FieldSpec*> optionalFields(const CloudFields& f) {
    std::vector<const FieldSpec*> out;
    if (f.label) out.push_back(&kLabel);
    if (f.view) out.push_back(&kView);
    if (f.range) out.push_back(&kRange);
    if (f.intensity) out.push_back(&kIntensity);
    if (f.returns) {
        out.push_back(&kReturnNumber);
        out.push_back(&kReturns);
    }
    if (f.incidence) out.push_back(&kIncidence);
    if (f.scan_angle) out.push_back(&kScanAngle);
    if (f.height_above_ground) out.push_back(&kHeight);
    return out;
}

// Header text; `count_at` receives the byte offsets of the padded count fields.
std::string makeHeader(CloudFormat format, const glm::dvec3& origin, const CloudFields& fields,
                       long count_at[2]) {
    std::string h;
    const std::string zero = paddedCount(0);
    count_at[0] = count_at[1] = -1;
    if (isPly(format)) {
        h += "ply\n";
        h += isAscii(format) ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n";
        h += "comment generated by ladarvr; positions are local: world = origin + (x, y, z)\n";
        h += "comment ladarvr origin " + originText(origin) + "\n";
        h += "element vertex ";
        count_at[0] = long(h.size());
        h += zero + "\n";
        h += "property float x\nproperty float y\nproperty float z\n";
        if (fields.rgb) h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
        for (const FieldSpec* f : optionalFields(fields))
            h += std::string("property ") + f->ply_type + " " + f->ply_name + "\n";
        h += "end_header\n";
        return h;
    }
    std::string names = "x y z", sizes = "4 4 4", types = "F F F", counts = "1 1 1";
    auto add = [&](const char* n, int s, char t) {
        names += std::string(" ") + n;
        sizes += " " + std::to_string(s);
        types += std::string(" ") + t;
        counts += " 1";
    };
    if (fields.rgb) add("rgb", 4, 'F');
    for (const FieldSpec* f : optionalFields(fields)) add(f->pcd_name, f->pcd_size, f->pcd_type);
    h += "# .PCD v0.7 - Point Cloud Data file format (ladarvr: world = origin + (x, y, z))\n";
    h += "# ladarvr origin " + originText(origin) + "\n";
    h += "VERSION 0.7\nFIELDS " + names + "\nSIZE " + sizes + "\nTYPE " + types + "\nCOUNT " +
         counts + "\nWIDTH ";
    count_at[0] = long(h.size());
    h += zero + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS ";
    count_at[1] = long(h.size());
    h += zero + "\n";
    h += isAscii(format) ? "DATA ascii\n" : "DATA binary\n";
    return h;
}

template <typename T>
void putRaw(char*& out, T v) {
    std::memcpy(out, &v, sizeof v);
    out += sizeof v;
}

void putFloat(std::string& s, float v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}

void putUnsigned(std::string& s, std::uint32_t v) {
    char buf[16];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}

}  // namespace

// ---------------------------------------------------------------------------------
// Writer
// ---------------------------------------------------------------------------------

CloudWriter::CloudWriter(std::filesystem::path path, CloudFormat format, glm::dvec3 origin,
                         CloudFields fields, const LasOptions& las)
    : path_(std::move(path)), format_(format), fields_(fields) {
    checkWritableDestination(path_);
    if (!std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.z))
        throw Error("output: " + path_.string() + ": the cloud origin is not finite");
    temp_ = std::make_unique<TempFile>(path_);
    file_ = temp_->file();
    if (format_ == CloudFormat::Las || format_ == CloudFormat::Laz) {
        las_ = detail::openLasSink(*temp_, format_ == CloudFormat::Laz, origin, fields_, las);
        return;
    }
    const std::string header = makeHeader(format_, origin, fields_, count_offset_);
    buffer_.reserve(kFlushBytes + 4096);
    buffer_ = header;
}

// The TempFile removes the temporary when destroyed uncommitted.
CloudWriter::~CloudWriter() = default;

void CloudWriter::append(std::span<const CloudPoint> points) {
    if (!file_) throw Error("output: " + path_.string() + ": append after commit");
    if (las_) {
        las_->append(points);
        count_ += points.size();
        return;
    }
    const bool ply = isPly(format_);
    if (!isAscii(format_)) {
        std::size_t record = 12 + (fields_.rgb ? (ply ? 3 : 4) : 0);
        for (const FieldSpec* f : optionalFields(fields_)) record += std::size_t(ply ? f->ply_size : f->pcd_size);
        const bool extras = fields_.intensity || fields_.returns || fields_.incidence || fields_.scan_angle ||
                            fields_.height_above_ground;
        std::size_t done = 0;
        while (done < points.size()) {
            const std::size_t room = std::max<std::size_t>(1, (kFlushBytes - std::min(kFlushBytes, buffer_.size())) / record);
            const std::size_t n = std::min(room, points.size() - done);
            const std::size_t old = buffer_.size();
            buffer_.resize(old + n * record);
            char* out = buffer_.data() + old;
            for (std::size_t i = done; i < done + n; ++i) {
                const CloudPoint& p = points[i];
                putRaw(out, p.position.x);
                putRaw(out, p.position.y);
                putRaw(out, p.position.z);
                if (fields_.rgb) {
                    const std::uint32_t rgb = p.rgb & 0xFFFFFFu;
                    if (ply) {
                        putRaw(out, std::uint8_t(rgb >> 16));
                        putRaw(out, std::uint8_t(rgb >> 8));
                        putRaw(out, std::uint8_t(rgb));
                    } else {
                        putRaw(out, rgb);  // PCL's packed float: the same 4 bytes
                    }
                }
                if (fields_.label) putRaw(out, std::uint8_t(p.label));
                if (fields_.view) {
                    if (ply) putRaw(out, std::int32_t(p.view));
                    else putRaw(out, p.view);
                }
                if (fields_.range) putRaw(out, p.range_m);
                if (!extras) continue;
                if (fields_.intensity) {
                    if (ply) putRaw(out, std::int32_t(p.intensity));
                    else putRaw(out, p.intensity);
                }
                if (fields_.returns) {
                    putRaw(out, p.return_number);
                    putRaw(out, p.returns);
                }
                if (fields_.incidence) putRaw(out, p.incidence_deg);
                if (fields_.scan_angle) putRaw(out, p.scan_angle_deg);
                if (fields_.height_above_ground) putRaw(out, p.height_above_ground_m);
            }
            done += n;
            count_ += n;
            if (buffer_.size() >= kFlushBytes) {
                if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
                    throw Error("output: " + path_.string() + ": write failed: " +
                                std::strerror(errno));
                buffer_.clear();
            }
        }
        return;
    }
    for (const CloudPoint& p : points) {
        putFloat(buffer_, p.position.x);
        buffer_ += ' ';
        putFloat(buffer_, p.position.y);
        buffer_ += ' ';
        putFloat(buffer_, p.position.z);
        const std::uint32_t rgb = p.rgb & 0xFFFFFFu;
        if (fields_.rgb) {
            if (ply) {
                buffer_ += ' ';
                putUnsigned(buffer_, rgb >> 16);
                buffer_ += ' ';
                putUnsigned(buffer_, (rgb >> 8) & 0xFFu);
                buffer_ += ' ';
                putUnsigned(buffer_, rgb & 0xFFu);
            } else {
                // The packed float as a (tiny) float number: PCL's and Open3D's ASCII
                // readers parse a TYPE F field as a float and keep its bits.
                float packed;
                std::memcpy(&packed, &rgb, 4);
                buffer_ += ' ';
                putFloat(buffer_, packed);
            }
        }
        if (fields_.label) {
            buffer_ += ' ';
            putUnsigned(buffer_, std::uint32_t(p.label));
        }
        if (fields_.view) {
            buffer_ += ' ';
            putUnsigned(buffer_, p.view);
        }
        if (fields_.range) {
            buffer_ += ' ';
            putFloat(buffer_, p.range_m);
        }
        if (fields_.intensity) {
            buffer_ += ' ';
            putUnsigned(buffer_, p.intensity);
        }
        if (fields_.returns) {
            buffer_ += ' ';
            putUnsigned(buffer_, p.return_number);
            buffer_ += ' ';
            putUnsigned(buffer_, p.returns);
        }
        const std::pair<bool, float> floats[] = {{fields_.incidence, p.incidence_deg},
                                                  {fields_.scan_angle, p.scan_angle_deg},
                                                  {fields_.height_above_ground, p.height_above_ground_m}};
        for (const auto& [on, v] : floats) {
            if (!on) continue;
            buffer_ += ' ';
            putFloat(buffer_, v);
        }
        buffer_ += '\n';
        ++count_;
        if (buffer_.size() >= kFlushBytes) {
            if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
                throw Error("output: " + path_.string() + ": write failed: " + std::strerror(errno));
            buffer_.clear();
        }
    }
}

void CloudWriter::commit() {
    if (!file_) throw Error("output: " + path_.string() + ": commit called twice");
    auto fail = [&](const std::string& what) {
        const std::string reason = std::strerror(errno);
        file_ = nullptr;
        temp_->discard();
        throw Error("output: " + path_.string() + ": " + what + ": " + reason);
    };
    if (las_) {
        file_ = nullptr;
        las_->finish();  // header counts, bounds and (LAZ) the chunk table, then flushed
        las_.reset();
        temp_->commit();
        return;
    }
    if (!buffer_.empty() && std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
        fail("write failed");
    buffer_.clear();
    buffer_.shrink_to_fit();
    const std::string count = paddedCount(count_);
    if (count.size() != std::size_t(kCountDigits)) {
        errno = EFBIG;
        fail("too many points for the header");
    }
    for (long at : count_offset_) {
        if (at < 0) continue;
        if (std::fseek(file_, at, SEEK_SET) != 0 ||
            std::fwrite(count.data(), 1, count.size(), file_) != count.size())
            fail("cannot write the point count");
    }
    file_ = nullptr;
    temp_->commit();  // flush, close, rename over path_ (or remove the temporary and throw)
}

void writeCloud(const std::filesystem::path& path, const PointCloud& cloud, CloudFormat format,
                const LasOptions& las) {
    CloudWriter writer(path, format, cloud.origin, cloud.fields, las);
    writer.append(cloud.points);
    writer.commit();
}

}  // namespace engine
