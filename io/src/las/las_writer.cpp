// las_writer: uncompressed LAS 1.4 through LASzip (docs/formats.md). The records go through a std::ostream over
// the TempFile's stream that keeps the reason of a failed write (a full disk is named as
// such); the header's counts and bounds are written at the end from our own inventory of
// the records (LasRecord::patchHeader).
#include "las_record.hpp"
#include "format_writer.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <sys/types.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ostream>
#include <streambuf>

namespace io::detail {

using core::CloudPoint;
using core::Error;

namespace {

/// A std::streambuf onto a FILE* that keeps the errno of the first failed write (an
/// ostream keeps only its fail bit, and LASzip reports only that a write failed).
class FileBuf final : public std::streambuf {
  public:
    explicit FileBuf(std::FILE* file) : file_(file) {}
    /// 0, or the errno of the first write or flush that failed.
    int error() const { return error_; }

  protected:
    int_type overflow(int_type c) override {
        if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
        const char ch = traits_type::to_char_type(c);
        return put(&ch, 1) ? c : traits_type::eof();
    }
    std::streamsize xsputn(const char* s, std::streamsize n) override { return put(s, std::size_t(n)) ? n : 0; }
    int sync() override {
        if (error_ == 0 && std::fflush(file_) == 0) return 0;
        if (error_ == 0) error_ = errno ? errno : EIO;
        return -1;
    }
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        if (!(off == 0 && dir == std::ios_base::cur)) {
            const int whence = dir == std::ios_base::beg ? SEEK_SET : dir == std::ios_base::cur ? SEEK_CUR : SEEK_END;
            if (::fseeko(file_, off_t(off), whence) != 0) return pos_type(off_type(-1));
        }
        return pos_type(off_type(::ftello(file_)));
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }

  private:
    bool put(const char* s, std::size_t n) {
        if (error_ != 0) return false;
        errno = 0;
        if (std::fwrite(s, 1, n, file_) == n) return true;
        error_ = errno ? errno : EIO;
        return false;
    }

    std::FILE* file_;
    int error_ = 0;
};

class LasWriter final : public FormatWriter {
  public:
    LasWriter(platform::TempFile& file, const LasRecord& record)
        : record_(record), fd_(fileno(file.file())), buf_(file.file()), stream_(&buf_) {
        if (laszip_create(&zip_) != 0 || !zip_) throw Error(record_.where() + ": LASzip could not be started");
        record_.setUp(zip_);
        check(laszip_get_point_pointer(zip_, &point_), "point");
        check(laszip_open_writer_stream(zip_, stream_, 0, 0), "open");
        open_ = true;
    }
    ~LasWriter() override {
        if (open_) laszip_close_writer(zip_);
        if (zip_) laszip_destroy(zip_);
    }
    LasWriter(const LasWriter&) = delete;
    LasWriter& operator=(const LasWriter&) = delete;

    void append(std::span<const CloudPoint> points) override {
        for (const CloudPoint& p : points) {
            record_.fill(*point_, p, inventory_.points, &inventory_);
            check(laszip_write_point(zip_), "write");
        }
    }

    void appendForeign(std::span<const CloudPoint> points, const unsigned char* records) override {
        const std::size_t stride = record_.foreign() ? record_.foreign()->stride() : 0;
        for (std::size_t i = 0; i < points.size(); ++i) {
            record_.fill(*point_, points[i], inventory_.points, &inventory_, records + i * stride);
            check(laszip_write_point(zip_), "write");
        }
    }

    void finish() override {
        open_ = false;
        check(laszip_close_writer(zip_), "close");
        stream_.flush();
        if (buf_.error() != 0 || !stream_) throw writeFailed();
        record_.patchHeader(fd_, inventory_);
    }

  private:
    void check(laszip_I32 rc, const char* what) {
        if (buf_.error() != 0 || !stream_) throw writeFailed();
        record_.check(zip_, rc, what);
    }

    // As the other formats word it: "write failed: No space left on device".
    Error writeFailed() const {
        return Error(record_.where() + ": write failed: " + std::strerror(buf_.error() != 0 ? buf_.error() : EIO));
    }

    LasRecord record_;
    int fd_;
    FileBuf buf_;
    std::ostream stream_;
    laszip_POINTER zip_ = nullptr;
    laszip_point_struct* point_ = nullptr;
    LasInventory inventory_;
    bool open_ = false;
};

}  // namespace

std::unique_ptr<FormatWriter> openLasWriter(platform::TempFile& file, const glm::dvec3& origin,
                                            const core::CloudFields& fields, const LasOptions& options) {
    return std::make_unique<LasWriter>(file,
                                       LasRecord("output: " + file.destination().string(), origin, fields, options));
}

}  // namespace io::detail
