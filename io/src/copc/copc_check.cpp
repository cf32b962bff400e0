// io/src/copc/copc_check.cpp: io::checkCopc, the COPC validator. The layout is checked
// without decoding (copc_parse.cpp), the whole file by the LAS reader's own checks (as
// `view` and `metric` read it), then every node on its own: its chunk wrapped as a LAZ
// file, checked by the LAS reader and decoded by LASzip in a child process (a corrupt
// chunk ends only the child), which sends back what the node's points hold: bounds,
// counts by return, and the first point outside its cube, outside the GPS time range or
// with a return number beyond its number of returns. One node at a time, so memory stays
// that of one chunk. Rules and names: docs/formats.md ("Checking COPC").
#include <io/cloud_reader.hpp>
#include <io/copc.hpp>

#include "copc_parse.hpp"

#include <core/error.hpp>

#include <laszip/laszip_api.h>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstring>
#include <map>
#include <sstream>

namespace io {

using core::Error;

namespace {

// What a node's points hold, sent by the decoding child as plain bytes.
struct NodeStats {
    std::uint64_t points = 0;
    std::int32_t min[3] = {INT32_MAX, INT32_MAX, INT32_MAX};
    std::int32_t max[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
    std::uint64_t by_return[15] = {};
    std::uint64_t outside = 0, first_outside = 0;
    double outside_xyz[3] = {};
    std::uint64_t bad_return = 0, first_bad_return = 0;
    unsigned return_number = 0, returns = 0;
    std::uint64_t bad_gps = 0, first_bad_gps = 0;
    double gps = 0.0;
};

bool readAll(int fd, void* data, std::size_t n) {
    char* p = static_cast<char*>(data);
    while (n > 0) {
        const ssize_t r = ::read(fd, p, n);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) return false;
        p += r;
        n -= std::size_t(r);
    }
    return true;
}

[[noreturn]] void decodeChild(int fd, const std::string& laz, const detail::CopcLayout& l, const CopcNode& node) {
    for (const int sig : {SIGINT, SIGTERM, SIGPIPE, SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL})
        std::signal(sig, SIG_DFL);
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null >= 0) ::dup2(null, STDERR_FILENO);
    glm::dvec3 lo, hi;
    detail::nodeCube(l.info, node.key, lo, hi);
    NodeStats st;
    std::istringstream in(laz);
    laszip_POINTER zip = nullptr;
    laszip_BOOL compressed = 0;
    laszip_point_struct* q = nullptr;
    if (laszip_create(&zip) != 0 || laszip_open_reader_stream(zip, in, &compressed) != 0 ||
        laszip_get_point_pointer(zip, &q) != 0)
        ::_exit(1);
    for (std::uint64_t i = 0; i < std::uint64_t(node.point_count); ++i) {
        if (laszip_read_point(zip) != 0) ::_exit(1);
        const std::int32_t xyz[3] = {q->X, q->Y, q->Z};
        bool outside = false;
        for (int k = 0; k < 3; ++k) {
            st.min[k] = std::min(st.min[k], xyz[k]);
            st.max[k] = std::max(st.max[k], xyz[k]);
            const double w = double(xyz[k]) * l.scale[k] + l.offset[k];
            if (!(w >= lo[k] - l.scale[k] && w <= hi[k] + l.scale[k])) outside = true;
        }
        if (outside && st.outside++ == 0) {
            st.first_outside = i;
            for (int k = 0; k < 3; ++k) st.outside_xyz[k] = double(xyz[k]) * l.scale[k] + l.offset[k];
        }
        const unsigned rn = q->extended_return_number, nr = q->extended_number_of_returns;
        if ((rn < 1 || rn > nr) && st.bad_return++ == 0) {
            st.first_bad_return = i;
            st.return_number = rn;
            st.returns = nr;
        }
        if (rn >= 1 && rn <= 15) ++st.by_return[rn - 1];
        const double t = q->gps_time;
        if (!(t >= l.info.gpstime_minimum && t <= l.info.gpstime_maximum) && st.bad_gps++ == 0) {
            st.first_bad_gps = i;
            st.gps = t;
        }
        ++st.points;
    }
    const char* p = reinterpret_cast<const char*>(&st);
    std::size_t n = sizeof st;
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) ::_exit(1);
        p += w;
        n -= std::size_t(w);
    }
    ::_exit(0);
}

// Decodes `node` in a child; false when LASzip fails or the child dies.
bool decodeNode(const std::string& laz, const detail::CopcLayout& l, const CopcNode& node, NodeStats& st) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw Error(std::string("copc: cannot start a decoder: ") + std::strerror(errno));
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int e = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        throw Error(std::string("copc: cannot start a decoder: ") + std::strerror(e));
    }
    if (pid == 0) {
        ::close(fds[0]);
        decodeChild(fds[1], laz, l, node);
    }
    ::close(fds[1]);
    const bool got = readAll(fds[0], &st, sizeof st);
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    return got && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::string n2s(std::uint64_t v) { return std::to_string(v); }
std::string num(double v) { return core::shownNumber(v, 10); }

// A reader's message without its "<module>: <file>: " start: the finding is about that file.
std::string aboutFile(const std::string& message, const char* module, const std::filesystem::path& file) {
    const std::string start = std::string(module) + ": " + file.string() + ": ";
    return message.rfind(start, 0) == 0 ? message.substr(start.size()) : message;
}

// At most 20 findings per rule, then one line counting the rest.
std::vector<CopcFinding> capped(const std::vector<CopcFinding>& all) {
    std::vector<CopcFinding> out;
    std::map<std::string, std::size_t> seen;
    for (const CopcFinding& f : all)
        if (++seen[f.rule] <= 20) out.push_back(f);
    for (const auto& [rule, n] : seen)
        if (n > 20) out.push_back({rule, n2s(n - 20) + " more findings of this rule"});
    return out;
}

}  // namespace

std::vector<CopcFinding> checkCopc(const std::filesystem::path& file) {
    std::vector<CopcFinding> f;
    std::unique_ptr<detail::ByteSource> source;
    try {
        source = detail::fileSource(file, "copc");
    } catch (const Error& e) {
        return {{"not-las", aboutFile(e.what(), "copc", file)}};
    }
    detail::CopcLayout l;
    const bool ok = detail::parseCopc(*source, l, f);
    if (!l.header.empty()) {
        try {
            CloudReader whole(file);
        } catch (const Error& e) {
            f.push_back({"las", aboutFile(e.what(), "las", file)});
        }
    }
    // Nodes are decoded only in a file of COPC's point formats whose layout could be read.
    if (!ok || l.laszip_vlr.size() < 54 + 34 || l.format < 6 || l.format > 8) return capped(f);
    // The header is compared with the points only when the nodes hold every chunk's points.
    const bool complete = std::none_of(f.begin(), f.end(), [](const CopcFinding& x) {
        return x.rule == "point-count" || x.rule == "chunk-unreferenced" || x.rule == "node-chunk" ||
               x.rule == "chunk-table";
    });

    std::uint64_t by_return[15] = {};
    std::int64_t min[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, max[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    std::uint64_t decoded = 0;
    bool all_decoded = true;
    for (const CopcNode& node : l.nodes) {
        const std::string name = "node " + detail::keyName(node.key);
        const std::string laz = detail::nodeLaz(*source, l, node);
        try {
            CloudReader layout(laz, name);  // the LAS reader's checks before LASzip decodes
        } catch (const Error& e) {
            std::string m = e.what();
            if (m.rfind("las: ", 0) == 0) m.erase(0, 5);  // the LAS reader's module name
            f.push_back({"chunk-decode", m});
            all_decoded = false;
            continue;
        }
        NodeStats st;
        if (!decodeNode(laz, l, node, st) || st.points != std::uint64_t(node.point_count)) {
            f.push_back({"chunk-decode", name + ": LASzip cannot decode its " + n2s(std::uint64_t(node.point_count)) +
                                             " points from its chunk of " + std::to_string(node.byte_size) +
                                             " bytes at byte " + n2s(node.offset)});
            all_decoded = false;
            continue;
        }
        decoded += st.points;
        for (int r = 0; r < 15; ++r) by_return[r] += st.by_return[r];
        for (int k = 0; k < 3; ++k) {
            min[k] = std::min<std::int64_t>(min[k], st.min[k]);
            max[k] = std::max<std::int64_t>(max[k], st.max[k]);
        }
        if (st.outside > 0 && detail::cubeUsable(l.info)) {  // else info-values says why
            glm::dvec3 lo, hi;
            detail::nodeCube(l.info, node.key, lo, hi);
            f.push_back({"xyz", name + ": " + n2s(st.outside) + " of its " + n2s(st.points) +
                                    " points are outside its cube (" + num(lo.x) + ", " + num(lo.y) + ", " + num(lo.z) +
                                    ") to (" + num(hi.x) + ", " + num(hi.y) + ", " + num(hi.z) +
                                    "); the first: point " + n2s(st.first_outside) + " at (" + num(st.outside_xyz[0]) +
                                    ", " + num(st.outside_xyz[1]) + ", " + num(st.outside_xyz[2]) + ")"});
        }
        if (st.bad_gps > 0)
            f.push_back({"gps-time", name + ": " + n2s(st.bad_gps) + " points have a GPS time outside the info VLR's " +
                                         num(l.info.gpstime_minimum) + " to " + num(l.info.gpstime_maximum) +
                                         "; the first: point " + n2s(st.first_bad_gps) + " at " + num(st.gps)});
        if (st.bad_return > 0)
            f.push_back({"return-number", name + ": " + n2s(st.bad_return) +
                                              " points have a return number outside 1 to their number of returns; "
                                              "the first: point " +
                                              n2s(st.first_bad_return) + ", return " + n2s(st.return_number) + " of " +
                                              n2s(st.returns)});
    }
    if (!all_decoded || !complete || decoded == 0) return capped(f);
    // The header against the points: bounds (to half a scale unit) and counts.
    for (int k = 0; k < 3; ++k) {
        const double lo = double(min[k]) * l.scale[k] + l.offset[k];
        const double hi = double(max[k]) * l.scale[k] + l.offset[k];
        if (std::abs(lo - l.min[k]) > 0.5 * l.scale[k] || std::abs(hi - l.max[k]) > 0.5 * l.scale[k])
            f.push_back({"header-bounds", std::string("the header's ") + "xyz"[k] + " bounds " + num(l.min[k]) +
                                              " to " + num(l.max[k]) + " are not the points' " + num(lo) + " to " +
                                              num(hi)});
    }
    for (std::size_t r = 0; r < 15; ++r)
        if (l.by_return[r] != by_return[r])
            f.push_back({"point-count-by-return", "the header counts " + n2s(l.by_return[r]) + " points of return " +
                                                      n2s(r + 1) + " but the points hold " + n2s(by_return[r])});
    // LAS 1.4 legacy counts: zero, or (for files that fit them) the same as the 64-bit ones.
    const bool legacy_zero = l.legacy_count == 0;
    if (!legacy_zero && (decoded > UINT32_MAX || l.legacy_count != decoded))
        f.push_back({"legacy-point-count", "the legacy point count is " + n2s(l.legacy_count) +
                                               "; allowed: 0 or the points' " + n2s(decoded)});
    for (std::size_t r = 0; r < 5; ++r) {
        const std::uint32_t v = l.legacy_by_return[r];
        if (v != 0 && (legacy_zero || v != by_return[r]))
            f.push_back({"legacy-point-count", "the legacy count of return " + n2s(r + 1) + " is " + n2s(v) +
                                                   "; allowed: " +
                                                   (legacy_zero ? std::string("0 (the legacy point count is 0)")
                                                                : "0 or the points' " + n2s(by_return[r]))});
    }
    return capped(f);
}

}  // namespace io
