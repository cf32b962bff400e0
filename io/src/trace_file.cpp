// trace_file: writing and strictly reading a study's head trace
// (io/trace_file.hpp).
#include <io/trace_file.hpp>

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace io {

using core::Error;
using core::printable;
namespace {

constexpr std::array<std::string_view, 8> kHeadColumns = {"t_s",     "head_x",  "head_y",  "head_z",
                                                          "head_qw", "head_qx", "head_qy", "head_qz"};
constexpr std::array<std::string_view, 5> kStudyColumns = {"mode", "scale", "hit_x", "hit_y", "hit_z"};

std::vector<std::string_view> splitFields(std::string_view line) {
    std::vector<std::string_view> fields;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = line.find(',', start);
        fields.push_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    return fields;
}

bool hasStudyColumns(const std::vector<std::string_view>& header) {
    if (header.size() < kHeadColumns.size() + kStudyColumns.size()) return false;
    for (std::size_t k = 0; k < kStudyColumns.size(); ++k)
        if (header[kHeadColumns.size() + k] != kStudyColumns[k]) return false;
    return true;
}

}  // namespace

const char* traceModeName(TraceMode mode) { return mode == TraceMode::Free ? "free" : "automatic"; }

std::string formatTraceRow(const TraceRow& r) {
    char buffer[512];
    int n = std::snprintf(buffer, sizeof buffer, "%.6f,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f,%s,%.9g,", r.t_s,
                          r.head_world.x, r.head_world.y, r.head_world.z, r.head_orientation.w, r.head_orientation.x,
                          r.head_orientation.y, r.head_orientation.z, traceModeName(r.mode), r.scale);
    std::string row(buffer, static_cast<std::size_t>(std::max(n, 0)));
    if (r.hit_world) {
        n = std::snprintf(buffer, sizeof buffer, "%.6f,%.6f,%.6f\n", r.hit_world->x, r.hit_world->y, r.hit_world->z);
        row.append(buffer, static_cast<std::size_t>(std::max(n, 0)));
    } else {
        row += ",,\n";
    }
    return row;
}

namespace {

// The reader's rules, one line at a time: parseTrace feeds it a text, forEachTraceRow a
// file read in blocks, so both accept and refuse exactly the same traces.
class TraceParser {
  public:
    explicit TraceParser(const std::filesystem::path& name)
        : where_("trace: " + printable(name.string(), 400) + ": ") {}

    bool studyColumns() const { return study_columns_; }

    // One line without its line break; a row when it is a sample, none for the header.
    std::optional<TraceRow> line(std::string_view line) {
        ++line_no_;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::vector<std::string_view> fields = splitFields(line);
        if (line_no_ == 1) {
            const std::string allowed =
                "; allowed a header starting t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz";
            // A first line that does not start with t_s is not a trace, and none of it is
            // quoted: the file may be anything (a password file named by mistake or not).
            if (fields.empty() || fields[0] != kHeadColumns[0])
                fail(1, "", "not a trace: the first line does not start with the column t_s" + allowed);
            for (std::size_t k = 1; k < kHeadColumns.size(); ++k)
                if (k >= fields.size() || fields[k] != kHeadColumns[k])
                    fail(1, "",
                         "header column " + std::to_string(k + 1) + " is '" +
                             printable(k < fields.size() ? fields[k] : std::string_view(), 20) + "'" + allowed);
            header_fields_ = fields.size();
            study_columns_ = hasStudyColumns(fields);
            return std::nullopt;
        }
        if (line.empty()) fail(line_no_, "", "empty line; allowed one sample per line");
        if (fields.size() != header_fields_)
            fail(line_no_, "",
                 std::to_string(fields.size()) + " fields; allowed " + std::to_string(header_fields_) +
                     " (as the header)");
        auto number = [&](std::size_t k, std::string_view column) {
            const std::string_view f = fields[k];
            double v = 0.0;
            const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
            if (f.empty() || ec != std::errc() || ptr != f.data() + f.size() || !std::isfinite(v))
                fail(line_no_, column, "'" + printable(f, 40) + "' is not a finite number");
            return v;
        };
        double v[8];
        for (std::size_t k = 0; k < kHeadColumns.size(); ++k) v[k] = number(k, kHeadColumns[k]);
        TraceRow r;
        r.t_s = v[0];
        if (r.t_s < 0.0) fail(line_no_, "t_s", "negative; allowed seconds >= 0");
        if (r.t_s > kMaxTraceTime_s)
            fail(line_no_, "t_s",
                 core::shownNumber(r.t_s) + " s; allowed seconds from 0 to " + core::shownNumber(kMaxTraceTime_s));
        if (rows_ > 0 && r.t_s < last_t_s_)
            fail(line_no_, "t_s", "decreases (" + std::to_string(last_t_s_) + " before); allowed times in order");
        r.head_world = {v[1], v[2], v[3]};
        if (!(std::abs(v[1]) <= 1e9 && std::abs(v[2]) <= 1e9 && std::abs(v[3]) <= 1e9))
            fail(line_no_, "head_x", "out of range; allowed world coordinates within 1e9 m");
        const glm::dquat q(v[4], v[5], v[6], v[7]);
        const double norm = glm::length(q);
        if (!(std::abs(norm - 1.0) <= 1e-3))
            fail(line_no_, "head_qw",
                 "quaternion norm " + std::to_string(norm) + "; allowed a unit quaternion (within 1e-3)");
        r.head_orientation = q / norm;
        if (study_columns_) {
            const std::size_t m = kHeadColumns.size();
            if (fields[m] == "automatic")
                r.mode = TraceMode::Automatic;
            else if (fields[m] == "free")
                r.mode = TraceMode::Free;
            else
                fail(line_no_, "mode", "'" + printable(fields[m], 40) + "'; allowed automatic or free");
            r.scale = number(m + 1, "scale");
            if (!(r.scale > 0.0))
                fail(line_no_, "scale", "'" + printable(fields[m + 1], 40) + "'; allowed a number > 0");
            if (r.scale > kMaxTraceScale)
                fail(line_no_, "scale",
                     "'" + printable(fields[m + 1], 40) + "'; allowed at most " + core::shownNumber(kMaxTraceScale));
            if (!fields[m + 2].empty() || !fields[m + 3].empty() || !fields[m + 4].empty()) {
                const glm::dvec3 hit(number(m + 2, "hit_x"), number(m + 3, "hit_y"), number(m + 4, "hit_z"));
                if (!(std::abs(hit.x) <= 1e9 && std::abs(hit.y) <= 1e9 && std::abs(hit.z) <= 1e9))
                    fail(line_no_, "hit_x", "out of range; allowed world coordinates within 1e9 m");
                r.hit_world = hit;
            }
        }
        ++rows_;
        last_t_s_ = r.t_s;
        return r;
    }

    // After the last line: a trace has a header and at least one sample.
    void finish() const {
        if (line_no_ == 0) fail(1, "", "empty file; allowed a header and samples");
        if (rows_ == 0) fail(line_no_, "", "no samples after the header");
    }

    std::size_t lineNumber() const { return line_no_; }
    [[noreturn]] void fail(std::size_t line, std::string_view column, const std::string& what) const {
        throw Error(where_ + "line " + std::to_string(line) +
                    (column.empty() ? std::string() : ", column " + std::string(column)) + ": " + what);
    }

  private:
    std::string where_;
    std::size_t line_no_ = 0, header_fields_ = 0, rows_ = 0;
    double last_t_s_ = 0.0;
    bool study_columns_ = false;
};

}  // namespace

Trace parseTrace(std::string_view text, const std::filesystem::path& name) {
    TraceParser parser(name);
    Trace trace;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        if (std::optional<TraceRow> row = parser.line(text.substr(pos, end - pos))) trace.rows.push_back(*row);
        pos = end + 1;
    }
    parser.finish();
    trace.study_columns = parser.studyColumns();
    return trace;
}

namespace {

// The blocks of `file` read in order, each handed to `block`; at most `max_bytes` of them
// (0: no bound). Throws Error("<what> ...") when the file cannot be read, is not a
// regular file, or has more bytes than that.
void forEachBlock(const std::filesystem::path& file, const std::string& what, std::uint64_t max_bytes,
                  const std::function<void(std::string_view)>& block) {
    platform::checkInputFile(file, what);
    // O_NONBLOCK: should the name have become a FIFO since the check, open() must not wait.
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) throw Error(what + " cannot be read: " + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st{};
    if (::fstat(fd, &st) != 0) throw Error(what + " cannot be read: " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw Error(what + " is not a regular file; allowed: a regular file");
    const auto too_long = [&](std::uint64_t bytes) {
        return Error(what + " " + std::to_string(bytes) + " bytes or more; allowed at most " +
                     std::to_string(max_bytes));
    };
    if (max_bytes > 0 && std::uint64_t(st.st_size) > max_bytes) throw too_long(std::uint64_t(st.st_size));
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::vector<char> buffer(kTraceBlockBytes);
    std::uint64_t read = 0;
    for (;;) {
        const ssize_t n = ::read(fd, buffer.data(), buffer.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            throw Error(what + " cannot be read: " + std::strerror(errno));
        }
        if (n == 0) break;
        read += std::uint64_t(n);
        if (max_bytes > 0 && read > max_bytes) throw too_long(read);  // grown since fstat
        block(std::string_view(buffer.data(), std::size_t(n)));
    }
}

// The rows of `file` by the parser's rules, a block at a time, each handed to `visit`;
// returns whether the header has the study columns.
bool forEachRow(const std::filesystem::path& file, const std::string& what, std::uint64_t max_bytes,
                const std::function<void(const TraceRow&)>& visit) {
    TraceParser parser(file);
    std::string carry;  // the line begun at the end of the previous block
    forEachBlock(file, what, max_bytes, [&](std::string_view data) {
        while (!data.empty()) {
            const std::size_t end = data.find('\n');
            if (end == std::string_view::npos) {
                carry.append(data);
                if (carry.size() > kMaxTraceLineBytes)
                    parser.fail(
                        parser.lineNumber() + 1, "",
                        "longer than " + std::to_string(kMaxTraceLineBytes) + " bytes; allowed one sample per line");
                break;
            }
            std::optional<TraceRow> row;
            if (carry.empty()) {
                row = parser.line(data.substr(0, end));
            } else {
                carry.append(data.substr(0, end));
                row = parser.line(carry);
                carry.clear();
            }
            if (row) visit(*row);
            data.remove_prefix(end + 1);
        }
    });
    if (!carry.empty())
        if (std::optional<TraceRow> row = parser.line(carry)) visit(*row);
    parser.finish();
    return parser.studyColumns();
}

}  // namespace

Trace readTrace(const std::filesystem::path& file) {
    const std::string what = "trace: " + printable(file.string(), 400) + ":";
    // The rows counted first (one per line after the header; the last line may lack its
    // break), so that they are held in one allocation of their size rather than in a
    // vector grown twice over.
    std::size_t breaks = 0;
    bool ends_with_break = true;
    forEachBlock(file, what, kMaxTraceBytes, [&](std::string_view b) {
        breaks += std::size_t(std::count(b.begin(), b.end(), '\n'));
        ends_with_break = b.back() == '\n';
    });
    const std::size_t lines = breaks + (ends_with_break ? 0 : 1);
    Trace trace;
    trace.rows.reserve(std::min(lines > 0 ? lines - 1 : 0, kMaxTraceRows));
    trace.study_columns = forEachRow(file, what, kMaxTraceBytes, [&](const TraceRow& row) {
        if (trace.rows.size() == kMaxTraceRows)
            throw Error(what + " line " + std::to_string(kMaxTraceRows + 2) + ": more than " +
                        std::to_string(kMaxTraceRows) + " samples; allowed at most " + std::to_string(kMaxTraceRows));
        trace.rows.push_back(row);
    });
    return trace;
}

bool forEachTraceRow(const std::filesystem::path& file, const std::function<void(const TraceRow&)>& visit) {
    return forEachRow(file, "trace: " + printable(file.string(), 400) + ":", 0, visit);
}

}  // namespace io
