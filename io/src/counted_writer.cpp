// counted_writer: the stream, buffer and point-count fix-up the PCD and PLY writers share.
#include "counted_writer.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <unistd.h>

namespace io::detail {

static_assert(std::endian::native == std::endian::little,
              "the PCD and PLY writers write little-endian records with memcpy");

std::string paddedCount(std::size_t n) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%0*zu", kCountDigits, n);
    return buf;
}

std::string originText(const glm::dvec3& o) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", o.x, o.y, o.z);
    return buf;
}

std::vector<OptionalField> optionalFields(const core::CloudFields& f) {
    std::vector<OptionalField> out;
    if (f.label) out.push_back(OptionalField::Label);
    if (f.view) out.push_back(OptionalField::View);
    if (f.range) out.push_back(OptionalField::Range);
    if (f.intensity) out.push_back(OptionalField::Intensity);
    if (f.returns) {
        out.push_back(OptionalField::ReturnNumber);
        out.push_back(OptionalField::Returns);
    }
    if (f.incidence) out.push_back(OptionalField::Incidence);
    if (f.scan_angle) out.push_back(OptionalField::ScanAngle);
    if (f.height_above_ground) out.push_back(OptionalField::Height);
    return out;
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

void putTextFields(std::string& s, const core::CloudPoint& p, const core::CloudFields& fields) {
    if (fields.label) {
        s += ' ';
        putUnsigned(s, std::uint32_t(p.label));
    }
    if (fields.view) {
        s += ' ';
        putUnsigned(s, p.view);
    }
    if (fields.range) {
        s += ' ';
        putFloat(s, p.range_m);
    }
    if (fields.intensity) {
        s += ' ';
        putUnsigned(s, p.intensity);
    }
    if (fields.returns) {
        s += ' ';
        putUnsigned(s, p.return_number);
        s += ' ';
        putUnsigned(s, p.returns);
    }
    const std::pair<bool, float> floats[] = {{fields.incidence, p.incidence_deg},
                                             {fields.scan_angle, p.scan_angle_deg},
                                             {fields.height_above_ground, p.height_above_ground_m}};
    for (const auto& [on, v] : floats) {
        if (!on) continue;
        s += ' ';
        putFloat(s, v);
    }
}

CountedWriter::CountedWriter(platform::TempFile& file, std::string header, std::vector<long> count_at)
    : where_("output: " + file.destination().string()), file_(file.file()), count_at_(std::move(count_at)) {
    buffer_.reserve(kFlushBytes + 4096);
    header_bytes_ = header.size();
    buffer_ = std::move(header);
}

std::uint64_t CountedWriter::recordOffset(std::uint64_t index, std::size_t record_bytes) {
    const std::lock_guard lock(flushing_);
    if (!buffer_.empty()) {
        if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) fail("write failed");
        buffer_.clear();
        buffer_.shrink_to_fit();  // the records read back take its place in memory
    }
    if (std::fflush(file_) != 0) fail("write failed");
    return header_bytes_ + index * record_bytes;
}

void CountedWriter::transfer(bool write, char* data, std::size_t bytes, std::uint64_t offset) const {
    const int fd = ::fileno(file_);
    while (bytes > 0) {
        const ssize_t n = write ? ::pwrite(fd, data, bytes, off_t(offset)) : ::pread(fd, data, bytes, off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            if (n == 0) errno = EIO;  // the file is shorter than the records written to it
            fail(write ? "cannot rewrite points" : "cannot read points back");
        }
        data += n;
        bytes -= std::size_t(n);
        offset += std::uint64_t(n);
    }
}

void CountedWriter::fail(const std::string& what) const {
    throw core::Error(where_ + ": " + what + ": " + std::strerror(errno));
}

void CountedWriter::flushIfFull() {
    if (buffer_.size() < kFlushBytes) return;
    if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) fail("write failed");
    buffer_.clear();
}

void CountedWriter::appendPacked(const char* data, std::size_t bytes, std::size_t records) {
    // What is buffered (the header, at first) goes first; the records, already packed in
    // memory of the caller's, are written from there in one call.
    if (!buffer_.empty()) {
        if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) fail("write failed");
        buffer_.clear();
    }
    if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes) fail("write failed");
    count_ += records;
}

void CountedWriter::finish() {
    if (!buffer_.empty() && std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
        fail("write failed");
    buffer_.clear();
    buffer_.shrink_to_fit();
    const std::string count = paddedCount(count_);
    if (count.size() != std::size_t(kCountDigits)) {
        errno = EFBIG;
        fail("too many points for the header");
    }
    for (long at : count_at_) {
        if (std::fseek(file_, at, SEEK_SET) != 0 || std::fwrite(count.data(), 1, count.size(), file_) != count.size())
            fail("cannot write the point count");
    }
}

}  // namespace io::detail
