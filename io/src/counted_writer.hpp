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
#include <mutex>
#include <span>
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
/// Reads a `T` from `in` and moves past it.
template <typename T>
T getRaw(const char*& in) {
    T v;
    std::memcpy(&v, in, sizeof v);
    in += sizeof v;
    return v;
}
/// Reads back what putBinaryFields wrote, into the fields `f` turns on.
template <typename ViewInt, typename IntensityInt>
void getBinaryFields(const char*& in, core::CloudPoint& p, const core::CloudFields& f) {
    if (f.label) p.label = core::Role(getRaw<std::uint8_t>(in));
    if (f.view) p.view = std::uint16_t(getRaw<ViewInt>(in));
    if (f.range) p.range_m = getRaw<float>(in);
    if (f.intensity) p.intensity = std::uint16_t(getRaw<IntensityInt>(in));
    if (f.returns) {
        p.return_number = getRaw<std::uint8_t>(in);
        p.returns = getRaw<std::uint8_t>(in);
    }
    if (f.incidence) p.incidence_deg = getRaw<float>(in);
    if (f.scan_angle) p.scan_angle_deg = getRaw<float>(in);
    if (f.height_above_ground) p.height_above_ground_m = getRaw<float>(in);
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
    /// FormatWriter::readBack for records of `record_bytes` each, `read(in, point)` filling
    /// one point from one record. The caller (CloudWriter) keeps the range within count().
    template <class Read>
    std::size_t readBackBinary(std::uint64_t first, std::span<core::CloudPoint> out, std::size_t record_bytes,
                               Read read) {
        std::vector<char> bytes(std::min(out.size(), kRecordsPerCall) * record_bytes);
        for (std::size_t done = 0; done < out.size();) {
            const std::size_t n = std::min(out.size() - done, kRecordsPerCall);
            transfer(false, bytes.data(), n * record_bytes, recordOffset(first + done, record_bytes));
            const char* in = bytes.data();
            for (std::size_t i = done; i < done + n; ++i) read(in, out[i]);
            done += n;
        }
        return out.size();
    }
    /// FormatWriter::rewrite for records of `record_bytes` each, `write(out, point)` filling one.
    template <class Write>
    void rewriteBinary(std::uint64_t first, std::span<const core::CloudPoint> points, std::size_t record_bytes,
                       Write write) {
        std::vector<char> bytes(std::min(points.size(), kRecordsPerCall) * record_bytes);
        for (std::size_t done = 0; done < points.size();) {
            const std::size_t n = std::min(points.size() - done, kRecordsPerCall);
            char* out = bytes.data();
            for (std::size_t i = done; i < done + n; ++i) write(out, points[i]);
            transfer(true, bytes.data(), n * record_bytes, recordOffset(first + done, record_bytes));
            done += n;
        }
    }
    /// Appends `records` records already packed, `bytes` bytes in all, after what is buffered.
    void appendPacked(const char* data, std::size_t bytes, std::size_t records);
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
    static constexpr std::size_t kFlushBytes = 256u << 10;
    // Records read back or rewritten per system call: a buffer of well under a MiB.
    static constexpr std::size_t kRecordsPerCall = 8192;
    void flushIfFull();
    // The byte offset of record `index`, after flushing what is buffered (once, whichever
    // thread comes first).
    std::uint64_t recordOffset(std::uint64_t index, std::size_t record_bytes);
    // pwrite (`write`) or pread of exactly `bytes` bytes at `offset` of the file.
    void transfer(bool write, char* data, std::size_t bytes, std::uint64_t offset) const;
    [[noreturn]] void fail(const std::string& what) const;

    std::string where_;  // "output: <path>"
    std::FILE* file_;
    std::vector<long> count_at_;
    std::string buffer_;
    std::size_t count_ = 0;
    std::uint64_t header_bytes_ = 0;
    std::mutex flushing_;  // readBack and rewrite may run on two threads
};

/// A CountedWriter of text lines or binary records of `record_bytes` each, made by
/// `Derived`'s text(line, point), binary(out, point) and unbinary(in, point) (the PCD and
/// PLY writers); binary records can be read back and rewritten in place.
template <class Derived>
class RecordWriter : public CountedWriter {
  public:
    void append(std::span<const core::CloudPoint> points) override {
        if (ascii_)
            appendText(points, [this](std::string& s, const core::CloudPoint& p) { self().text(s, p); });
        else
            appendBinary(points, record_bytes_,
                         [this](char*& out, const core::CloudPoint& p) { self().binary(out, p); });
    }
    bool rewritable() const override { return !ascii_; }
    std::size_t recordBytes() const override { return ascii_ ? 0 : record_bytes_; }
    std::size_t readBack(std::uint64_t first, std::span<core::CloudPoint> out) override {
        return readBackBinary(first, out, record_bytes_,
                              [this](const char*& in, core::CloudPoint& p) { self().unbinary(in, p); });
    }
    void rewrite(std::uint64_t first, std::span<const core::CloudPoint> points) override {
        rewriteBinary(first, points, record_bytes_,
                      [this](char*& out, const core::CloudPoint& p) { self().binary(out, p); });
    }
    void packRecords(std::span<const core::CloudPoint> points, char* out) const override {
        for (const core::CloudPoint& p : points) self().binary(out, p);
    }
    void appendRecords(const char* records, std::size_t count) override {
        appendPacked(records, count * record_bytes_, count);
    }

  protected:
    RecordWriter(platform::TempFile& file, std::string header, std::vector<long> count_at, bool ascii,
                 std::size_t record_bytes)
        : CountedWriter(file, std::move(header), std::move(count_at)), ascii_(ascii), record_bytes_(record_bytes) {}

  private:
    const Derived& self() const { return static_cast<const Derived&>(*this); }

    bool ascii_;
    std::size_t record_bytes_;
};

}  // namespace io::detail
