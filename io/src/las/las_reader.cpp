// las_reader: LAS 1.0-1.4 and LAZ through LASzip, behind io::CloudReader. The header
// and the VLRs are checked here first, bounded by the bytes present (LASzip trusts
// them), and so is the layout of compressed data that LASzip would otherwise trust: the
// LASzip VLR's compressor and items against the point format, the chunk table's place
// and count against the file, and each layered chunk's layer sizes against the bytes it
// can have. Then LASzip decodes the points from a stream over the ByteSource, a chunk at
// a time. Coordinates are computed in double and moved onto a double origin (whole metres
// near the middle of the header's bounds, or of the first point when the bounds are far
// from it) before the cast to float. Classes map to roles
// (roleForClass), unless the file has our `label` extra bytes (docs/formats.md). For
// `ladarvr info` the same reader also records the header's fields and VLRs and counts
// the raw records (las_facts.hpp).
#include "cloud_decode.hpp"
#include "crs_wkt.hpp"
#include "las_facts.hpp"

#include <io/las_crs.hpp>

#include <core/error.hpp>

#include <laszip/laszip_api.h>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <istream>
#include <streambuf>

namespace io::detail {

using core::CloudFields;
using core::CloudPoint;
using core::Error;
using core::packRgb;
using core::Role;

namespace {

// Bytes of the fixed fields of point formats 0..10.
constexpr std::array<std::size_t, 11> kMinRecord = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
constexpr std::size_t kVlrHeader = 54;
constexpr std::size_t kExtraBytesDescriptor = 192;

// LASzip's compressors (the VLR's first field) and item types.
constexpr unsigned kPointwise = 1, kPointwiseChunked = 2, kLayeredChunked = 3;
// How far (in the file's units) the first point may lie outside the header's bounds before
// the local frame is placed on it instead: far enough that rounding or a stale header that
// is nearly right keeps the bounds' frame (and its outputs), near enough that floats there
// still hold millimetres.
constexpr double kBoundsSlack = 1000.0;
enum ItemType : unsigned {
    kByte = 0,
    kPoint10 = 6,
    kGpsTime11 = 7,
    kRgb12 = 8,
    kWavePacket13 = 9,
    kPoint14 = 10,
    kRgb14 = 11,
    kRgbNir14 = 12,
    kWavePacket14 = 13,
    kByte14 = 14
};
constexpr std::uint32_t kVariableChunks = 0xFFFFFFFFu;  // chunk size of tables with point counts

template <typename T>
T le(std::string_view bytes, std::size_t at) {
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return v;
}

/// A read-only, seekable std::streambuf over a ByteSource (LASzip reads through an
/// istream and seeks to LAZ's chunk table).
class SourceBuf final : public std::streambuf {
  public:
    explicit SourceBuf(ByteSource& source) : source_(source) {}

  protected:
    int_type underflow() override {
        if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
        const std::uint64_t at = base_ + std::uint64_t(egptr() - eback());
        if (at >= source_.size()) return traits_type::eof();
        const std::size_t n = std::size_t(std::min<std::uint64_t>(kBlock, source_.size() - at));
        const std::string_view v = source_.view(at, n);
        block_.assign(v.begin(), v.end());
        base_ = at;
        setg(block_.data(), block_.data(), block_.data() + block_.size());
        return traits_type::to_int_type(*gptr());
    }

    std::streamsize xsgetn(char* out, std::streamsize n) override {
        std::streamsize done = 0;
        while (done < n) {
            if (gptr() == egptr() && underflow() == traits_type::eof()) break;
            const std::streamsize take = std::min<std::streamsize>(n - done, egptr() - gptr());
            std::memcpy(out + done, gptr(), std::size_t(take));
            gbump(int(take));
            done += take;
        }
        return done;
    }

    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        const std::int64_t here = std::int64_t(base_) + (gptr() - eback());
        const std::int64_t from = dir == std::ios_base::beg   ? 0
                                  : dir == std::ios_base::cur ? here
                                                              : std::int64_t(source_.size());
        return seekpos(pos_type(off_type(from + off)), std::ios_base::in);
    }

    pos_type seekpos(pos_type pos, std::ios_base::openmode) override {
        const std::int64_t at = std::int64_t(pos);
        if (at < 0 || std::uint64_t(at) > source_.size()) return pos_type(off_type(-1));
        base_ = std::uint64_t(at);
        block_.clear();
        setg(nullptr, nullptr, nullptr);
        return pos;
    }

  private:
    static constexpr std::size_t kBlock = 1u << 16;
    ByteSource& source_;
    std::vector<char> block_;
    std::uint64_t base_ = 0;  // file offset of eback()
};

struct ExtraField {
    bool present = false;
    int type = 0;  // LAS data type 1..10
    std::size_t offset = 0;
};

double extraValue(const unsigned char* bytes, const ExtraField& f) {
    switch (f.type) {
        case 1: return bytes[f.offset];
        case 2: return std::int8_t(bytes[f.offset]);
        case 3: {
            std::uint16_t v;
            std::memcpy(&v, bytes + f.offset, 2);
            return v;
        }
        case 4: {
            std::int16_t v;
            std::memcpy(&v, bytes + f.offset, 2);
            return v;
        }
        case 5: {
            std::uint32_t v;
            std::memcpy(&v, bytes + f.offset, 4);
            return v;
        }
        case 6: {
            std::int32_t v;
            std::memcpy(&v, bytes + f.offset, 4);
            return v;
        }
        case 7: {
            std::uint64_t v;
            std::memcpy(&v, bytes + f.offset, 8);
            return double(v);
        }
        case 8: {
            std::int64_t v;
            std::memcpy(&v, bytes + f.offset, 8);
            return double(v);
        }
        case 9: {
            float v;
            std::memcpy(&v, bytes + f.offset, 4);
            return v;
        }
        default: {
            double v;
            std::memcpy(&v, bytes + f.offset, 8);
            return v;
        }
    }
}

class LasReader final : public FormatReader {
  public:
    LasReader(ByteSource& source, const std::string& prefix, LasFacts* facts = nullptr, LasTally* tally = nullptr,
              bool keep_foreign = false, bool positions_only = false)
        : source_(source),
          prefix_(prefix),
          buf_(source),
          stream_(&buf_),
          facts_(facts),
          tally_(tally),
          keep_foreign_(keep_foreign),
          positions_only_(positions_only) {
        checkHeader();
        if (keep_foreign_ && !label_.present) makeForeignHeader();
        stride_ = foreign ? foreign->stride() : 0;
        if (tally_) label_ = ExtraField{};  // counted as it is, not read as our roles
        if (compressed_) {
            try {
                startDecoder();
            } catch (...) {
                stopDecoder();  // no destructor runs for a constructor that throws
                throw;
            }
        } else {
            openLaszip();
        }
    }

    ~LasReader() override {
        if (open_) laszip_close_reader(zip_);
        if (zip_) laszip_destroy(zip_);
        stopDecoder();
    }
    LasReader(const LasReader&) = delete;
    LasReader& operator=(const LasReader&) = delete;

    std::size_t next(std::vector<CloudPoint>& out, std::size_t max_points) override {
        const std::size_t n = std::min(max_points, declared - done_);
        out.reserve(out.size() + n);
        std::vector<unsigned char>* records = stride_ > 0 ? foreign_out : nullptr;
        if (records) records->reserve(records->size() + n * stride_);
        if (compressed_) {
            for (std::size_t k = 0; k < n;) {
                if (pending_at_ == pending_.size()) receive(done_ + k);
                const std::size_t take = std::min(n - k, pending_.size() - pending_at_);
                out.insert(out.end(), pending_.begin() + std::ptrdiff_t(pending_at_),
                           pending_.begin() + std::ptrdiff_t(pending_at_ + take));
                if (records)
                    records->insert(records->end(), pending_foreign_.begin() + std::ptrdiff_t(pending_at_ * stride_),
                                    pending_foreign_.begin() + std::ptrdiff_t((pending_at_ + take) * stride_));
                pending_at_ += take;
                k += take;
            }
        } else {
            for (std::size_t k = 0; k < n; ++k) {
                if (laszip_read_point(zip_) != 0) pointFailed(done_ + k);
                out.push_back(convert(*point_, done_ + k));
                if (records) {
                    records->resize(records->size() + stride_);
                    foreignRecord(*point_, records->data() + records->size() - stride_);
                }
            }
        }
        done_ += n;
        return n;
    }

  private:
    void openLaszip() {
        if (laszip_create(&zip_) != 0 || !zip_) throw Error(prefix_ + ": LASzip could not be started");
        if (positions_only_ && compressed_) {
            // LAS 1.4's layered compression keeps each field group in a layer of its own
            // within a chunk, so the others are skipped, not decoded: x, y (with the
            // returns), z and the point source ID (the view), and the extra bytes where
            // they hold the range that decides which points are dropped. Older formats
            // are decoded whole whatever is asked.
            laszip_U32 layers = laszip_DECOMPRESS_SELECTIVE_CHANNEL_RETURNS_XY | laszip_DECOMPRESS_SELECTIVE_Z |
                                laszip_DECOMPRESS_SELECTIVE_POINT_SOURCE;
            if (range_.present) layers |= laszip_DECOMPRESS_SELECTIVE_EXTRA_BYTES;
            check(laszip_decompress_selective(zip_, layers), "cannot select the fields to decode");
        }
        laszip_BOOL compressed = 0;
        check(laszip_open_reader_stream(zip_, stream_, &compressed), "cannot open");
        open_ = true;
        check(laszip_get_point_pointer(zip_, &point_), "cannot read");
    }

    // The point LASzip decoded, as a CloudPoint in the local frame. Throws Error (a label
    // other than 0..2); counts unknown classes in `stats`.
    CloudPoint convert(const laszip_point_struct& q, std::size_t index) {
        if (tally_) tallyRecord(q);
        CloudPoint p;
        p.position = glm::vec3(float(double(q.X) * scale_.x + offset_.x - origin.x),
                               float(double(q.Y) * scale_.y + offset_.y - origin.y),
                               float(double(q.Z) * scale_.z + offset_.z - origin.z));
        p.intensity = q.intensity;
        p.view = q.point_source_ID;
        if (extended_) {
            p.return_number = q.extended_return_number;
            p.returns = q.extended_number_of_returns;
            p.scan_angle_deg = float(q.extended_scan_angle * 0.006);
        } else {
            p.return_number = q.return_number;
            p.returns = q.number_of_returns;
            p.scan_angle_deg = float(q.scan_angle_rank);
        }
        if (fields.rgb)
            p.rgb = packRgb(std::uint8_t(q.rgb[0] >> 8), std::uint8_t(q.rgb[1] >> 8), std::uint8_t(q.rgb[2] >> 8));
        const unsigned char* extra = q.num_extra_bytes >= int(extra_size_) ? q.extra_bytes : nullptr;
        if (label_.present && extra) {
            const double v = extraValue(extra, label_);
            if (!(v == 0.0 || v == 1.0 || v == 2.0)) {
                char shown_v[32];  // %g: any double (a float extra byte may hold 1e31 or NaN)
                std::snprintf(shown_v, sizeof shown_v, "%g", v);
                throw Error(prefix_ + ": point " + std::to_string(index) + ": label " + shown_v +
                            " is not 0 (ground), 1 (environment) or 2 (target)");
            }
            p.label = Role(std::uint8_t(v));
        } else {
            const unsigned cls = extended_ ? q.extended_classification : q.classification;
            bool known = true;
            p.label = roleForClass(cls, known);
            // With side records kept, the class itself is written back: nothing to warn of.
            if (!known && stride_ == 0 && stats.unknown_classes++ == 0) stats.first_unknown = cls;
        }
        if (extra) {
            if (range_.present) p.range_m = float(extraValue(extra, range_));
            if (incidence_.present) p.incidence_deg = float(extraValue(extra, incidence_));
            if (height_.present) p.height_above_ground_m = float(extraValue(extra, height_));
        }
        return p;
    }

    // Counts one record into tally_, as the file holds it.
    void tallyRecord(const laszip_point_struct& q) {
        LasTally& t = *tally_;
        const std::array<std::int32_t, 3> xyz = {q.X, q.Y, q.Z};
        for (std::size_t k = 0; k < 3; ++k) {
            t.xyz_min[k] = t.points == 0 ? xyz[k] : std::min(t.xyz_min[k], xyz[k]);
            t.xyz_max[k] = t.points == 0 ? xyz[k] : std::max(t.xyz_max[k], xyz[k]);
            if (fields.rgb) t.rgb_max[k] = std::max(t.rgb_max[k], q.rgb[k]);
        }
        ++t.points;
        ++t.classes[extended_ ? q.extended_classification : q.classification];
        ++t.returns[(extended_ ? q.extended_return_number : q.return_number) & 15u];
    }

    // Compressed points are decoded in a child process. LASzip trusts the arithmetic-coded
    // data inside a chunk, and a build with assertions aborts on symbols a corrupt file
    // makes (ArithmeticDecoder::decodeSymbol), which no check of sizes and offsets can
    // foresee short of decoding the data; in a child, a fault or an abort of LASzip ends
    // only the child, and the reader reports it as one line. The child (forked with the
    // header already checked, reading the same ByteSource) sends frames over a pipe: one
    // "open" or error frame, then frames of converted points, or an error; when records
    // are counted, each frame of points follows a frame of the tally so far.
    struct Frame {
        char kind = 0;  // 'O' opened, 'P' points, 'E' error message, 'T' tally
        std::uint32_t bytes = 0;
        std::uint64_t unknown_classes = 0;  // so far, with 'P'
        std::uint32_t first_unknown = 0;
    };
    static constexpr std::size_t kFramePoints = 4096;

    void startDecoder() {
        // The point the child is decoding, shared, so that a fault can be placed exactly.
        void* shared =
            ::mmap(nullptr, sizeof(std::uint64_t), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (shared == MAP_FAILED) throw Error(prefix_ + ": cannot start the LAZ decoder: " + std::strerror(errno));
        decoding_ = static_cast<std::uint64_t*>(shared);
        *decoding_ = 0;
        int fds[2];
        if (::pipe2(fds, O_CLOEXEC) != 0)
            throw Error(prefix_ + ": cannot start the LAZ decoder: " + std::strerror(errno));
        const pid_t pid = ::fork();
        if (pid < 0) {
            const int e = errno;
            ::close(fds[0]);
            ::close(fds[1]);
            throw Error(prefix_ + ": cannot start the LAZ decoder: " + std::strerror(e));
        }
        if (pid == 0) {
            ::close(fds[0]);
            decodeInChild(fds[1]);  // never returns
        }
        ::close(fds[1]);
        ::fcntl(fds[0], F_SETPIPE_SZ, 1 << 20);  // fewer switches between the two; best effort
        child_ = pid;
        pipe_ = fds[0];
        receive(0);  // 'O', or the error of opening
    }

    [[noreturn]] void decodeInChild(int fd) noexcept {
        // The parent's handlers (temporary file cleanup, a sanitizer's or fuzzer's crash
        // report) are not the child's to run: it ends by the signal, which the parent reports.
        for (const int sig : {SIGINT, SIGTERM, SIGPIPE, SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL})
            std::signal(sig, SIG_DFL);
        // LASzip's own words on stderr (an assertion's) would be a second line: the
        // parent reports how the child ended.
        const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (null >= 0) ::dup2(null, STDERR_FILENO);
        try {
            openLaszip();
            send(fd, Frame{'O'}, nullptr);
            // A frame's payload: its points, then their side records when kept.
            std::vector<unsigned char> batch;
            const std::size_t per_point = sizeof(CloudPoint) + stride_;
            batch.reserve(kFramePoints * per_point);
            for (std::size_t i = 0; i < declared;) {
                const std::size_t n = std::min(kFramePoints, declared - i);
                batch.resize(n * per_point);
                for (std::size_t k = 0; k < n; ++k, ++i) {
                    __atomic_store_n(decoding_, std::uint64_t(i), __ATOMIC_RELAXED);
                    if (laszip_read_point(zip_) != 0) pointFailed(i);
                    const CloudPoint p = convert(*point_, i);
                    std::memcpy(batch.data() + k * sizeof(CloudPoint), &p, sizeof p);
                    if (stride_ > 0) foreignRecord(*point_, batch.data() + n * sizeof(CloudPoint) + k * stride_);
                }
                if (tally_) send(fd, Frame{'T', std::uint32_t(sizeof(LasTally))}, tally_);
                Frame f{'P', std::uint32_t(batch.size()), stats.unknown_classes, stats.first_unknown};
                send(fd, f, batch.data());
            }
        } catch (const Error& e) {
            const std::string m = e.what();
            send(fd, Frame{'E', std::uint32_t(std::min<std::size_t>(m.size(), 4096))}, m.data());
        } catch (...) {
            const std::string m = prefix_ + ": the LAZ decoder failed";
            send(fd, Frame{'E', std::uint32_t(m.size())}, m.data());
        }
        ::_exit(0);
    }

    static void send(int fd, const Frame& f, const void* payload) noexcept {
        if (!writeAll(fd, &f, sizeof f) || (f.bytes > 0 && !writeAll(fd, payload, f.bytes))) ::_exit(0);
    }

    static bool writeAll(int fd, const void* data, std::size_t n) noexcept {
        const char* p = static_cast<const char*>(data);
        while (n > 0) {
            const ssize_t w = ::write(fd, p, n);
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0) return false;
            p += w;
            n -= std::size_t(w);
        }
        return true;
    }

    // false at the end of the pipe (the child gone) before `n` bytes.
    bool readAll(void* data, std::size_t n) {
        char* p = static_cast<char*>(data);
        while (n > 0) {
            const ssize_t r = ::read(pipe_, p, n);
            if (r < 0 && errno == EINTR) continue;
            if (r <= 0) return false;
            p += r;
            n -= std::size_t(r);
        }
        return true;
    }

    // The next frame: points into pending_, or the child's error, or how it ended.
    // `index`: the point being waited for, for messages.
    void receive(std::size_t index) {
        Frame f;
        if (!readAll(&f, sizeof f)) decoderDied(index);
        if (f.kind == 'T') {
            if (!tally_ || f.bytes != sizeof(LasTally) || !readAll(tally_, sizeof(LasTally))) decoderDied(index);
            if (!readAll(&f, sizeof f)) decoderDied(index);
        }
        if (f.kind == 'O') return;
        if (f.kind == 'E') {
            std::string m(f.bytes, '\0');
            if (!readAll(m.data(), m.size())) decoderDied(index);
            throw Error(m);
        }
        const std::size_t per_point = sizeof(CloudPoint) + stride_;
        if (f.kind != 'P' || f.bytes == 0 || f.bytes % per_point != 0 || f.bytes / per_point > kFramePoints)
            decoderDied(index);
        const std::size_t n = f.bytes / per_point;
        pending_.resize(n);
        pending_at_ = 0;
        if (!readAll(pending_.data(), n * sizeof(CloudPoint))) decoderDied(index);
        pending_foreign_.resize(n * stride_);
        if (stride_ > 0 && !readAll(pending_foreign_.data(), pending_foreign_.size())) decoderDied(index);
        stats.unknown_classes = std::size_t(f.unknown_classes);
        stats.first_unknown = f.first_unknown;
    }

    [[noreturn]] void decoderDied(std::size_t index) {
        if (decoding_) index = std::max<std::size_t>(index, std::size_t(__atomic_load_n(decoding_, __ATOMIC_RELAXED)));
        int status = 0;
        std::string how = "ended without a word";
        if (child_ > 0 && ::waitpid(child_, &status, 0) == child_) {
            child_ = -1;
            if (WIFSIGNALED(status)) {
                const char* name = sigabbrev_np(WTERMSIG(status));
                how = std::string("stopped by SIG") + (name ? name : std::to_string(WTERMSIG(status)).c_str());
            } else if (WIFEXITED(status)) {
                how = "exited with status " + std::to_string(WEXITSTATUS(status));
            }
        }
        throw Error(prefix_ + ": point " + std::to_string(index) + " of " + std::to_string(declared) +
                    ": the compressed point data cannot be decoded; the LAZ file is corrupt (LASzip " + how +
                    " in the decoding process)");
    }

    void stopDecoder() noexcept {
        if (pipe_ >= 0) ::close(pipe_);
        pipe_ = -1;
        if (child_ > 0) {
            ::kill(child_, SIGKILL);  // done or abandoned: nothing of it is needed
            while (::waitpid(child_, nullptr, 0) < 0 && errno == EINTR) {}
            child_ = -1;
        }
        if (decoding_) ::munmap(decoding_, sizeof(std::uint64_t));
        decoding_ = nullptr;
    }

    // LASzip's message ("reading point 0 of 4096 total points") names neither the cause
    // nor what is allowed: the checks before it leave a decoding failure or a file cut
    // short inside a chunk.
    [[noreturn]] void pointFailed(std::size_t index) {
        laszip_CHAR* message = nullptr;
        if (zip_) laszip_get_error(zip_, &message);
        // LASzip's own words, unless they only repeat the point's number.
        const std::string said = message ? std::string(message) : std::string();
        const std::string detail = said.empty() || said.rfind("reading point ", 0) == 0
                                       ? std::string()
                                       : " (LASzip: " + core::printable(said, 160, false) + ")";
        throw Error(prefix_ + ": point " + std::to_string(index) + " of " + std::to_string(declared) + ": " +
                    (compressed_ ? "the compressed point data cannot be decoded; the LAZ file is corrupt or cut short"
                                 : "the point record cannot be read") +
                    detail);
    }

    void check(laszip_I32 rc, const char* what) {
        if (rc == 0) return;
        laszip_CHAR* message = nullptr;
        if (zip_) laszip_get_error(zip_, &message);
        throw Error(prefix_ + ": " + what + ": " +
                    (message ? core::printable(message, 160, false) : std::string("LASzip failed")));
    }

    // The public header block and the VLRs, checked against the file's size before
    // LASzip sees them.
    void checkHeader() {
        const std::uint64_t size = source_.size();
        if (size >= 4 && source_.view(0, 4) != "LASF")
            throw Error(prefix_ + ": not a LAS file: it starts with '" +
                        core::printable(source_.view(0, 4), 20, false) + "'; allowed: 'LASF'");
        if (size < 227)
            throw Error(prefix_ + ": truncated: a LAS header needs 227 bytes, the file has " + std::to_string(size));
        const std::string_view h = source_.view(0, std::size_t(std::min<std::uint64_t>(size, 375)));
        const std::string head(h);  // the view changes with the next read
        const int major = std::uint8_t(head[24]), minor = std::uint8_t(head[25]);
        if (major != 1 || minor > 4)
            throw Error(prefix_ + ": LAS version " + std::to_string(major) + "." + std::to_string(minor) +
                        " is not one of 1.0 to 1.4");
        const std::size_t header_size = le<std::uint16_t>(head, 94);
        const std::uint64_t data_at = le<std::uint32_t>(head, 96);
        const std::uint32_t vlrs = le<std::uint32_t>(head, 100);
        const unsigned raw_format = std::uint8_t(head[104]);
        const unsigned format = raw_format & 0x3Fu;
        const bool compressed = (raw_format & 0xC0u) != 0;  // LASzip marks LAZ with bit 7 (or 6)
        const std::size_t record = le<std::uint16_t>(head, 105);
        const std::size_t min_header = minor >= 4 ? 375 : minor == 3 ? 235 : 227;
        if (header_size < min_header || header_size > data_at || data_at > size)
            throw Error(prefix_ + ": header size " + std::to_string(header_size) + " and point data offset " +
                        std::to_string(data_at) + " do not fit a LAS 1." + std::to_string(minor) + " file of " +
                        std::to_string(size) + " bytes");
        if (format >= kMinRecord.size())
            throw Error(prefix_ + ": point data format " + std::to_string(format) + " is not one of 0 to 10");
        if (record < kMinRecord[format])
            throw Error(prefix_ + ": point records of " + std::to_string(record) + " bytes are too short for format " +
                        std::to_string(format) + " (" + std::to_string(kMinRecord[format]) + " bytes)");
        for (int k = 0; k < 3; ++k) {
            scale_[k] = le<double>(head, 131 + 8 * std::size_t(k));
            offset_[k] = le<double>(head, 155 + 8 * std::size_t(k));
            if (!std::isfinite(scale_[k]) || scale_[k] == 0.0 || !std::isfinite(offset_[k]))
                throw Error(prefix_ + ": the scale and offset of " + "xyz"[k] +
                            " must be finite and the scale non-zero");
        }
        std::uint64_t count = le<std::uint32_t>(head, 107);
        if (minor >= 4 && count == 0) count = le<std::uint64_t>(head, 247);
        // VLRs: each header and payload inside the space before the points.
        std::uint64_t at = header_size;
        if (vlrs > (data_at - header_size) / kVlrHeader)
            throw Error(prefix_ + ": " + std::to_string(vlrs) + " VLRs cannot fit before the point data");
        std::size_t extra_declared = 0;
        bool laszip_vlr = false, extra_vlr = false;
        LaszipVlr laz;
        for (std::uint32_t v = 0; v < vlrs; ++v) {
            if (data_at - at < kVlrHeader)
                throw Error(prefix_ + ": VLR " + std::to_string(v) + " runs into the point data");
            const std::string vh(source_.view(at, kVlrHeader));
            const std::uint16_t length = le<std::uint16_t>(vh, 20);
            if (data_at - at - kVlrHeader < length)
                throw Error(prefix_ + ": VLR " + std::to_string(v) + " runs into the point data");
            const std::string user(vh.data() + 2, strnlen(vh.data() + 2, 16));
            if (facts_)
                facts_->vlrs.push_back({user, le<std::uint16_t>(vh, 18),
                                        std::string(vh.data() + 22, strnlen(vh.data() + 22, 32)), at + kVlrHeader,
                                        length, false});
            // One extra bytes VLR and one LASzip VLR: the fields of one and the sizes of
            // another would describe different records.
            if (keep_foreign_) keepVlr(user, le<std::uint16_t>(vh, 18), at + kVlrHeader, length);
            if (user == "LASF_Spec" && le<std::uint16_t>(vh, 18) == 4) {
                if (extra_vlr)
                    throw Error(prefix_ + ": VLR " + std::to_string(v) +
                                " is a second extra bytes VLR; allowed: one per file");
                extra_declared = readExtraBytes(std::string(source_.view(at + kVlrHeader, length)));
                extra_vlr = true;
            }
            if (user == "laszip encoded" && le<std::uint16_t>(vh, 18) == 22204) {
                if (laszip_vlr)
                    throw Error(prefix_ + ": VLR " + std::to_string(v) +
                                " is a second LASzip VLR; allowed: one per file");
                laz = checkLaszipVlr(std::string(source_.view(at + kVlrHeader, length)), format, record);
                laszip_vlr = true;
            }
            at += kVlrHeader + length;
        }
        // LASzip leaks its reader when it refuses a LAZ file (its header checks do not free
        // what they allocated), so what it would refuse is refused here first.
        if (compressed && !laszip_vlr)
            throw Error(prefix_ + ": the point format marks compressed (LAZ) data but there is no LASzip VLR");
        if (!compressed && laszip_vlr)
            throw Error(prefix_ + ": the file has a LASzip VLR but the point format " + std::to_string(raw_format) +
                        " does not mark compressed (LAZ) data");
        if (extra_declared > record - kMinRecord[format])
            throw Error(prefix_ + ": the extra bytes VLR describes " + std::to_string(extra_declared) +
                        " bytes but the records have " + std::to_string(record - kMinRecord[format]));
        extra_size_ = extra_declared;
        record_extra_ = record - kMinRecord[format];
        point_format_ = format;
        const std::uint64_t remaining = size - data_at;
        if (!compressed && count > remaining / record)
            throw Error(prefix_ + ": truncated: the header says " + std::to_string(count) + " points of " +
                        std::to_string(record) + " bytes but only " + std::to_string(remaining) +
                        " bytes of point data follow");
        if (compressed && count > 0 && remaining == 0)
            throw Error(prefix_ + ": truncated: no compressed point data follow the header");
        if (minor >= 4) checkEvlrs(head);
        if (!compressed) checkTrailingBytes(head, minor, data_at + count * record, count, record);
        if (compressed && (laz.compressor == kPointwiseChunked || laz.compressor == kLayeredChunked))
            checkChunks(laz, data_at, count, record);
        if (facts_) recordFacts(head, format, compressed, record);
        system_id_.assign(head.data() + 26, strnlen(head.data() + 26, 32));
        compressed_ = compressed;
        declared = std::size_t(count);
        // LAZ: at least one byte per point is a safe amount to reserve (the real count
        // needs its memory anyway; a hostile count on a small file gets the file size).
        bound = compressed ? std::size_t(std::min<std::uint64_t>(count, remaining)) : declared;
        extended_ = format >= 6;
        // The local frame: whole metres near the middle of the bounds.
        const glm::dvec3 max{le<double>(head, 179), le<double>(head, 195), le<double>(head, 211)};
        const glm::dvec3 min{le<double>(head, 187), le<double>(head, 203), le<double>(head, 219)};
        origin = shiftFor(0.5 * (min + max));
        // Bounds far from the points (zeros, stale values) would put the origin far away and
        // cost the floats their precision (0.25 m at 3,700 km): the first point decides then.
        // It is stored raw, first in the point data (uncompressed, and LAZ's first chunk
        // too, after the chunk table's position when there are chunks).
        const std::uint64_t first_at = compressed && laz.compressor != kPointwise ? data_at + 8 : data_at;
        if (count > 0 && first_at + 12 <= size) {
            const std::string xyz(source_.view(first_at, 12));
            glm::dvec3 first;
            bool outside = false;
            for (int k = 0; k < 3; ++k) {
                first[k] = double(le<std::int32_t>(xyz, 4 * std::size_t(k))) * scale_[k] + offset_[k];
                outside = outside || !(first[k] >= min[k] - kBoundsSlack && first[k] <= max[k] + kBoundsSlack);
            }
            if (outside) origin = shiftFor(first);
        }
        fields = CloudFields{};
        fields.rgb = format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
        fields.label = true;
        fields.view = true;
        fields.range = range_.present;
        fields.intensity = true;
        fields.returns = true;
        fields.scan_angle = true;
        fields.incidence = incidence_.present;
        fields.height_above_ground = height_.present;
    }

    // The header's fields into facts_ (the header checked: `head` holds all of them).
    void recordFacts(const std::string& head, unsigned format, bool compressed, std::size_t record) {
        LasFacts& f = *facts_;
        f.major = std::uint8_t(head[24]);
        f.minor = std::uint8_t(head[25]);
        f.point_format = format;
        f.compressed = compressed;
        f.record_bytes = record;
        f.legacy_points = le<std::uint32_t>(head, 107);
        f.points_64 = f.minor >= 4 ? le<std::uint64_t>(head, 247) : 0;
        f.system_id.assign(head.data() + 26, strnlen(head.data() + 26, 32));
        f.software.assign(head.data() + 58, strnlen(head.data() + 58, 32));
        f.creation_day = le<std::uint16_t>(head, 90);
        f.creation_year = le<std::uint16_t>(head, 92);
        f.scale = scale_;
        f.offset = offset_;
        f.max = {le<double>(head, 179), le<double>(head, 195), le<double>(head, 211)};
        f.min = {le<double>(head, 187), le<double>(head, 203), le<double>(head, 219)};
    }

    struct LaszipVlr {
        unsigned compressor = 0;
        std::uint32_t chunk_points = 0;  // kVariableChunks: each chunk's count is in the table
        std::size_t layers = 0;          // per chunk, of layered compression
    };

    // The LASzip VLR: the compressor, the arithmetic coder, the chunk size and the items.
    // LASzip builds its decoders from the items without checking that they suit the
    // compressor (LAS 1.4 items are only decoded in layers, the older ones only
    // point-wise; the wrong kind crashes it), so the items must be exactly those of the
    // point format and its extra bytes, each in a version of its compressor.
    LaszipVlr checkLaszipVlr(const std::string& payload, unsigned format, std::size_t record) {
        if (payload.size() < 34) throw Error(prefix_ + ": the LASzip VLR is shorter than 34 bytes");
        LaszipVlr laz;
        laz.compressor = le<std::uint16_t>(payload, 0);
        const unsigned coder = le<std::uint16_t>(payload, 2);
        laz.chunk_points = le<std::uint32_t>(payload, 12);
        const std::size_t items = le<std::uint16_t>(payload, 32);
        const bool las14 = format >= 6;
        const bool compressor_ok = las14 ? laz.compressor == kLayeredChunked
                                         : laz.compressor == kPointwise || laz.compressor == kPointwiseChunked;
        if (!compressor_ok || coder != 0 || payload.size() != 34 + 6 * items || items == 0)
            throw Error(prefix_ + ": the LASzip VLR is not one this reader knows (compressor " +
                        std::to_string(laz.compressor) + ", coder " + std::to_string(coder) + ", " +
                        std::to_string(items) + " items in " + std::to_string(payload.size()) +
                        " bytes); allowed for point format " + std::to_string(format) + ": compressor " +
                        (las14 ? "3 (layered chunks)" : "1 or 2 (point-wise)") + ", coder 0");
        // The items the point format needs, then its extra bytes.
        std::vector<unsigned> expected;
        if (!las14) {
            expected.push_back(kPoint10);
            if (format == 1 || format >= 3) expected.push_back(kGpsTime11);
            if (format == 2 || format == 3 || format == 5) expected.push_back(kRgb12);
            if (format == 4 || format == 5) expected.push_back(kWavePacket13);
        } else {
            expected.push_back(kPoint14);
            if (format == 7) expected.push_back(kRgb14);
            if (format == 8 || format == 10) expected.push_back(kRgbNir14);
            if (format == 9 || format == 10) expected.push_back(kWavePacket14);
        }
        const std::size_t extra = record - kMinRecord[format];
        if (extra > 0) expected.push_back(las14 ? kByte14 : kByte);
        std::string listed;
        bool matches = items == expected.size();
        for (std::size_t i = 0; i < items; ++i) {
            const unsigned type = le<std::uint16_t>(payload, 34 + 6 * i);
            const unsigned size = le<std::uint16_t>(payload, 36 + 6 * i);
            const unsigned version = le<std::uint16_t>(payload, 38 + 6 * i);
            listed +=
                (i ? ", " : "") + std::to_string(type) + "/" + std::to_string(size) + "/v" + std::to_string(version);
            if (!matches) continue;
            const bool bytes = type == kByte || type == kByte14;
            const std::size_t want_size = bytes                              ? extra
                                          : type == kPoint10                 ? 20
                                          : type == kGpsTime11               ? 8
                                          : type == kRgb12 || type == kRgb14 ? 6
                                          : type == kPoint14                 ? 30
                                          : type == kRgbNir14                ? 8
                                                                             : 29;
            const bool version_ok = las14 ? (version >= 2 && version <= 4 && !(type == kWavePacket14 && version == 2))
                                          : (version == 1 || (version == 2 && type != kWavePacket13));
            matches = type == expected[i] && size == want_size && version_ok;
            if (type == kPoint14) laz.layers += 9;
            if (type == kRgb14 || type == kWavePacket14) laz.layers += 1;
            if (type == kRgbNir14) laz.layers += 2;
            if (type == kByte14) laz.layers += size;  // one layer per byte
        }
        if (!matches)
            throw Error(prefix_ + ": the LASzip VLR's items (type/size/version: " +
                        core::printable(listed, 200, false) + ") are not those of point format " +
                        std::to_string(format) + " with " + std::to_string(extra) + " extra bytes");
        if (laz.chunk_points == 0) laz.chunk_points = kVariableChunks;  // LASzip reads 0 so
        return laz;
    }

    // Chunked LAZ: the 8 bytes before the chunks give the chunk table's place (or -1: in
    // the file's last 8 bytes; or none, the table's own place: no table, LASzip then
    // finds the chunks as it reads them). The table must lie inside the file, be version
    // 0 and count no more chunks than the points and bytes allow (LASzip allocates
    // by the count and trusts a table cut short). A table of fixed-size chunks counts
    // exactly the chunks the header's points fill, so trailing chunks are refused.
    // Layered chunks are then walked: each one's raw first point, point count and layer
    // sizes, whose sum LASzip allocates and reads in 32 bits.
    void checkChunks(const LaszipVlr& laz, std::uint64_t data_at, std::uint64_t count, std::size_t record) {
        const std::uint64_t size = source_.size();
        const std::uint64_t chunks_at = data_at + 8;
        if (count == 0) return;
        if (chunks_at > size) throw Error(prefix_ + ": truncated: the chunk table's position is cut short");
        std::int64_t table = le<std::int64_t>(std::string(source_.view(data_at, 8)), 0);
        if (table == -1 && size >= chunks_at + 8) table = le<std::int64_t>(std::string(source_.view(size - 8, 8)), 0);
        std::uint64_t end = size;  // where the chunks must end
        std::uint64_t tabled = 0;
        const bool has_table = table != std::int64_t(data_at);
        if (has_table) {
            if (table < std::int64_t(chunks_at) || std::uint64_t(table) > size - std::min<std::uint64_t>(size, 8))
                throw Error(prefix_ + ": the chunk table's position " + std::to_string(table) +
                            " is outside the file; allowed: " + std::to_string(chunks_at) + " to " +
                            std::to_string(size >= 8 ? size - 8 : 0) + " (the table needs 8 bytes)");
            const std::string t(source_.view(std::uint64_t(table), 8));
            const std::uint32_t version = le<std::uint32_t>(t, 0);
            tabled = le<std::uint32_t>(t, 4);
            if (version != 0)
                throw Error(prefix_ + ": the chunk table's version is " + std::to_string(version) + "; allowed: 0");
            const std::uint64_t most = std::min<std::uint64_t>(count, std::uint64_t(table) - chunks_at);
            if (laz.chunk_points != kVariableChunks) {
                const std::uint64_t fill = (count + laz.chunk_points - 1) / laz.chunk_points;
                if (tabled != fill)
                    throw Error(prefix_ + ": the chunk table lists " + std::to_string(tabled) +
                                " chunks but the header's " + std::to_string(count) + " points fill " +
                                std::to_string(fill) + " chunks of " + std::to_string(laz.chunk_points) +
                                (tabled > fill ? " (the header counts fewer points than the data hold)" : ""));
            } else if (tabled == 0 || tabled > most) {
                throw Error(prefix_ + ": the chunk table lists " + std::to_string(tabled) + " chunks; allowed: 1 to " +
                            std::to_string(most) + " for " + std::to_string(count) + " points");
            }
            end = std::uint64_t(table);
        } else if (laz.chunk_points == kVariableChunks) {
            throw Error(prefix_ + ": chunks of variable size need a chunk table, and the file has none");
        }
        if (laz.compressor != kLayeredChunked) return;
        std::uint64_t at = chunks_at, left = count, chunk = 0;
        const std::uint64_t head = record + 4 + 4 * std::uint64_t(laz.layers);
        while (left > 0) {
            if (end - at < head)
                throw Error(prefix_ + ": truncated: chunk " + std::to_string(chunk) + " at byte " + std::to_string(at) +
                            " has no room for its first point and layer sizes before byte " + std::to_string(end));
            const std::string h(source_.view(at + record, std::size_t(4 + 4 * laz.layers)));
            const std::uint32_t points = le<std::uint32_t>(h, 0);
            std::uint64_t bytes = 0;
            for (std::size_t l = 0; l < laz.layers; ++l) bytes += le<std::uint32_t>(h, 4 + 4 * l);
            const std::uint64_t want =
                laz.chunk_points == kVariableChunks ? 0 : std::min<std::uint64_t>(left, laz.chunk_points);
            if (points == 0 || points > left || (want != 0 && points != want))
                throw Error(prefix_ + ": chunk " + std::to_string(chunk) + " holds " + std::to_string(points) +
                            " points; allowed: " + (want != 0 ? std::to_string(want) : "1 to " + std::to_string(left)) +
                            " (of the header's " + std::to_string(count) + ")");
            if (bytes > end - at - head)
                throw Error(prefix_ + ": chunk " + std::to_string(chunk) + "'s layers declare " +
                            std::to_string(bytes) + " bytes but " + std::to_string(end - at - head) +
                            " remain before byte " + std::to_string(end));
            at += head + bytes;
            left -= points;
            ++chunk;
        }
        if (has_table && (at != end || chunk != tabled))
            throw Error(prefix_ + ": the header's " + std::to_string(count) + " points end at byte " +
                        std::to_string(at) + " in chunk " + std::to_string(chunk) +
                        " but the chunk table starts at byte " + std::to_string(end) + " after " +
                        std::to_string(tabled) + " chunks (the header counts fewer points than the data hold?)");
    }

    // LAS 1.4's extended VLRs after the points: each with its 64-bit length inside the
    // file (the trailing-bytes check lets the points end where they begin, so they are
    // what the rest of the file must hold).
    void checkEvlrs(const std::string& head) {
        const std::uint64_t size = source_.size();
        const std::uint32_t n = le<std::uint32_t>(head, 243);
        if (n == 0) return;
        std::uint64_t at = le<std::uint64_t>(head, 235);
        constexpr std::uint64_t kEvlrHeader = 60;
        if (at > size || n > (size - at) / kEvlrHeader)
            throw Error(prefix_ + ": " + std::to_string(n) + " EVLRs from byte " + std::to_string(at) +
                        " do not fit a file of " + std::to_string(size) + " bytes");
        for (std::uint32_t e = 0; e < n; ++e) {
            if (size - at < kEvlrHeader)
                throw Error(prefix_ + ": EVLR " + std::to_string(e) + " at byte " + std::to_string(at) +
                            " is cut short");
            const std::string eh(source_.view(at, kEvlrHeader));
            const std::uint64_t length = le<std::uint64_t>(eh, 20);
            if (length > size - at - kEvlrHeader)
                throw Error(prefix_ + ": EVLR " + std::to_string(e) + " at byte " + std::to_string(at) + " declares " +
                            std::to_string(length) + " bytes but " + std::to_string(size - at - kEvlrHeader) +
                            " follow it");
            if (keep_foreign_)
                keepVlr(std::string(eh.data() + 2, strnlen(eh.data() + 2, 16)), le<std::uint16_t>(eh, 18),
                        at + kEvlrHeader, length);
            if (facts_)
                facts_->vlrs.push_back(
                    {std::string(eh.data() + 2, strnlen(eh.data() + 2, 16)), le<std::uint16_t>(eh, 18),
                     std::string(eh.data() + 28, strnlen(eh.data() + 28, 32)), at + kEvlrHeader, length, true});
            at += kEvlrHeader + length;
        }
    }

    // Uncompressed points must end where the file does, or where what LAS 1.3 and 1.4 put
    // after them begins (waveform data, EVLRs): bytes left over would be points the
    // header does not count.
    void checkTrailingBytes(const std::string& head, int minor, std::uint64_t points_end, std::uint64_t count,
                            std::size_t record) {
        const std::uint64_t size = source_.size();
        if (points_end == size) return;
        if (minor >= 3 && head.size() >= 235 && le<std::uint64_t>(head, 227) == points_end) return;
        if (minor >= 4 && head.size() >= 247 && le<std::uint32_t>(head, 243) > 0 &&
            le<std::uint64_t>(head, 235) == points_end)
            return;
        throw Error(prefix_ + ": " + std::to_string(size - points_end) + " bytes follow the header's " +
                    std::to_string(count) + " points of " + std::to_string(record) +
                    " bytes; allowed: the points end where the file, its waveform data or its EVLRs begin");
    }

    // LAS 1.4 extra bytes descriptors: our fields by name; returns the bytes they cover.
    std::size_t readExtraBytes(const std::string& payload) {
        static constexpr std::array<std::size_t, 11> kTypeSize = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
        std::size_t offset = 0;
        for (std::size_t d = 0; d + kExtraBytesDescriptor <= payload.size(); d += kExtraBytesDescriptor) {
            const int type = std::uint8_t(payload[d + 2]);
            const std::size_t size = type == 0   ? std::uint8_t(payload[d + 3])
                                     : type < 11 ? kTypeSize[std::size_t(type)]
                                                 : 0;
            if (type >= 11) break;  // deprecated array types: the offsets after them are unknown
            const std::string name(payload.data() + d + 4, strnlen(payload.data() + d + 4, 32));
            ExtraField f{true, type, offset};
            if (type != 0) {
                if (name == "range")
                    range_ = f;
                else if (name == "label")
                    label_ = f;
                else if (name == "incidence_deg")
                    incidence_ = f;
                else if (name == "height_above_ground_m" || name == "HeightAboveGround")
                    height_ = f;
            }
            offset += size;
        }
        return offset;
    }

    // Keeps the payload of a VLR or EVLR the writers give back (the CRS, the extra bytes'
    // descriptors); the reader checked that it lies inside the file.
    void keepVlr(const std::string& user, std::uint16_t record, std::uint64_t at, std::uint64_t length) {
        constexpr std::uint64_t kMostKept = 1u << 20;  // a CRS record is a few kilobytes
        if (length > kMostKept) return;
        const auto payload = [&] { return std::string(source_.view(at, std::size_t(length))); };
        if (user == "LASF_Projection" && record == 2112 && wkt_vlr_.empty()) wkt_vlr_ = payload();
        if (user == "LASF_Projection" && record == 34735) geo_keys_ = payload();
        if (user == "LASF_Projection" && record == 34736) geo_doubles_ = payload();
        if (user == "LASF_Projection" && record == 34737) geo_ascii_ = payload();
        if (user == "LASF_Spec" && record == 4) extra_vlr_ = payload();
    }

    // The foreign file's header facts, from the VLRs kept: the WKT record as it is, else
    // the GeoTIFF keys' EPSG code as WKT.
    void makeForeignHeader() {
        auto h = std::make_shared<core::ForeignHeader>();
        h->point_format = int(point_format_);
        h->nir = point_format_ == 8 || point_format_ == 10;
        h->extra_bytes = record_extra_;
        h->extra_bytes_vlr = extra_vlr_;
        h->scale = scale_;
        h->offset = offset_;
        h->system_identifier = system_id_;
        if (!wkt_vlr_.empty()) {
            h->wkt = wkt_vlr_;
        } else if (!geo_keys_.empty()) {
            const LasCrs crs = crsFromGeoKeys(geo_keys_, geo_doubles_, geo_ascii_);
            std::string problem = crs.problem;
            if (problem.empty()) h->wkt = wktForCrs(crs, problem);
            if (h->wkt.empty()) h->crs_problem = prefix_ + ": its GeoTIFF CRS cannot be written as WKT: " + problem;
        }
        foreign = std::move(h);
    }

    // Point `q`'s side record (core::ForeignPoint, then its extra bytes) into `out`.
    void foreignRecord(const laszip_point_struct& q, unsigned char* out) const {
        core::ForeignPoint f;
        f.gps_time_s = q.gps_time;
        f.xyz[0] = q.X;
        f.xyz[1] = q.Y;
        f.xyz[2] = q.Z;
        f.rgb[0] = q.rgb[0];
        f.rgb[1] = q.rgb[1];
        f.rgb[2] = q.rgb[2];
        f.nir = q.rgb[3];
        f.point_source_id = q.point_source_ID;
        f.user_data = q.user_data;
        if (extended_) {
            f.classification = q.extended_classification;
            f.flags = std::uint8_t((q.extended_classification_flags & 15u) | ((q.extended_scanner_channel & 3u) << 4));
        } else {
            f.classification = q.classification;
            f.flags =
                std::uint8_t((q.synthetic_flag ? 1u : 0u) | (q.keypoint_flag ? 2u : 0u) | (q.withheld_flag ? 4u : 0u));
        }
        f.flags = std::uint8_t(f.flags | (q.scan_direction_flag ? 64u : 0u) | (q.edge_of_flight_line ? 128u : 0u));
        std::memcpy(out, &f, sizeof f);
        if (record_extra_ == 0) return;
        if (q.extra_bytes && q.num_extra_bytes >= int(record_extra_))
            std::memcpy(out + sizeof f, q.extra_bytes, record_extra_);
        else
            std::memset(out + sizeof f, 0, record_extra_);
    }

    ByteSource& source_;
    std::string prefix_;
    SourceBuf buf_;
    std::istream stream_;
    LasFacts* facts_ = nullptr;    // filled when given
    LasTally* tally_ = nullptr;    // counts the records when given
    bool keep_foreign_ = false;    // side records for a file without our label
    bool positions_only_ = false;  // PointFields::Positions: LASzip skips the other layers
    std::size_t stride_ = 0;       // bytes of a point's side record; 0: none kept
    std::string wkt_vlr_, geo_keys_, geo_doubles_, geo_ascii_, extra_vlr_;
    std::string system_id_;         // the header's system identifier, up to its first NUL
    std::size_t record_extra_ = 0;  // bytes a record has after its format's fields
    unsigned point_format_ = 0;
    std::vector<unsigned char> pending_foreign_;  // the side records of pending_
    laszip_POINTER zip_ = nullptr;
    laszip_point_struct* point_ = nullptr;
    bool open_ = false;
    bool extended_ = false;
    bool compressed_ = false;
    pid_t child_ = -1;                   // the decoding process of compressed data
    int pipe_ = -1;                      // its frames
    std::uint64_t* decoding_ = nullptr;  // shared with it: the point it is decoding
    std::vector<CloudPoint> pending_;
    std::size_t pending_at_ = 0;
    glm::dvec3 scale_{1.0}, offset_{0.0};
    ExtraField range_, label_, incidence_, height_;
    std::size_t extra_size_ = 0;
    std::size_t done_ = 0;
};

}  // namespace

std::unique_ptr<FormatReader> openLas(ByteSource& source, const std::string& prefix, bool keep_foreign,
                                      bool positions_only) {
    return std::make_unique<LasReader>(source, prefix, nullptr, nullptr, keep_foreign, positions_only);
}

std::unique_ptr<FormatReader> openLasCounted(ByteSource& source, const std::string& prefix, LasFacts& facts,
                                             LasTally& tally) {
    return std::make_unique<LasReader>(source, prefix, &facts, &tally);
}

}  // namespace io::detail
