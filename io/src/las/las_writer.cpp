// las_writer: uncompressed LAS 1.4 through LASzip (docs/formats.md). The records go through a std::ostream over
// the TempFile's descriptor; the header's counts and bounds are written at the end from
// our own inventory of the records (LasRecord::patchHeader).
#include "las_record.hpp"
#include "format_writer.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <ext/stdio_filebuf.h>

#include <ostream>

namespace io::detail {

using core::Error;
using core::CloudPoint;

namespace {

class LasWriter final : public FormatWriter {
public:
    LasWriter(platform::TempFile& file, const LasRecord& record)
        : record_(record), fd_(fileno(file.file())), buf_(file.file(), std::ios::out | std::ios::binary),
          stream_(&buf_) {
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
            record_.fill(*point_, p, inventory_.points);
            inventory_.add(*point_);
            check(laszip_write_point(zip_), "write");
        }
    }

    void finish() override {
        open_ = false;
        check(laszip_close_writer(zip_), "close");
        stream_.flush();
        if (!stream_) throw Error(record_.where() + ": write failed");
        record_.patchHeader(fd_, inventory_);
    }

private:
    void check(laszip_I32 rc, const char* what) {
        if (!stream_) throw Error(record_.where() + ": LASzip " + what + " failed: write failed");
        record_.check(zip_, rc, what);
    }

    LasRecord record_;
    int fd_;
    __gnu_cxx::stdio_filebuf<char> buf_;
    std::ostream stream_;
    laszip_POINTER zip_ = nullptr;
    laszip_point_struct* point_ = nullptr;
    LasInventory inventory_;
    bool open_ = false;
};

}  // namespace

std::unique_ptr<FormatWriter> openLasWriter(platform::TempFile& file, const glm::dvec3& origin,
                                            const core::CloudFields& fields, const LasOptions& options) {
    return std::make_unique<LasWriter>(file, LasRecord("output: " + file.destination().string(), origin, fields, options));
}

}  // namespace io::detail
