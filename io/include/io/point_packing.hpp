// io/point_packing.hpp: a point in as few bytes as the fields a cloud carries, for
// scratch files (the COPC writer's spill and parts, the generator's spool). The record
// always holds what a LAS record is made of whatever the fields (position, view, label,
// return number and returns); the optional fields only when the cloud has them.
// unpack(pack(p)) gives a point that LasRecord::fill() turns into the same record as p;
// the fields the cloud lacks come back as their defaults.
//
// A packing made Quantized holds, in the position's 12 bytes, the integer coordinates the
// writer's records will hold (packQuantized), so that the readers of a scratch file sort
// and fill records without converting the position again; unpack() then leaves the
// position at its default.
#pragma once
#include <core/point_cloud.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace io {

class PointPacking {
  public:
    enum class Position { Float, Quantized };

    explicit PointPacking(const core::CloudFields& fields, Position position = Position::Float)
        : fields_(fields), quantized_(position == Position::Quantized) {
        size_ = 12 + 2 + 1 + 1 + 1;
        if (fields.rgb) size_ += 4;
        if (fields.range) size_ += 4;
        if (fields.incidence) size_ += 4;
        if (fields.scan_angle) size_ += 4;
        if (fields.height_above_ground) size_ += 4;
        if (fields.intensity) size_ += 2;
    }

    /// Bytes of one packed point.
    std::size_t size() const { return size_; }

    void pack(const core::CloudPoint& p, unsigned char* out) const {
        put(out, &p.position, 12);
        packRest(p, out);
    }

    /// Packs `p` with `xyz` in place of its position (a Quantized packing's records).
    void packQuantized(const core::CloudPoint& p, const std::array<std::int32_t, 3>& xyz, unsigned char* out) const {
        put(out, xyz.data(), 12);
        packRest(p, out);
    }

    /// The integer coordinates of a point packed by packQuantized (its first 12 bytes).
    static std::array<std::int32_t, 3> quantized(const unsigned char* in) {
        std::array<std::int32_t, 3> xyz;
        std::memcpy(xyz.data(), in, 12);
        return xyz;
    }

  private:
    void packRest(const core::CloudPoint& p, unsigned char*& out) const {
        put(out, &p.view, 2);
        put(out, &p.label, 1);
        put(out, &p.return_number, 1);
        put(out, &p.returns, 1);
        if (fields_.rgb) put(out, &p.rgb, 4);
        if (fields_.range) put(out, &p.range_m, 4);
        if (fields_.incidence) put(out, &p.incidence_deg, 4);
        if (fields_.scan_angle) put(out, &p.scan_angle_deg, 4);
        if (fields_.height_above_ground) put(out, &p.height_above_ground_m, 4);
        if (fields_.intensity) put(out, &p.intensity, 2);
    }

  public:
    /// The position of a packed point (its first 12 bytes), alone.
    static glm::vec3 position(const unsigned char* in) {
        glm::vec3 p;
        std::memcpy(&p, in, 12);
        return p;
    }

    core::CloudPoint unpack(const unsigned char* in) const {
        core::CloudPoint p;
        if (quantized_)
            in += 12;
        else
            get(in, &p.position, 12);
        get(in, &p.view, 2);
        get(in, &p.label, 1);
        get(in, &p.return_number, 1);
        get(in, &p.returns, 1);
        if (fields_.rgb) get(in, &p.rgb, 4);
        if (fields_.range) get(in, &p.range_m, 4);
        if (fields_.incidence) get(in, &p.incidence_deg, 4);
        if (fields_.scan_angle) get(in, &p.scan_angle_deg, 4);
        if (fields_.height_above_ground) get(in, &p.height_above_ground_m, 4);
        if (fields_.intensity) get(in, &p.intensity, 2);
        return p;
    }

  private:
    static void put(unsigned char*& out, const void* field, std::size_t n) {
        std::memcpy(out, field, n);
        out += n;
    }
    // GCC's -Warray-bounds, under -fsanitize=undefined, sees a null path of `in` that the
    // sanitizer's own check adds and flags this copy on it; `in` is never null here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
    static void get(const unsigned char*& in, void* field, std::size_t n) {
        std::memcpy(field, in, n);
        in += n;
    }
#pragma GCC diagnostic pop

    core::CloudFields fields_;
    bool quantized_ = false;
    std::size_t size_ = 0;
};

}  // namespace io
