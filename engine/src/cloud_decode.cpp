// cloud_decode: byte sources, text tokens and record decoding shared by the PCD and PLY
// readers (see cloud_decode.hpp).
#include "cloud_decode.hpp"

#include "text.hpp"

#include <engine/error.hpp>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace engine::detail {

static_assert(std::endian::native == std::endian::little,
              "decodeBinary reads little-endian records with memcpy");

namespace {

constexpr std::size_t kWindowBytes = 1u << 20;
constexpr std::size_t kMaxTokenBytes = 4096;
constexpr std::size_t kMaxPaddingBytes = 64u << 10;

class MemorySource final : public ByteSource {
public:
    explicit MemorySource(std::string_view bytes) : bytes_(bytes) { size_ = bytes.size(); }
    std::string_view view(std::uint64_t offset, std::size_t n) override {
        return bytes_.substr(std::size_t(offset), n);
    }

private:
    std::string_view bytes_;
};

class FileSource final : public ByteSource {
public:
    FileSource(int fd, std::uint64_t size, std::string prefix) : fd_(fd), prefix_(std::move(prefix)) {
        size_ = size;
    }
    ~FileSource() override { ::close(fd_); }
    FileSource(const FileSource&) = delete;
    FileSource& operator=(const FileSource&) = delete;

    std::string_view view(std::uint64_t offset, std::size_t n) override {
        if (offset >= window_at_ && offset + n <= window_at_ + window_.size())
            return std::string_view(window_).substr(std::size_t(offset - window_at_), n);
        if (n <= kWindowBytes) {
            const std::size_t len = std::size_t(std::min<std::uint64_t>(kWindowBytes, size_ - offset));
            window_.resize(len);
            window_at_ = offset;
            readAt(offset, window_.data(), len);
            return std::string_view(window_).substr(0, n);
        }
        large_.resize(n);
        readAt(offset, large_.data(), n);
        return large_;
    }

private:
    void readAt(std::uint64_t offset, char* out, std::size_t n) {
        std::size_t done = 0;
        while (done < n) {
            const ssize_t got = ::pread(fd_, out + done, n - done, off_t(offset + done));
            if (got < 0 && errno == EINTR) continue;
            if (got < 0) {
                window_.clear();
                throw Error(prefix_ + ": read failed: " + std::strerror(errno));
            }
            if (got == 0) {
                window_.clear();
                throw Error(prefix_ + ": the file became shorter while it was read");
            }
            done += std::size_t(got);
        }
    }

    int fd_;
    std::string prefix_;
    std::string window_, large_;
    std::uint64_t window_at_ = 0;
};

double loadScalar(const unsigned char* p, ScalarType t, bool swap) {
    unsigned char b[8];
    std::memcpy(b, p, std::size_t(t.size));
    if (swap) std::reverse(b, b + t.size);
    switch (t.kind) {
        case Kind::Float:
            if (t.size == 4) { float f; std::memcpy(&f, b, 4); return f; }
            { double d; std::memcpy(&d, b, 8); return d; }
        case Kind::UInt:
            switch (t.size) {
                case 1: return b[0];
                case 2: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
                case 4: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
                default: { std::uint64_t v; std::memcpy(&v, b, 8); return double(v); }
            }
        case Kind::Int:
            switch (t.size) {
                case 1: return std::int8_t(b[0]);
                case 2: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
                case 4: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
                default: { std::int64_t v; std::memcpy(&v, b, 8); return double(v); }
            }
    }
    return 0.0;
}

std::uint32_t loadBits32(const unsigned char* p, bool swap) {
    unsigned char b[4];
    std::memcpy(b, p, 4);
    if (swap) std::reverse(b, b + 4);
    std::uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
}

bool parseFloat(std::string_view s, float& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

std::string shortNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

Role checkedLabel(double v, std::size_t i, const std::string& prefix) {
    if (!(v == 0.0 || v == 1.0 || v == 2.0))
        throw Error(prefix + ": point " + std::to_string(i) + ": label " + shortNumber(v) +
                    " is not 0 (ground), 1 (environment) or 2 (target)");
    return Role(std::uint8_t(v));
}

std::uint16_t checkedView(double v, std::size_t i, const std::string& prefix) {
    if (!(v >= 0.0 && v <= 65535.0) || v != std::floor(v))
        throw Error(prefix + ": point " + std::to_string(i) + ": view " + shortNumber(v) +
                    " is not an integer in 0..65535");
    return std::uint16_t(v);
}

std::uint8_t colourByte(double v, bool is_float) {
    if (is_float) v *= 255.0;
    if (!(v > 0.0)) return 0;  // also NaN
    if (v >= 255.0) return 255;
    return std::uint8_t(std::lround(v));
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

}  // namespace

std::unique_ptr<ByteSource> memorySource(std::string_view bytes) {
    return std::make_unique<MemorySource>(bytes);
}

std::unique_ptr<ByteSource> fileSource(const std::filesystem::path& path, const char* module) {
    const std::string prefix = std::string(module) + ": " + path.string();
    // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused just below.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw Error(prefix + ": file does not exist");
        throw Error(prefix + ": cannot be read: " + std::strerror(errno));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const bool dir = S_ISDIR(st.st_mode);
        ::close(fd);
        throw Error(prefix + (dir ? ": is a directory, not a regular file" : ": is not a regular file"));
    }
    return std::make_unique<FileSource>(fd, std::uint64_t(st.st_size), prefix);
}

TextStream::TextStream(ByteSource& source, std::uint64_t begin, std::string prefix)
    : source_(source), next_(begin), prefix_(std::move(prefix)) {}

bool TextStream::refill() {
    if (next_ >= source_.size()) return false;
    const std::size_t len = std::size_t(std::min<std::uint64_t>(kWindowBytes, source_.size() - next_));
    block_ = source_.view(next_, len);
    next_ += len;
    at_ = 0;
    return true;
}

bool TextStream::next(std::string_view& token) {
    for (;;) {
        while (at_ < block_.size()) {
            const char c = block_[at_];
            if (c == '\n') ++line_no_;
            else if (!isSpace(c)) break;
            ++at_;
        }
        if (at_ < block_.size()) break;
        if (!refill()) return false;
    }
    const std::size_t start = at_;
    while (at_ < block_.size() && !isSpace(block_[at_])) ++at_;
    if (at_ < block_.size() || next_ >= source_.size()) {
        token = block_.substr(start, at_ - start);
        if (token.size() > kMaxTokenBytes)
            throw Error(prefix_ + ": a value longer than 4096 bytes; not a text cloud?");
        return true;
    }
    // The token runs into the next block: gather it (bounded) before the view moves on.
    long_token_.assign(block_.substr(start));
    while (refill()) {
        std::size_t end = 0;
        while (end < block_.size() && !isSpace(block_[end])) ++end;
        long_token_.append(block_.substr(0, std::min(end, kMaxTokenBytes + 1)));
        at_ = end;
        if (long_token_.size() > kMaxTokenBytes)
            throw Error(prefix_ + ": a value longer than 4096 bytes; not a text cloud?");
        if (end < block_.size()) break;
    }
    token = long_token_;
    return true;
}

std::string headerPrefix(ByteSource& source) {
    const std::size_t n = std::size_t(std::min<std::uint64_t>(source.size(), kMaxHeaderBytes));
    return std::string(source.view(0, n));
}

bool LineReader::next(std::string_view& line) {
    if (pos >= data.size()) return false;
    const std::size_t nl = data.find('\n', pos);
    const std::size_t end = nl == std::string_view::npos ? data.size() : nl;
    line = data.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = nl == std::string_view::npos ? data.size() : nl + 1;
    ++line_no;
    return true;
}

CloudFields Layout::fields() const {
    CloudFields f;
    f.rgb = rgb.present || (red.present && green.present && blue.present);
    f.label = label.present;
    f.view = view.present;
    f.range = range.present;
    return f;
}

std::vector<std::string_view> splitWords(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

bool parseSize(std::string_view s, std::size_t& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parseSmallInt(std::string_view s, int& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool parseDouble(std::string_view s, double& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    if (r.ec == std::errc() && r.ptr == s.data() + s.size()) return true;
    if (r.ec == std::errc::result_out_of_range && r.ptr == s.data() + s.size()) {
        // from_chars leaves `out` alone here; strtod gives +-HUGE_VAL on overflow (caught
        // as non-finite later) and the nearest denormal or 0 on underflow.
        const std::string copy(s);
        out = std::strtod(copy.c_str(), nullptr);
        if (std::fabs(out) == HUGE_VAL) out = std::copysign(std::numeric_limits<double>::infinity(), out);
        return true;
    }
    return false;
}

glm::dvec3 parseOrigin(const std::vector<std::string_view>& words, std::size_t first,
                       const std::string& where) {
    if (words.size() != first + 3)
        throw Error(where + ": the ladarvr origin needs 3 numbers X Y Z");
    glm::dvec3 o;
    for (int k = 0; k < 3; ++k) {
        if (!parseDouble(words[first + std::size_t(k)], o[k]) || !std::isfinite(o[k]))
            throw Error(where + ": the ladarvr origin value '" +
                        shown(words[first + std::size_t(k)], 40) + "' is not a finite number");
    }
    return o;
}

void checkPadding(ByteSource& source, std::uint64_t from, const std::string& prefix,
                  const std::string& what) {
    if (from >= source.size()) return;
    const std::uint64_t extra = source.size() - from;
    bool zeros = extra <= kMaxPaddingBytes;
    if (zeros) {
        const std::string_view tail = source.view(from, std::size_t(extra));
        zeros = std::all_of(tail.begin(), tail.end(), [](char c) { return c == 0; });
    }
    if (!zeros)
        throw Error(prefix + ": " + std::to_string(extra) + " bytes of data follow the " + what +
                    "; the header must count every point");
}

void decodeBinary(const unsigned char* data, std::size_t first, std::size_t count,
                  const Layout& l, bool swap, std::size_t number, const std::string& prefix,
                  std::vector<CloudPoint>& out) {
    auto at = [&](const Column& c, std::size_t k) { return data + c.base + (first + k) * c.stride; };
    const std::size_t old = out.size();
    out.resize(old + count);
    CloudPoint* points = out.data() + old;
    const bool rgb_from_channels = !l.rgb.present && l.red.present && l.green.present && l.blue.present;
    // Fast path for native-endian files of our own layout (and PCL's usual x y z [rgb]):
    // fixed types, no per-value type switch; the general loop below handles the rest.
    const auto is = [](const Column& c, Kind k, int size) { return c.type.kind == k && c.type.size == size; };
    if (!swap && is(l.x, Kind::Float, 4) && is(l.y, Kind::Float, 4) && is(l.z, Kind::Float, 4) &&
        !rgb_from_channels && (!l.label.present || is(l.label, Kind::UInt, 1)) &&
        (!l.view.present || is(l.view, Kind::UInt, 2)) && (!l.range.present || is(l.range, Kind::Float, 4))) {
        for (std::size_t k = 0; k < count; ++k) {
            CloudPoint& p = points[k];
            std::memcpy(&p.position.x, at(l.x, k), 4);
            std::memcpy(&p.position.y, at(l.y, k), 4);
            std::memcpy(&p.position.z, at(l.z, k), 4);
            if (l.rgb.present) {
                std::uint32_t bits;
                std::memcpy(&bits, at(l.rgb, k), 4);
                p.rgb = bits & 0xFFFFFFu;
            }
            if (l.label.present) {
                const std::uint8_t b = *at(l.label, k);
                p.label = b <= 2 ? Role(b) : checkedLabel(double(b), number + k, prefix);
            }
            if (l.view.present) std::memcpy(&p.view, at(l.view, k), 2);
            if (l.range.present) std::memcpy(&p.range_m, at(l.range, k), 4);
        }
        return;
    }
    for (std::size_t k = 0; k < count; ++k) {
        CloudPoint& p = points[k];
        p.position = glm::vec3(float(loadScalar(at(l.x, k), l.x.type, swap)),
                               float(loadScalar(at(l.y, k), l.y.type, swap)),
                               float(loadScalar(at(l.z, k), l.z.type, swap)));
        if (l.rgb.present) {
            p.rgb = loadBits32(at(l.rgb, k), swap) & 0xFFFFFFu;
        } else if (rgb_from_channels) {
            p.rgb = packRgb(colourByte(loadScalar(at(l.red, k), l.red.type, swap), l.colour_float),
                            colourByte(loadScalar(at(l.green, k), l.green.type, swap), l.colour_float),
                            colourByte(loadScalar(at(l.blue, k), l.blue.type, swap), l.colour_float));
        }
        if (l.label.present)
            p.label = checkedLabel(loadScalar(at(l.label, k), l.label.type, swap), number + k, prefix);
        if (l.view.present)
            p.view = checkedView(loadScalar(at(l.view, k), l.view.type, swap), number + k, prefix);
        if (l.range.present) p.range_m = float(loadScalar(at(l.range, k), l.range.type, swap));
    }
}

void decodeText(TextStream& tokens, std::size_t count, std::size_t per_point, const Layout& l,
                std::size_t number, std::size_t total, std::size_t line_base,
                const std::string& prefix, std::vector<CloudPoint>& out) {
    std::vector<std::string> tok(per_point);
    std::size_t i = number;
    auto value = [&](const Column& c) {
        // Floats of 4 bytes parse as float: the shortest text of a float reads back exactly.
        float f;
        if (c.type.kind == Kind::Float && c.type.size == 4 && parseFloat(tok[c.token], f))
            return double(f);
        double v;
        if (!parseDouble(tok[c.token], v))
            throw Error(prefix + ": line " + std::to_string(line_base + tokens.lineNo()) + ": value '" +
                        shown(tok[c.token], 40) + "' of point " + std::to_string(i) + " is not a number");
        return v;
    };
    const bool rgb_from_channels = !l.rgb.present && l.red.present && l.green.present && l.blue.present;
    for (std::size_t k = 0; k < count; ++k, ++i) {
        for (std::size_t t = 0; t < per_point; ++t) {
            std::string_view piece;
            if (!tokens.next(piece))
                throw Error(prefix + ": truncated: the header says " + std::to_string(total) +
                            " points but the data end at line " +
                            std::to_string(line_base + tokens.lineNo()) + " inside point " +
                            std::to_string(i));
            tok[t].assign(piece);
        }
        CloudPoint p;
        p.position = glm::vec3(float(value(l.x)), float(value(l.y)), float(value(l.z)));
        if (l.rgb.present) {
            // TYPE F rgb: PCL's writer puts the uint32 bits as an integer, others the float.
            std::uint32_t bits = 0;
            const std::string& t = tok[l.rgb.token];
            const auto r = std::from_chars(t.data(), t.data() + t.size(), bits);
            if (!l.rgb_float_text || r.ec != std::errc() || r.ptr != t.data() + t.size()) {
                const double v = value(l.rgb);
                if (l.rgb_float_text) {
                    const float f = float(v);
                    std::memcpy(&bits, &f, 4);
                } else {
                    bits = v >= 0.0 && v <= 4294967295.0 ? std::uint32_t(v) : 0u;
                }
            }
            p.rgb = bits & 0xFFFFFFu;
        } else if (rgb_from_channels) {
            p.rgb = packRgb(colourByte(value(l.red), l.colour_float),
                            colourByte(value(l.green), l.colour_float),
                            colourByte(value(l.blue), l.colour_float));
        }
        if (l.label.present) p.label = checkedLabel(value(l.label), i, prefix);
        if (l.view.present) p.view = checkedView(value(l.view), i, prefix);
        if (l.range.present) p.range_m = float(value(l.range));
        out.push_back(p);
    }
}

}  // namespace engine::detail
