// las_writer: LAS 1.4 and LAZ output through LASzip (docs/formats.md). Point format 7
// (RGB) or 6, scale 0.001 m and the cloud's double origin as the offsets, so the
// georeferencing survives any coordinate magnitude; classification from the role, GPS
// time from the view's time along the orbit, point source ID = view, and extra bytes
// for our range, label and (when the cloud has them) incidence angle and height above
// ground. The data go through a std::ostream over the TempFile's descriptor: LASzip
// seeks back at the end to write the counts, the bounds and LAZ's chunk table.
#include "las_sink.hpp"

#include <engine/error.hpp>
#include <engine/safe_file.hpp>

#include <laszip/laszip_api.h>

#include <ext/stdio_filebuf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <ostream>
#include <vector>

namespace engine::detail {

namespace {

constexpr double kScale_m = 0.001;
constexpr double kScanAngleUnit_deg = 0.006;  // LAS 1.4 point formats 6..10

// LAS extra bytes data types as laszip_add_attribute takes them (LAS code - 1).
constexpr laszip_U32 kExtraUChar = 0;
constexpr laszip_U32 kExtraFloat = 8;

struct Extra {
    enum What { Range, Label, Incidence, Height } what;
    int offset = 0;  // within the point's extra bytes
};

class LaszipSink final : public LasSink {
public:
    LaszipSink(TempFile& file, bool compress, const glm::dvec3& origin, const CloudFields& fields,
               const LasOptions& options)
        : where_("output: " + file.destination().string()), fields_(fields), options_(options),
          buf_(file.file(), std::ios::out | std::ios::binary), stream_(&buf_) {
        if (laszip_create(&zip_) != 0 || !zip_) throw Error(where_ + ": LASzip could not be started");
        laszip_header_struct* h = nullptr;
        check(laszip_get_header_pointer(zip_, &h), "header");
        h->version_major = 1;
        h->version_minor = 4;
        h->header_size = 375;
        h->offset_to_point_data = 375;
        h->global_encoding = 1u << 4;  // WKT (required by point formats 6..10); GPS week time
        std::snprintf(h->generating_software, sizeof h->generating_software, "ladarvr");
        std::snprintf(h->system_identifier, sizeof h->system_identifier, "ladarvr simulation");
        h->point_data_format = fields.rgb ? 7 : 6;
        h->point_data_record_length = fields.rgb ? 36 : 30;
        h->x_scale_factor = h->y_scale_factor = h->z_scale_factor = kScale_m;
        h->x_offset = origin.x;
        h->y_offset = origin.y;
        h->z_offset = origin.z;
        int at = 0;
        auto add = [&](Extra::What what, laszip_U32 type, const char* name, const char* description, int size) {
            check(laszip_add_attribute(zip_, type, name, description, 1.0, 0.0), name);
            extras_.push_back({what, at});
            at += size;
        };
        if (fields.range) add(Extra::Range, kExtraFloat, "range", "sensor-to-hit distance (m)", 4);
        if (fields.label) add(Extra::Label, kExtraUChar, "label", "ladarvr role: 0 ground 1 env 2 target", 1);
        if (fields.incidence) add(Extra::Incidence, kExtraFloat, "incidence_deg", "beam-to-normal angle (deg)", 4);
        if (fields.height_above_ground)
            add(Extra::Height, kExtraFloat, "height_above_ground_m", "above the fitted terrain (m)", 4);
        extra_bytes_ = at;
        h->point_data_record_length = laszip_U16(h->point_data_record_length + at);
        check(laszip_get_point_pointer(zip_, &point_), "point");
        check(laszip_open_writer_stream(zip_, stream_, compress ? 1 : 0, 0), "open");
        open_ = true;
    }

    ~LaszipSink() override {
        if (open_) laszip_close_writer(zip_);
        if (zip_) laszip_destroy(zip_);
    }
    LaszipSink(const LaszipSink&) = delete;
    LaszipSink& operator=(const LaszipSink&) = delete;

    void append(std::span<const CloudPoint> points) override {
        laszip_point_struct& q = *point_;
        for (const CloudPoint& p : points) {
            const double local[3] = {p.position.x, p.position.y, p.position.z};
            laszip_I32 xyz[3];
            for (int k = 0; k < 3; ++k) {
                const double mm = std::round(local[k] / kScale_m);
                if (!(std::fabs(mm) <= 2147483647.0))
                    throw Error(where_ + ": point " + std::to_string(count_) +
                                " lies beyond 2,147 km of the cloud origin, out of LAS's reach at 1 mm");
                xyz[k] = laszip_I32(mm);
            }
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
            const std::uint8_t cls = options_.class_of_role[std::min<int>(int(p.label), kRoleCount - 1)];
            q.extended_classification = cls;
            q.classification = cls < 32 ? cls & 31u : 0u;
            const double angle = std::clamp(std::round(p.scan_angle_deg / kScanAngleUnit_deg), -30000.0, 30000.0);
            q.extended_scan_angle = fields_.scan_angle ? laszip_I16(angle) : 0;
            q.scan_angle_rank = laszip_I8(std::clamp(std::lround(fields_.scan_angle ? p.scan_angle_deg : 0.0f), -90L, 90L));
            q.point_source_ID = p.view;
            q.gps_time = options_.gps_start_s + double(p.view) * options_.view_interval_s;
            if (fields_.rgb) {
                q.rgb[0] = laszip_U16(((p.rgb >> 16) & 0xFFu) * 257u);
                q.rgb[1] = laszip_U16(((p.rgb >> 8) & 0xFFu) * 257u);
                q.rgb[2] = laszip_U16((p.rgb & 0xFFu) * 257u);
            }
            if (extra_bytes_ > 0) {
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
            check(laszip_write_point(zip_), "write");
            check(laszip_update_inventory(zip_), "inventory");
            ++count_;
        }
    }

    void finish() override {
        open_ = false;
        check(laszip_close_writer(zip_), "close");
        stream_.flush();
        if (!stream_) throw Error(where_ + ": write failed");
    }

private:
    void check(laszip_I32 rc, const char* what) {
        if (rc == 0 && stream_) return;
        laszip_CHAR* message = nullptr;
        if (zip_) laszip_get_error(zip_, &message);
        throw Error(where_ + ": LASzip " + what + " failed: " +
                    (!stream_ ? std::string("write failed") : message ? std::string(message) : "unknown error"));
    }

    std::string where_;
    CloudFields fields_;
    LasOptions options_;
    __gnu_cxx::stdio_filebuf<char> buf_;
    std::ostream stream_;
    laszip_POINTER zip_ = nullptr;
    laszip_point_struct* point_ = nullptr;
    std::vector<Extra> extras_;
    int extra_bytes_ = 0;
    bool open_ = false;
    std::size_t count_ = 0;
};

}  // namespace

std::unique_ptr<LasSink> openLasSink(TempFile& file, bool compress, const glm::dvec3& origin,
                                     const CloudFields& fields, const LasOptions& options) {
    return std::make_unique<LaszipSink>(file, compress, origin, fields, options);
}

}  // namespace engine::detail
