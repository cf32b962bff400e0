// io/src/counted_writer.hpp (internal): what the PCD and PLY writers share. Both are a
// text header then the records; the header's point counts are written zero-padded to
// kCountDigits digits (PCL, Open3D's rply and Python parse the leading zeros as decimal;
// trailing spaces would break PCL's strict PLY parser) and overwritten in place by
// finish(), so the file is written in one stream of unknown length.
#pragma once
#include "format_writer.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace io::detail {

inline constexpr int kCountDigits = 12;

/// `n` zero-padded to kCountDigits digits (more when it does not fit).
std::string paddedCount(std::size_t n);
/// "X Y Z" of the origin, each "%.17g" (round-trips a double).
std::string originText(const glm::dvec3& o);

/// The fields after x y z and rgb, in file order.
enum class OptionalField { Label, View, Range, Intensity, ReturnNumber, Returns, Incidence, ScanAngle, Height };
/// The optional fields `fields` turns on, in file order.
std::vector<OptionalField> optionalFields(const core::CloudFields& fields);

/// Appends the bytes of `v` at `out` and moves past them (little-endian host: the file's order).
template <typename T>
void putRaw(char*& out, T v) {
    std::memcpy(out, &v, sizeof v);
    out += sizeof v;
}
/// The optional fields of `p` that `fields` turns on, as the binary PCD and PLY records
/// hold them (file order); the view and the intensity as `ViewInt` and `IntensityInt`
/// (PCD keeps their 16 bits, PLY widens them to int).
template <typename ViewInt, typename IntensityInt>
void putBinaryFields(char*& out, const core::CloudPoint& p, const core::CloudFields& f) {
    if (f.label) putRaw(out, std::uint8_t(p.label));
    if (f.view) putRaw(out, ViewInt(p.view));
    if (f.range) putRaw(out, p.range_m);
    if (f.intensity) putRaw(out, IntensityInt(p.intensity));
    if (f.returns) {
        putRaw(out, p.return_number);
        putRaw(out, p.returns);
    }
    if (f.incidence) putRaw(out, p.incidence_deg);
    if (f.scan_angle) putRaw(out, p.scan_angle_deg);
    if (f.height_above_ground) putRaw(out, p.height_above_ground_m);
}
void putFloat(std::string& s, float v);
void putUnsigned(std::string& s, std::uint32_t v);
/// The optional fields of `p` that `fields` turns on, each after a space, as the ascii
/// PCD and PLY records write them (the same numbers in both).
void putTextFields(std::string& s, const core::CloudPoint& p, const core::CloudFields& fields);

class CountedWriter : public FormatWriter {
  public:
    /// Flushes the records, then writes the point count at each of the header's count fields.
    void finish() override;

  protected:
    /// `header` is the text header with paddedCount(0) at each byte offset of `count_at`.
    CountedWriter(platform::TempFile& file, std::string header, std::vector<long> count_at);

    /// Appends records of `record_bytes` each, `write(out, point)` filling one.
    template <class Write>
    void appendBinary(std::span<const core::CloudPoint> points, std::size_t record_bytes, Write write) {
        std::size_t done = 0;
        while (done < points.size()) {
            const std::size_t room =
                std::max<std::size_t>(1, (kFlushBytes - std::min(kFlushBytes, buffer_.size())) / record_bytes);
            const std::size_t n = std::min(room, points.size() - done);
            const std::size_t old = buffer_.size();
            buffer_.resize(old + n * record_bytes);
            char* out = buffer_.data() + old;
            for (std::size_t i = done; i < done + n; ++i) write(out, points[i]);
            done += n;
            count_ += n;
            flushIfFull();
        }
    }
    /// Appends one text line per point, `write(buffer, point)` adding it without its newline.
    template <class Write>
    void appendText(std::span<const core::CloudPoint> points, Write write) {
        for (const core::CloudPoint& p : points) {
            write(buffer_, p);
            buffer_ += '\n';
            ++count_;
            flushIfFull();
        }
    }

  private:
    static constexpr std::size_t kFlushBytes = 8u << 20;
    void flushIfFull();
    [[noreturn]] void fail(const std::string& what) const;

    std::string where_;  // "output: <path>"
    std::FILE* file_;
    std::vector<long> count_at_;
    std::string buffer_;
    std::size_t count_ = 0;
};

}  // namespace io::detail
