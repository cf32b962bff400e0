// cloud_decode: byte sources, text tokens and record decoding shared by the PCD and PLY
// readers (see cloud_decode.hpp).
#include "cloud_decode.hpp"

#include <core/error.hpp>

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

namespace io::detail {

using core::CloudFields;
using core::CloudPoint;
using core::Error;
using core::packRgb;
using core::Role;

static_assert(std::endian::native == std::endian::little, "decodeBinary reads little-endian records with memcpy");

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
    FileSource(int fd, std::uint64_t size, std::string prefix) : fd_(fd), prefix_(std::move(prefix)) { size_ = size; }
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
            if (t.size == 4) {
                float f;
                std::memcpy(&f, b, 4);
                return f;
            }
            {
                double d;
                std::memcpy(&d, b, 8);
                return d;
            }
        case Kind::UInt:
            switch (t.size) {
                case 1: return b[0];
                case 2: {
                    std::uint16_t v;
                    std::memcpy(&v, b, 2);
                    return v;
                }
                case 4: {
                    std::uint32_t v;
                    std::memcpy(&v, b, 4);
                    return v;
                }
                default: {
                    std::uint64_t v;
                    std::memcpy(&v, b, 8);
                    return double(v);
                }
            }
        case Kind::Int:
            switch (t.size) {
                case 1: return std::int8_t(b[0]);
                case 2: {
                    std::int16_t v;
                    std::memcpy(&v, b, 2);
                    return v;
                }
                case 4: {
                    std::int32_t v;
                    std::memcpy(&v, b, 4);
                    return v;
                }
                default: {
                    std::int64_t v;
                    std::memcpy(&v, b, 8);
                    return double(v);
                }
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

Role checkedLabel(double v, std::size_t i, const std::string& prefix) {
    if (!(v == 0.0 || v == 1.0 || v == 2.0))
        throw Error(prefix + ": point " + std::to_string(i) + ": label " + core::shownNumber(v, 6) +
                    " is not 0 (ground), 1 (environment) or 2 (target)");
    return Role(std::uint8_t(v));
}

// Our role from a label value: our own 0..2, or an ASPRS class (Layout::label_codes).
Role labelRole(double v, const Layout& l, std::size_t i, const std::string& prefix, DecodeStats& stats) {
    if (l.label_codes == LabelCodes::Roles || (l.label_codes == LabelCodes::RolesThenClasses && v >= 0.0 && v <= 2.0))
        return checkedLabel(v, i, prefix);
    if (!(v >= 0.0 && v <= 255.0) || v != std::floor(v))
        throw Error(prefix + ": point " + std::to_string(i) + ": label " + core::shownNumber(v, 6) +
                    " is not an ASPRS class 0..255");
    bool known = true;
    const Role r = roleForClass(unsigned(v), known);
    if (!known && stats.unknown_classes++ == 0) stats.first_unknown = unsigned(v);
    return r;
}

std::uint16_t clampedU16(double v) {
    if (!(v > 0.0)) return 0;  // also NaN
    if (v >= 65535.0) return 65535;
    return std::uint16_t(std::lround(v));
}

std::uint8_t clampedU8(double v) {
    if (!(v > 0.0)) return 0;
    if (v >= 255.0) return 255;
    return std::uint8_t(std::lround(v));
}

// The optional fields after range; `get(column)` gives a present column's value.
template <typename Get>
void decodeExtras(CloudPoint& p, const Layout& l, Get&& get) {
    if (l.intensity.present) p.intensity = clampedU16(get(l.intensity));
    if (l.return_number.present) p.return_number = clampedU8(get(l.return_number));
    if (l.returns.present) p.returns = clampedU8(get(l.returns));
    if (l.incidence.present) p.incidence_deg = float(get(l.incidence));
    if (l.scan_angle.present) p.scan_angle_deg = float(get(l.scan_angle));
    if (l.height_above_ground.present) p.height_above_ground_m = float(get(l.height_above_ground));
}

std::uint16_t checkedView(double v, std::size_t i, const std::string& prefix) {
    if (!(v >= 0.0 && v <= 65535.0) || v != std::floor(v))
        throw Error(prefix + ": point " + std::to_string(i) + ": view " + core::shownNumber(v, 6) +
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

std::unique_ptr<ByteSource> memorySource(std::string_view bytes) { return std::make_unique<MemorySource>(bytes); }

std::unique_ptr<ByteSource> fileSource(const std::filesystem::path& path, const char* module) {
    const std::string prefix = std::string(module) + ": " + path.string();
    // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused just below.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw Error(prefix + ": file does not exist");
        throw Error(prefix + ": cannot be read: " + std::strerror(errno));
    }
    struct stat st{};
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
            if (c == '\n')
                ++line_no_;
            else if (!isSpace(c))
                break;
            ++at_;
        }
        if (at_ < block_.size()) break;
        if (!refill()) return false;
    }
    const std::size_t start = at_;
    while (at_ < block_.size() && !isSpace(block_[at_])) ++at_;
    if (at_ < block_.size() || next_ >= source_.size()) {
        token = block_.substr(start, at_ - start);
        if (token.size() > kMaxTokenBytes) throw Error(prefix_ + ": a value longer than 4096 bytes; not a text cloud?");
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
    f.intensity = intensity.present;
    f.returns = return_number.present || returns.present;
    f.incidence = incidence.present;
    f.scan_angle = scan_angle.present;
    f.height_above_ground = height_above_ground.present;
    return f;
}

bool Layout::wideXyz() const {
    const auto wide = [](const Column& c) { return !(c.type.kind == Kind::Float && c.type.size == 4); };
    return wide(x) || wide(y) || wide(z);
}

Column* columnFor(Layout& l, std::string_view name) {
    if (name.starts_with("scalar_")) name.remove_prefix(7);
    if (name == "label" || name == "classification" || name == "Classification") return &l.label;
    if (name == "view") return &l.view;
    if (name == "range") return &l.range;
    if (name == "intensity") return &l.intensity;
    if (name == "return_number") return &l.return_number;
    if (name == "number_of_returns") return &l.returns;
    if (name == "incidence_deg") return &l.incidence;
    if (name == "scan_angle_deg") return &l.scan_angle;
    if (name == "height_above_ground_m") return &l.height_above_ground;
    return nullptr;
}

glm::dvec3 shiftFor(const glm::dvec3& first) {
    glm::dvec3 s{0.0};
    for (int k = 0; k < 3; ++k)
        if (std::isfinite(first[k]) && std::fabs(first[k]) >= kShiftFrom_m) s[k] = std::round(first[k]);
    return s;
}

LabelCodes labelCodesFor(std::string_view name, bool ours) {
    if (name.starts_with("scalar_")) name.remove_prefix(7);
    if (name == "classification" || name == "Classification") return LabelCodes::Classes;
    return ours ? LabelCodes::Roles : LabelCodes::RolesThenClasses;
}

Role roleForClass(unsigned code, bool& known) {
    known = true;
    if (code == 2) return Role::Ground;
    if (code == kTargetClass) return Role::Target;
    known = code <= 22;
    return Role::Environment;
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

glm::dvec3 parseOrigin(const std::vector<std::string_view>& words, std::size_t first, const std::string& where) {
    if (words.size() != first + 3) throw Error(where + ": the ladarvr origin needs 3 numbers X Y Z");
    glm::dvec3 o;
    for (int k = 0; k < 3; ++k) {
        if (!parseDouble(words[first + std::size_t(k)], o[k]) || !std::isfinite(o[k]))
            throw Error(where + ": the ladarvr origin value '" + core::printable(words[first + std::size_t(k)], 40) +
                        "' is not a finite number");
    }
    return o;
}

void checkPadding(ByteSource& source, std::uint64_t from, const std::string& prefix, const std::string& what) {
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

glm::dvec3 peekBinaryXyz(const unsigned char* record, const Layout& l, bool swap) {
    return {loadScalar(record + l.x.base, l.x.type, swap), loadScalar(record + l.y.base, l.y.type, swap),
            loadScalar(record + l.z.base, l.z.type, swap)};
}

bool peekTextXyz(TextStream& tokens, const Layout& l, std::size_t per_point, glm::dvec3& xyz) {
    for (std::size_t t = 0; t < per_point; ++t) {
        std::string_view piece;
        if (!tokens.next(piece)) return false;
        for (int k = 0; k < 3; ++k) {
            const Column& c = k == 0 ? l.x : k == 1 ? l.y : l.z;
            if (c.token == t && !parseDouble(piece, xyz[k])) return false;
        }
    }
    return true;
}

void decodeBinary(const unsigned char* data, std::size_t first, std::size_t count, const Layout& l, bool swap,
                  std::size_t number, const std::string& prefix, std::vector<CloudPoint>& out, DecodeStats& stats) {
    auto at = [&](const Column& c, std::size_t k) { return data + c.base + (first + k) * c.stride; };
    const std::size_t old = out.size();
    out.resize(old + count);
    CloudPoint* points = out.data() + old;
    const bool rgb_from_channels = !l.rgb.present && l.red.present && l.green.present && l.blue.present;
    // Fast path for native-endian files of our own layout (and PCL's usual x y z [rgb]):
    // fixed types, no per-value type switch; the general loop below handles the rest.
    const auto is = [](const Column& c, Kind k, int size) { return c.type.kind == k && c.type.size == size; };
    const bool extras = l.intensity.present || l.return_number.present || l.returns.present || l.incidence.present ||
                        l.scan_angle.present || l.height_above_ground.present;
    if (!swap && is(l.x, Kind::Float, 4) && is(l.y, Kind::Float, 4) && is(l.z, Kind::Float, 4) &&
        l.shift == glm::dvec3(0.0) && !rgb_from_channels && (!l.label.present || is(l.label, Kind::UInt, 1)) &&
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
                p.label = b <= 2 && l.label_codes != LabelCodes::Classes
                              ? Role(b)
                              : labelRole(double(b), l, number + k, prefix, stats);
            }
            if (l.view.present) std::memcpy(&p.view, at(l.view, k), 2);
            if (l.range.present) std::memcpy(&p.range_m, at(l.range, k), 4);
            if (extras) decodeExtras(p, l, [&](const Column& c) { return loadScalar(at(c, k), c.type, false); });
        }
        return;
    }
    for (std::size_t k = 0; k < count; ++k) {
        CloudPoint& p = points[k];
        p.position = glm::vec3(float(loadScalar(at(l.x, k), l.x.type, swap) - l.shift.x),
                               float(loadScalar(at(l.y, k), l.y.type, swap) - l.shift.y),
                               float(loadScalar(at(l.z, k), l.z.type, swap) - l.shift.z));
        if (l.rgb.present) {
            p.rgb = loadBits32(at(l.rgb, k), swap) & 0xFFFFFFu;
        } else if (rgb_from_channels) {
            p.rgb = packRgb(colourByte(loadScalar(at(l.red, k), l.red.type, swap), l.colour_float),
                            colourByte(loadScalar(at(l.green, k), l.green.type, swap), l.colour_float),
                            colourByte(loadScalar(at(l.blue, k), l.blue.type, swap), l.colour_float));
        }
        if (l.label.present)
            p.label = labelRole(loadScalar(at(l.label, k), l.label.type, swap), l, number + k, prefix, stats);
        if (l.view.present) p.view = checkedView(loadScalar(at(l.view, k), l.view.type, swap), number + k, prefix);
        if (l.range.present) p.range_m = float(loadScalar(at(l.range, k), l.range.type, swap));
        if (extras) decodeExtras(p, l, [&](const Column& c) { return loadScalar(at(c, k), c.type, swap); });
    }
}

void decodeText(TextStream& tokens, std::size_t count, std::size_t per_point, const Layout& l, std::size_t number,
                std::size_t total, std::size_t line_base, const std::string& prefix, std::vector<CloudPoint>& out,
                DecodeStats& stats) {
    std::vector<std::string> tok(per_point);
    std::size_t i = number;
    const bool exact = l.shift == glm::dvec3(0.0);
    auto value = [&](const Column& c) {
        // Floats of 4 bytes parse as float: the shortest text of a float reads back exactly
        // (but not when x, y, z are shifted: then their digits beyond a float count).
        float f;
        if (exact && c.type.kind == Kind::Float && c.type.size == 4 && parseExact(tok[c.token], f)) return double(f);
        double v;
        if (!parseDouble(tok[c.token], v))
            throw Error(prefix + ": line " + std::to_string(line_base + tokens.lineNo()) + ": value '" +
                        core::printable(tok[c.token], 40) + "' of point " + std::to_string(i) + " is not a number");
        return v;
    };
    const bool rgb_from_channels = !l.rgb.present && l.red.present && l.green.present && l.blue.present;
    for (std::size_t k = 0; k < count; ++k, ++i) {
        for (std::size_t t = 0; t < per_point; ++t) {
            std::string_view piece;
            if (!tokens.next(piece))
                throw Error(prefix + ": truncated: the header says " + std::to_string(total) +
                            " points but the data end at line " + std::to_string(line_base + tokens.lineNo()) +
                            " inside point " + std::to_string(i));
            tok[t].assign(piece);
        }
        CloudPoint p;
        p.position =
            glm::vec3(float(value(l.x) - l.shift.x), float(value(l.y) - l.shift.y), float(value(l.z) - l.shift.z));
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
            p.rgb = packRgb(colourByte(value(l.red), l.colour_float), colourByte(value(l.green), l.colour_float),
                            colourByte(value(l.blue), l.colour_float));
        }
        if (l.label.present) p.label = labelRole(value(l.label), l, i, prefix, stats);
        if (l.view.present) p.view = checkedView(value(l.view), i, prefix);
        if (l.range.present) p.range_m = float(value(l.range));
        decodeExtras(p, l, value);
        out.push_back(p);
    }
}

}  // namespace io::detail
