// io/src/las/las_record.hpp (internal): how a CloudPoint becomes a LAS 1.4 point record,
// shared by the LAS writer (las_writer.cpp) and the LAZ writer (laz_writer.cpp), and the
// header fields both fill in at the end (generating software, counts by return, bounds).
#pragma once
#include <io/cloud_io.hpp>

#include <laszip/laszip_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace io::detail {

/// Point counts and integer bounds of the records written, as the LAS header holds them.
struct LasInventory {
    std::uint64_t points = 0;
    std::array<std::uint64_t, 16> by_return{};  // [r]: records with return number r
    std::array<laszip_I32, 3> min{}, max{};
    double gps_min_s = 0.0, gps_max_s = 0.0;  // of the records' GPS times (0 when none)
    /// Counts a record of these integer coordinates, GPS time and return number.
    void add(const std::array<laszip_I32, 3>& xyz, double gps_time_s, unsigned return_number) {
        if (points == 0) {
            min = max = xyz;
            gps_min_s = gps_max_s = gps_time_s;
        } else {
            gps_min_s = std::min(gps_min_s, gps_time_s);
            gps_max_s = std::max(gps_max_s, gps_time_s);
            for (std::size_t k = 0; k < 3; ++k) {
                min[k] = std::min(min[k], xyz[k]);
                max[k] = std::max(max[k], xyz[k]);
            }
        }
        ++points;
        ++by_return[return_number & 15u];
    }
    void merge(const LasInventory& other);
};

/// The day of the year (1..366) and the year, in UTC, that LAS headers give as their
/// creation date: SOURCE_DATE_EPOCH's when it is set (reproducible outputs), else the
/// day the process first asked; one value for the whole process, so every chunk of a LAZ
/// file (and a file LASzip writes alone for comparison) gets the same header. Throws
/// Error when SOURCE_DATE_EPOCH is not a whole number of seconds.
struct LasDate {
    std::uint16_t day = 0, year = 0;
};
LasDate lasCreationDate();

/// One field of a foreign file's extra bytes, from its descriptor (LAS 1.4 R15 §2.6.3).
struct ExtraDescriptor {
    int type = 0;    // LAS data type 1..10, or 0: `size` undocumented bytes
    int size = 0;    // bytes
    int offset = 0;  // within the record's extra bytes
    std::string name, description;
    double scale = 1.0, offset_value = 0.0;
};
/// The fields `f`'s extra bytes VLR describes, in order, as far as they fit its records'
/// extra bytes (an array type or an overrun ends the list: the bytes after stay raw).
std::vector<ExtraDescriptor> extraDescriptors(const core::ForeignHeader& f);
/// The height above ground's extra bytes name in files of other producers (PDAL's).
inline constexpr const char* kForeignHeightName = "HeightAboveGround";

class LasRecord {
  public:
    static constexpr double kScale_m = 0.001;  // the records' scale for clouds we generated

    /// Whether every axis must have the same scale (a COPC file: its octree's cubes are
    /// cubes of integer steps).
    enum class Scales { PerAxis, One };

    /// `where`: "output: <path>" for messages. The records' scale and offset: a foreign
    /// file's (LasOptions::foreign), so that its points keep their integer coordinates,
    /// with `scales` One its finest scale on every axis; else 1 mm and the origin.
    LasRecord(std::string where, const glm::dvec3& origin, const core::CloudFields& fields, const LasOptions& options,
              Scales scales = Scales::PerAxis);

    /// Sets `zip`'s header (LAS 1.4, point format 7 or 6, the scale and offset above, the
    /// creation day and year of lasCreationDate()) and its extra bytes, before it is
    /// opened for writing. Throws Error.
    void setUp(laszip_POINTER zip) const;
    /// Fills `q` with point `p`, the `index`-th of the file (for messages), and counts its
    /// record into `inventory` when given (from the values it computes: reading them back
    /// from `q` would wait on the stores just made). `foreign`: the point's side record
    /// where LasOptions::foreign is set (else ignored). Throws Error(where + ": point N
    /// lies beyond ...") when it is out of the integer grid's reach.
    void fill(laszip_point_struct& q, const core::CloudPoint& p, std::uint64_t index, LasInventory* inventory = nullptr,
              const unsigned char* foreign = nullptr) const {
        fillQuantized(q, p, foreign ? quantize(p, index, foreign) : quantize(p, index), inventory, foreign);
    }
    /// The same, of a point whose integer coordinates quantize() gave before: `xyz`; its
    /// position is not read.
    void fillQuantized(laszip_point_struct& q, const core::CloudPoint& p, const std::array<laszip_I32, 3>& xyz,
                       LasInventory* inventory = nullptr, const unsigned char* foreign = nullptr) const;
    /// The foreign header the records take side records of (LasOptions::foreign), or null.
    const core::ForeignHeader* foreign() const { return options_.foreign.get(); }
    /// The integer coordinates fill() gives point `p` (scale steps from the offset: for a
    /// cloud we generated, millimetres from the origin). Throws as fill() does.
    std::array<laszip_I32, 3> quantize(const core::CloudPoint& p, std::uint64_t index) const {
        return quantize(p.position, index);
    }
    /// The same, of a foreign point with its side record `foreign` (null: as above): the
    /// integer coordinates the record holds, on this file's grid, while the point lies where
    /// they say (its position is the float the reader made of them); else as above.
    std::array<laszip_I32, 3> quantize(const core::CloudPoint& p, std::uint64_t index,
                                       const unsigned char* foreign) const;
    /// The same, of a point's position alone.
    std::array<laszip_I32, 3> quantize(const glm::vec3& position, std::uint64_t index) const {
        const double local[3] = {position.x, position.y, position.z};
        std::array<laszip_I32, 3> xyz{};
        for (std::size_t k = 0; k < 3; ++k) {
            // std::round (half away from zero) without a call to libm: below 2^31 in
            // magnitude the truncation and its remainder are exact. std::round gives at
            // most 2^31 - 1 in magnitude exactly when |v| < 2^31 - 0.5; NaN fails too.
            const double v = (local[k] + shift_[int(k)]) / scale_[int(k)];
            if (!(std::fabs(v) < 2147483647.5)) throwBeyondReach(index);
            const auto t = std::int64_t(v);
            const double rest = v - double(t);
            xyz[k] = laszip_I32(t + (rest >= 0.5 ? 1 : 0) - (rest <= -0.5 ? 1 : 0));
        }
        return xyz;
    }
    /// The GPS time fill() gives point `p`.
    double gpsTime(const core::CloudPoint& p) const;
    /// Throws Error(where + ": LASzip <what> failed: <its message>") unless rc is 0.
    void check(laszip_POINTER zip, laszip_I32 rc, const char* what) const;

    /// Writes the inventory into the header of the file open on `fd` (LAS 1.4 offsets:
    /// bounds at 179, counts at 247), as LASzip's own inventory does, and the generating
    /// software (stampSoftware).
    void patchHeader(int fd, const LasInventory& inventory) const;
    /// Writes "ladarvr <version>" into the generating-software field (offset 58, 32
    /// bytes) of the file open on `fd`: LASzip stamps its own name there when it opens a
    /// writer, whatever the header held.
    void stampSoftware(int fd) const;

    const std::string& where() const { return where_; }
    /// The records' scale and offset per axis, as the header holds them.
    const glm::dvec3& scale() const { return scale_; }
    const glm::dvec3& offset() const { return offset_; }

  private:
    [[noreturn]] void throwBeyondReach(std::uint64_t index) const;
    void useForeignGrid(const core::ForeignHeader& f, Scales scales);
    void setUpForeign(laszip_POINTER zip) const;
    std::string foreignExtraVlr() const;
    void fillForeign(laszip_point_struct& q, const unsigned char* foreign) const;
    std::uint8_t fillMeasured(laszip_point_struct& q, const core::CloudPoint& p,
                              const std::array<laszip_I32, 3>& xyz) const;
    void fillForeignQuantized(laszip_point_struct& q, const core::CloudPoint& p, const std::array<laszip_I32, 3>& xyz,
                              LasInventory* inventory, const unsigned char* foreign) const;

    struct Extra {
        enum What { Range, Label, Incidence, Height } what;
        int offset = 0;  // within the point's extra bytes
    };
    std::string where_;
    glm::dvec3 origin_;
    glm::dvec3 scale_{kScale_m};
    glm::dvec3 offset_;                          // the origin, or a foreign file's offset
    glm::dvec3 shift_{0.0};                      // origin - offset: a point's position plus this is from the offset
    bool kept_grid_ = false;                     // a foreign file's records: their integer coordinates are used
    glm::dvec3 in_scale_{1.0}, in_offset_{0.0};  // the grid of those integer coordinates
    core::CloudFields fields_;
    LasOptions options_;
    std::vector<Extra> extras_;
    int extra_bytes_ = 0;
    int extra_at_ = 0;          // where our extra bytes start (after a foreign file's)
    int height_in_place_ = -1;  // a foreign file's own HeightAboveGround (float), where it is
    LasDate date_;
};

}  // namespace io::detail
