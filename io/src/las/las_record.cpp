// io/src/las/las_record.cpp: see las_record.hpp. Point format 7 (RGB) or 6, scale
// 0.001 m and the cloud's double origin as the offsets, so the georeferencing survives
// any coordinate magnitude (a foreign file's points: its own scale and offset, so their
// integer coordinates come back as they were); classification from the role, GPS time from the view's time
// along the orbit, point source ID = view, and extra bytes for our range, label and
// (when the cloud has them) incidence angle and height above ground (docs/formats.md).
#include "las_record.hpp"

#include <core/error.hpp>

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string_view>

namespace io::detail {

using core::CloudFields;
using core::CloudPoint;
using core::Error;
using core::kRoleCount;

namespace {

constexpr double kScanAngleUnit_deg = 0.006;  // LAS 1.4 point formats 6..10

// LAS extra bytes data types as laszip_add_attribute takes them (LAS code - 1).
constexpr laszip_U32 kExtraUChar = 0;
constexpr laszip_U32 kExtraFloat = 8;

// LAS 1.4 header offsets of the fields written at the end.
constexpr off_t kBoundsAt = 179;   // max x, min x, max y, min y, max z, min z (doubles)
constexpr off_t kCountsAt = 247;   // points (u64), then points by return 1..15 (u64)
constexpr off_t kSoftwareAt = 58;  // generating software, 32 characters, NUL-padded
constexpr std::size_t kSoftwareSize = 32;
constexpr std::size_t kDescriptionSize = 32;       // an extra bytes description, NUL-padded
constexpr std::size_t kExtraDescriptorSize = 192;  // an extra bytes descriptor

// Extra bytes descriptions: whole words within the 32-character field (with its NUL).
constexpr const char* kRangeDescription = "sensor-to-hit distance (m)";
constexpr const char* kLabelDescription = "role: 0 ground, 1 env, 2 target";
constexpr const char* kIncidenceDescription = "beam-to-normal angle (deg)";
constexpr const char* kHeightDescription = "above the fitted terrain (m)";
static_assert(std::string_view(kRangeDescription).size() < kDescriptionSize &&
              std::string_view(kLabelDescription).size() < kDescriptionSize &&
              std::string_view(kIncidenceDescription).size() < kDescriptionSize &&
              std::string_view(kHeightDescription).size() < kDescriptionSize);

constexpr const char* kSoftware = "ladarvr " LADARVR_VERSION;
static_assert(std::string_view(kSoftware).size() < kSoftwareSize);

LasDate computeDate() {
    std::time_t t = std::time(nullptr);
    if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH")) {
        const std::string_view v(epoch);
        const bool digits = !v.empty() && v.size() <= 12 && v.find_first_not_of("0123456789") == std::string_view::npos;
        if (!digits)
            throw Error("SOURCE_DATE_EPOCH='" + std::string(v.substr(0, 40)) + (v.size() > 40 ? "..." : "") +
                        "': allowed a whole number of seconds since 1970-01-01 UTC (the LAS creation date)");
        t = std::time_t(std::strtoll(epoch, nullptr, 10));
    }
    std::tm utc{};
    if (!gmtime_r(&t, &utc) || utc.tm_year + 1900 > 65535)
        throw Error("SOURCE_DATE_EPOCH: the date is beyond the LAS header's year field (65535)");
    return LasDate{std::uint16_t(utc.tm_yday + 1), std::uint16_t(utc.tm_year + 1900)};
}

template <typename T>
void putLe(unsigned char*& out, T v) {
    std::memcpy(out, &v, sizeof v);  // x86-64 and aarch64 are little-endian, as LAS is
    out += sizeof v;
}

}  // namespace

LasDate lasCreationDate() {
    static const LasDate date = computeDate();  // a throw here leaves it to the next call
    return date;
}

void LasInventory::merge(const LasInventory& o) {
    if (o.points == 0) return;
    if (points == 0) {
        min = o.min;
        max = o.max;
        gps_min_s = o.gps_min_s;
        gps_max_s = o.gps_max_s;
    } else {
        gps_min_s = std::min(gps_min_s, o.gps_min_s);
        gps_max_s = std::max(gps_max_s, o.gps_max_s);
        for (std::size_t k = 0; k < 3; ++k) {
            min[k] = std::min(min[k], o.min[k]);
            max[k] = std::max(max[k], o.max[k]);
        }
    }
    points += o.points;
    for (std::size_t r = 0; r < by_return.size(); ++r) by_return[r] += o.by_return[r];
}

LasRecord::LasRecord(std::string where, const glm::dvec3& origin, const CloudFields& fields, const LasOptions& options,
                     Scales scales)
    : where_(std::move(where)), origin_(origin), offset_(origin), fields_(fields), options_(options) {
    try {
        date_ = lasCreationDate();
    } catch (const Error& e) {
        throw Error(where_ + ": " + e.what());
    }
    if (const core::ForeignHeader* f = options_.foreign.get()) useForeignGrid(*f, scales);
    int at = 0;
    const auto add = [&](Extra::What what, int size) {
        extras_.push_back({what, at});
        at += size;
    };
    if (const core::ForeignHeader* f = options_.foreign.get()) {
        // A foreign file's extra bytes come first, as they are; of ours only the height
        // above ground, unless the file has that field already.
        at = extra_at_ = int(f->extra_bytes);
        for (const ExtraDescriptor& d : extraDescriptors(*f))
            if (d.name == kForeignHeightName && d.type == 9) height_in_place_ = d.offset;
        if (fields.height_above_ground && height_in_place_ < 0) add(Extra::Height, 4);
        extra_bytes_ = at;
        return;
    }
    if (fields.range) add(Extra::Range, 4);
    if (fields.label) add(Extra::Label, 1);
    if (fields.incidence) add(Extra::Incidence, 4);
    if (fields.height_above_ground) add(Extra::Height, 4);
    extra_bytes_ = at;
}

namespace {

// The one scale of a COPC file that holds every axis' steps of `scale`: the finest of
// them, or the largest fraction 1/n of it (n up to 16) that divides all three (0.25 mm
// and 0.1 mm: 0.05 mm), so that every axis' integer coordinates become whole multiples;
// the finest alone when none does.
double commonStep(const glm::dvec3& scale) {
    const double finest = std::min({scale.x, scale.y, scale.z});
    for (int n = 1; n <= 16; ++n) {
        const double step = finest / n;
        bool whole = true;
        for (int k = 0; k < 3; ++k) {
            const double ratio = scale[k] / step;
            whole = whole && std::fabs(ratio - std::round(ratio)) <= 1e-9 * ratio;
        }
        if (whole) return step;
    }
    return finest;
}

}  // namespace

// A foreign file's integer grid: its scale and offset, where they are usable (positive
// finite scales; a reader always gives them). One scale: commonStep's.
void LasRecord::useForeignGrid(const core::ForeignHeader& f, Scales scales) {
    for (int k = 0; k < 3; ++k)
        if (!(f.scale[k] > 0.0 && std::isfinite(f.scale[k]) && std::isfinite(f.offset[k]))) return;
    scale_ = f.scale;
    if (scales == Scales::One) scale_ = glm::dvec3(commonStep(f.scale));
    offset_ = f.offset;
    shift_ = origin_ - offset_;
    in_scale_ = f.scale;
    in_offset_ = f.offset;
    kept_grid_ = true;
}

std::array<laszip_I32, 3> LasRecord::quantize(const CloudPoint& p, std::uint64_t index,
                                              const unsigned char* foreign) const {
    if (!kept_grid_ || !foreign) return quantize(p, index);
    core::ForeignPoint f;
    std::memcpy(&f, foreign, sizeof f);
    const float position[3] = {p.position.x, p.position.y, p.position.z};
    std::array<laszip_I32, 3> xyz{};
    for (int k = 0; k < 3; ++k) {
        const std::size_t a = std::size_t(k);
        // The reader's float of the record's coordinate, computed as it computes it.
        const double world = double(f.xyz[a]) * in_scale_[k] + in_offset_[k];
        if (float(world - origin_[k]) != position[a]) return quantize(p, index);  // the point moved
        if (in_scale_[k] == scale_[k] && in_offset_[k] == offset_[k]) {
            xyz[a] = f.xyz[a];
            continue;
        }
        // A finer grid (COPC's one scale): the steps in double, exact well within a half.
        const double v = std::round((double(f.xyz[a]) * in_scale_[k] + (in_offset_[k] - offset_[k])) / scale_[k]);
        if (!(std::fabs(v) < 2147483647.5)) return quantize(p, index);
        xyz[a] = laszip_I32(v);
    }
    return xyz;
}

std::vector<ExtraDescriptor> extraDescriptors(const core::ForeignHeader& f) {
    static constexpr std::array<int, 11> kTypeSize = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
    constexpr std::size_t kDescriptor = kExtraDescriptorSize;
    std::vector<ExtraDescriptor> out;
    const std::string& v = f.extra_bytes_vlr;
    int at = 0;
    for (std::size_t d = 0; d + kDescriptor <= v.size(); d += kDescriptor) {
        const int type = std::uint8_t(v[d + 2]);
        const int options = std::uint8_t(v[d + 3]);
        const int size = type == 0 ? options : type < 11 ? kTypeSize[std::size_t(type)] : 0;
        if (type >= 11 || size == 0 || at + size > int(f.extra_bytes)) break;  // the rest stays undescribed
        ExtraDescriptor e;
        e.type = type;
        e.size = size;
        e.offset = at;
        e.name.assign(v.data() + d + 4, strnlen(v.data() + d + 4, 32));
        e.description.assign(v.data() + d + 160, strnlen(v.data() + d + 160, 32));
        if (options & 8) std::memcpy(&e.scale, v.data() + d + 112, 8);
        if (options & 16) std::memcpy(&e.offset_value, v.data() + d + 136, 8);
        out.push_back(e);
        at += size;
    }
    return out;
}

void LasRecord::check(laszip_POINTER zip, laszip_I32 rc, const char* what) const {
    if (rc == 0) return;
    laszip_CHAR* message = nullptr;
    if (zip) laszip_get_error(zip, &message);
    throw Error(where_ + ": LASzip " + what + " failed: " + (message ? std::string(message) : "unknown error"));
}

namespace {

// One extra bytes descriptor (LAS 1.4 R15 §2.6.3), all its other fields zero: no scale,
// offset, no-data value, minimum or maximum. `name` and `description` up to 31 bytes.
std::string extraDescriptor(int type, int options, std::string_view name, std::string_view description) {
    std::string d(kExtraDescriptorSize, '\0');
    d[2] = char(type);
    d[3] = char(options);
    name.substr(0, 31).copy(d.data() + 4, 31);
    description.substr(0, kDescriptionSize - 1).copy(d.data() + 160, kDescriptionSize - 1);
    return d;
}

}  // namespace

// A foreign file's extra bytes VLR: its own descriptors byte for byte (their scale,
// offset, no-data value, minimum, maximum and description kept). Where our height above
// ground follows them, the bytes no descriptor covers are described as undocumented
// (type 0, at most 255 a descriptor) first, so that the height lies where its descriptor
// says. A height written over the file's own loses that field's minimum and maximum,
// which no longer hold.
std::string LasRecord::foreignExtraVlr() const {
    const core::ForeignHeader& f = *options_.foreign;
    const std::vector<ExtraDescriptor> known = extraDescriptors(f);
    const std::string& own = f.extra_bytes_vlr;
    const bool adds =
        std::any_of(extras_.begin(), extras_.end(), [](const Extra& e) { return e.what == Extra::Height; });
    std::string v;
    if (!adds) {
        v = own.substr(0, own.size() / kExtraDescriptorSize * kExtraDescriptorSize);
    } else {
        v = own.substr(0, known.size() * kExtraDescriptorSize);
        int at = known.empty() ? 0 : known.back().offset + known.back().size;
        while (at < int(f.extra_bytes)) {
            const int n = std::min(255, int(f.extra_bytes) - at);
            v += extraDescriptor(0, n, "extra_bytes_" + std::to_string(at), "undescribed bytes");
            at += n;
        }
        v += extraDescriptor(9, 0, kForeignHeightName, kHeightDescription);
    }
    if (fields_.height_above_ground && height_in_place_ >= 0)
        for (std::size_t i = 0; i < known.size(); ++i)
            if (known[i].offset == height_in_place_) v[i * kExtraDescriptorSize + 3] &= char(~6);
    if (v.size() > 65535)
        throw Error(where_ + ": the extra bytes descriptors take " + std::to_string(v.size()) +
                    " bytes, more than a LAS VLR holds (65535)");
    return v;
}

// A foreign file's extra bytes descriptors (foreignExtraVlr), then its CRS as an OGC WKT
// record.
void LasRecord::setUpForeign(laszip_POINTER zip) const {
    const core::ForeignHeader& f = *options_.foreign;
    const std::string extra = foreignExtraVlr();
    if (!extra.empty())
        check(zip,
              laszip_add_vlr(zip, "LASF_Spec", 4, laszip_U16(extra.size()), nullptr,
                             reinterpret_cast<const laszip_U8*>(extra.data())),
              "extra bytes");
    if (!f.wkt.empty() && f.wkt.size() < 65535) {
        std::string payload = f.wkt;
        if (payload.back() != '\0') payload.push_back('\0');
        check(zip,
              laszip_add_vlr(zip, "LASF_Projection", 2112, laszip_U16(payload.size()), "OGC WKT",
                             reinterpret_cast<const laszip_U8*>(payload.data())),
              "the WKT record");
    }
}

void LasRecord::setUp(laszip_POINTER zip) const {
    laszip_header_struct* h = nullptr;
    check(zip, laszip_get_header_pointer(zip, &h), "header");
    h->version_major = 1;
    h->version_minor = 4;
    h->header_size = 375;
    h->offset_to_point_data = 375;
    h->global_encoding = 1u << 4;  // WKT (required by point formats 6..10); GPS week time
    // LASzip replaces the generating software when it opens the writer (stampSoftware).
    std::snprintf(h->generating_software, sizeof h->generating_software, "%s", kSoftware);
    // A survey's points were collected by its producer's system, not simulated by ours:
    // its identifier is kept, all 32 bytes of it (the field needs no terminating NUL),
    // or none where it named none.
    if (options_.foreign) {
        const std::string& system = options_.foreign->system_identifier;
        std::memset(h->system_identifier, 0, sizeof h->system_identifier);
        std::memcpy(h->system_identifier, system.data(), std::min(system.size(), sizeof h->system_identifier));
    } else {
        std::snprintf(h->system_identifier, sizeof h->system_identifier, "ladarvr simulation");
    }
    h->file_creation_day = date_.day;
    h->file_creation_year = date_.year;
    const bool nir = fields_.rgb && options_.foreign && options_.foreign->nir;
    h->point_data_format = nir ? 8 : fields_.rgb ? 7 : 6;
    h->point_data_record_length = laszip_U16((nir ? 38 : fields_.rgb ? 36 : 30) + extra_bytes_);
    h->x_scale_factor = scale_.x;
    h->y_scale_factor = scale_.y;
    h->z_scale_factor = scale_.z;
    h->x_offset = offset_.x;
    h->y_offset = offset_.y;
    h->z_offset = offset_.z;
    if (options_.foreign) {
        setUpForeign(zip);  // its extra bytes VLR describes the height above ground too
        return;
    }
    for (const Extra& e : extras_) {
        switch (e.what) {
            case Extra::Range:
                check(zip, laszip_add_attribute(zip, kExtraFloat, "range", kRangeDescription, 1.0, 0.0), "range");
                break;
            case Extra::Label:
                check(zip, laszip_add_attribute(zip, kExtraUChar, "label", kLabelDescription, 1.0, 0.0), "label");
                break;
            case Extra::Incidence:
                check(zip, laszip_add_attribute(zip, kExtraFloat, "incidence_deg", kIncidenceDescription, 1.0, 0.0),
                      "incidence_deg");
                break;
            case Extra::Height:
                check(zip,
                      laszip_add_attribute(zip, kExtraFloat, "height_above_ground_m", kHeightDescription, 1.0, 0.0),
                      "height_above_ground_m");
                break;
        }
    }
}

void LasRecord::throwBeyondReach(std::uint64_t index) const {
    if (scale_ == glm::dvec3(kScale_m) && shift_ == glm::dvec3(0.0))
        throw Error(where_ + ": point " + std::to_string(index) +
                    " lies beyond 2,147 km of the cloud origin, out of LAS's reach at 1 mm");
    char steps[96];
    std::snprintf(steps, sizeof steps, "%.17g, %.17g, %.17g", scale_.x, scale_.y, scale_.z);
    throw Error(where_ + ": point " + std::to_string(index) + " lies beyond 2^31 steps of the input's LAS scale (" +
                steps + ") from its offset, out of LAS's reach");
}

double LasRecord::gpsTime(const CloudPoint& p) const {
    return options_.gps_start_s + double(p.view) * options_.view_interval_s;
}

// The fields a foreign point's side record holds.
void LasRecord::fillForeign(laszip_point_struct& q, const unsigned char* foreign) const {
    core::ForeignPoint f;
    std::memcpy(&f, foreign, sizeof f);
    q.extended_classification = f.classification;
    q.classification = f.classification < 32 ? f.classification & 31u : 0u;
    q.extended_classification_flags = f.flags & 15u;
    q.synthetic_flag = f.flags & 1u;
    q.keypoint_flag = (f.flags >> 1) & 1u;
    q.withheld_flag = (f.flags >> 2) & 1u;
    q.extended_scanner_channel = (f.flags >> 4) & 3u;
    q.scan_direction_flag = (f.flags >> 6) & 1u;
    q.edge_of_flight_line = (f.flags >> 7) & 1u;
    q.user_data = f.user_data;
    q.point_source_ID = f.point_source_id;
    q.gps_time = f.gps_time_s;
    q.rgb[0] = f.rgb[0];
    q.rgb[1] = f.rgb[1];
    q.rgb[2] = f.rgb[2];
    q.rgb[3] = f.nir;
    const std::size_t own = options_.foreign->extra_bytes;
    if (own == 0) return;
    if (q.num_extra_bytes < int(own) || !q.extra_bytes) throw Error(where_ + ": LASzip did not size the extra bytes");
    std::memcpy(q.extra_bytes, foreign + sizeof f, own);
}

// What every point record takes from the point itself: position, intensity, returns and
// scan angle. Returns the point's return number as written (1..15).
std::uint8_t LasRecord::fillMeasured(laszip_point_struct& q, const CloudPoint& p,
                                     const std::array<laszip_I32, 3>& xyz) const {
    q.X = xyz[0];
    q.Y = xyz[1];
    q.Z = xyz[2];
    q.intensity = fields_.intensity ? p.intensity : 0;
    const std::uint8_t rn = std::clamp<std::uint8_t>(p.return_number, 1, 15);
    const std::uint8_t nr = std::clamp<std::uint8_t>(std::max(p.returns, rn), 1, 15);
    q.extended_point_type = 1;
    q.extended_return_number = rn & 15u;
    q.extended_number_of_returns = nr & 15u;
    q.return_number = std::min<std::uint8_t>(rn, 7) & 7u;
    q.number_of_returns = std::min<std::uint8_t>(nr, 7) & 7u;
    if (fields_.scan_angle) {
        const double angle = std::clamp(std::round(p.scan_angle_deg / kScanAngleUnit_deg), -30000.0, 30000.0);
        q.extended_scan_angle = laszip_I16(angle);
        q.scan_angle_rank = laszip_I8(std::clamp(std::lround(p.scan_angle_deg), -90L, 90L));
    } else {
        q.extended_scan_angle = 0;
        q.scan_angle_rank = 0;
    }
    return rn;
}

// A foreign point: position, intensity, returns and scan angle from `p`, the rest from
// its side record, and the height above ground when this file adds it.
void LasRecord::fillForeignQuantized(laszip_point_struct& q, const CloudPoint& p, const std::array<laszip_I32, 3>& xyz,
                                     LasInventory* inventory, const unsigned char* foreign) const {
    const std::uint8_t rn = fillMeasured(q, p, xyz);
    fillForeign(q, foreign);
    if (inventory) inventory->add(xyz, q.gps_time, rn);
    if (!fields_.height_above_ground) return;
    if (height_in_place_ >= 0) {
        std::memcpy(q.extra_bytes + height_in_place_, &p.height_above_ground_m, 4);
        return;
    }
    for (const Extra& e : extras_)
        if (e.what == Extra::Height) std::memcpy(q.extra_bytes + e.offset, &p.height_above_ground_m, 4);
}

void LasRecord::fillQuantized(laszip_point_struct& q, const CloudPoint& p, const std::array<laszip_I32, 3>& xyz,
                              LasInventory* inventory, const unsigned char* foreign) const {
    if (options_.foreign && foreign) {
        fillForeignQuantized(q, p, xyz, inventory, foreign);
        return;
    }
    const std::uint8_t rn = fillMeasured(q, p, xyz);
    const std::uint8_t cls = options_.class_of_role[std::min<int>(int(p.label), kRoleCount - 1)];
    q.extended_classification = cls;
    q.classification = cls < 32 ? cls & 31u : 0u;
    q.point_source_ID = p.view;
    const double gps_time_s = gpsTime(p);
    q.gps_time = gps_time_s;
    if (inventory) inventory->add(xyz, gps_time_s, rn);
    if (fields_.rgb) {
        q.rgb[0] = laszip_U16(((p.rgb >> 16) & 0xFFu) * 257u);
        q.rgb[1] = laszip_U16(((p.rgb >> 8) & 0xFFu) * 257u);
        q.rgb[2] = laszip_U16((p.rgb & 0xFFu) * 257u);
    }
    if (extra_bytes_ == 0) return;
    if (q.num_extra_bytes != extra_bytes_ || !q.extra_bytes)
        throw Error(where_ + ": LASzip did not size the extra bytes");
    for (const Extra& e : extras_) {
        unsigned char* at = q.extra_bytes + e.offset;
        switch (e.what) {
            case Extra::Range: std::memcpy(at, &p.range_m, 4); break;
            case Extra::Label: *at = std::uint8_t(p.label); break;
            case Extra::Incidence: std::memcpy(at, &p.incidence_deg, 4); break;
            case Extra::Height: std::memcpy(at, &p.height_above_ground_m, 4); break;
        }
    }
}

void LasRecord::stampSoftware(int fd) const {
    char field[kSoftwareSize] = {};
    std::memcpy(field, kSoftware, std::strlen(kSoftware));
    if (::pwrite(fd, field, sizeof field, kSoftwareAt) != ssize_t(sizeof field))
        throw Error(where_ + ": writing the header's generating software failed: " + std::strerror(errno));
}

void LasRecord::patchHeader(int fd, const LasInventory& inv) const {
    stampSoftware(fd);
    // An empty file keeps the zero counts and bounds it was opened with, as with LASzip.
    if (inv.points == 0) return;
    // The bounds as LASzip computes them: scale times the integer extreme plus the offset.
    unsigned char bounds[48], *b = bounds;
    for (std::size_t k = 0; k < 3; ++k) {
        const int a = int(k);
        putLe(b, scale_[a] * double(inv.max[k]) + offset_[a]);
        putLe(b, scale_[a] * double(inv.min[k]) + offset_[a]);
    }
    unsigned char counts[128], *c = counts;
    putLe(c, std::uint64_t(inv.points));
    for (std::size_t r = 1; r <= 15; ++r) putLe(c, std::uint64_t(inv.by_return[r]));
    const auto put = [&](const unsigned char* data, std::size_t size, off_t at) {
        if (::pwrite(fd, data, size, at) != ssize_t(size))
            throw Error(where_ + ": writing the header's counts failed: " + std::strerror(errno));
    };
    put(bounds, sizeof bounds, kBoundsAt);
    put(counts, sizeof counts, kCountsAt);
}

}  // namespace io::detail
