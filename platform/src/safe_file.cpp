// safe_file: the one place where the project opens outside files and creates its own
// (contract in platform/safe_file.hpp). Every name goes through *at() calls relative to an
// open folder, so a folder swapped for a symlink half-way cannot redirect a write.
#include <core/error.hpp>
#include <platform/cleanup.hpp>
#include <platform/safe_file.hpp>
#include <platform/test_hold.hpp>

#include "file_ops.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <system_error>
#include <vector>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

namespace platform {

using core::Error;
namespace fs = std::filesystem;

// Shared with output_folder.cpp (file_ops.hpp).

std::string shownPath(const fs::path& p) { return core::printable(p.string(), 400, true); }

std::string errnoText(int e) { return std::strerror(e); }

const char* kindName(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISLNK(mode)) return "a symbolic link";
    if (S_ISREG(mode)) return "a regular file";
    return "not a regular file";
}

// ".ladarvr-tmp-<pid>-" followed by six random letters and digits.
std::string randomTempName() {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    unsigned char bytes[6];
    if (::getrandom(bytes, sizeof bytes, 0) != ssize_t(sizeof bytes)) {
        // No entropy source: fall back on the clock; O_EXCL still makes creation safe.
        const auto t = std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count());
        for (std::size_t i = 0; i < sizeof bytes; ++i) bytes[i] = static_cast<unsigned char>(t >> (8 * i));
    }
    std::string name = std::string(kTempPrefix) + std::to_string(::getpid()) + "-";
    for (unsigned char b : bytes) name += kAlphabet[b % (sizeof kAlphabet - 1)];
    return name;
}

int openFolder(const fs::path& dir, const fs::path& for_output) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        throw Error("output: " + shownPath(for_output) + ": cannot open the folder '" + shownPath(dir) +
                    "': " + errnoText(errno));
    return fd;
}

namespace {

std::string sizeText(std::size_t bytes) {
    if (bytes >= (1u << 20) && bytes % (1u << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
    if (bytes >= (1u << 10) && bytes % (1u << 10) == 0) return std::to_string(bytes >> 10) + " KiB";
    return std::to_string(bytes) + " bytes";
}

// The pid of a temporary's name, ".ladarvr-tmp-<pid>-<tag>", or -1. The tag is the six
// random characters of randomTempName or a caller's own (a corpus item's id, 4 or more
// digits): 1 to kMaxTempTagChars letters and digits.
constexpr std::size_t kMaxTempTagChars = 32;
pid_t tempNamePid(std::string_view name) {
    if (name.substr(0, kTempPrefix.size()) != kTempPrefix) return -1;
    name.remove_prefix(kTempPrefix.size());
    const std::size_t dash = name.find('-');
    if (dash == 0 || dash == std::string_view::npos || dash > 10 || name.size() <= dash + 1 ||
        name.size() > dash + 1 + kMaxTempTagChars)
        return -1;
    long long pid = 0;
    for (char c : name.substr(0, dash)) {
        if (c < '0' || c > '9') return -1;
        pid = pid * 10 + (c - '0');
    }
    for (char c : name.substr(dash + 1))
        if (!std::isalnum(static_cast<unsigned char>(c))) return -1;
    return pid > 0 && pid <= 0x7fffffff ? pid_t(pid) : -1;
}

// The folder of a destination file and the file's name in it.
std::pair<fs::path, std::string> splitDestination(const fs::path& destination) {
    fs::path dir = destination.parent_path();
    if (dir.empty()) dir = ".";
    return {dir, destination.filename().string()};
}

// Removes a dead run's temporary file (regular, ours) or folder (removeOwnFolder's checks) by name
// inside `dirfd`; anything else stays.
void removeStaleEntry(int dirfd, const std::string& name, const OwnedName& folder_holds) {
    struct stat st{};
    if (::fstatat(dirfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0 || st.st_uid != ::geteuid()) return;
    if (S_ISDIR(st.st_mode))
        removeOwnFolder(dirfd, name, folder_holds);
    else if (S_ISREG(st.st_mode))
        ::unlinkat(dirfd, name.c_str(), 0);
}

}  // namespace

namespace {

// The length of the valid UTF-8 sequence of a printable character at s[i] (1 for ASCII),
// 0 when s[i] starts a control character (C0, DEL, C1) or is not valid UTF-8 there.
std::size_t printableCharLength(std::string_view s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = byte(i);
    if (c < 0x20 || c == 0x7f) return 0;
    if (c < 0x80) return 1;
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // the range of the second byte
    if (c >= 0xC2 && c <= 0xDF)
        n = 2;
    else if (c == 0xE0)
        n = 3, lo = 0xA0;
    else if (c == 0xED)
        n = 3, hi = 0x9F;  // no UTF-16 surrogates
    else if (c >= 0xE1 && c <= 0xEF)
        n = 3;
    else if (c == 0xF0)
        n = 4, lo = 0x90;
    else if (c == 0xF4)
        n = 4, hi = 0x8F;  // nothing past U+10FFFF
    else if (c >= 0xF1 && c <= 0xF3)
        n = 4;
    else
        return 0;  // a stray continuation, C0/C1 overlong, F5..FF
    if (i + n > s.size() || byte(i + 1) < lo || byte(i + 1) > hi) return 0;
    for (std::size_t k = 2; k < n; ++k)
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
    if (c == 0xC2 && byte(i + 1) < 0xA0) return 0;  // U+0080..U+009F: C1 controls (CSI is U+009B)
    return n;
}

// Calls piece(text) for each character of `s` as shown: kept, or "\xNN" per byte.
template <class Piece>
void forEachShown(std::string_view s, Piece&& piece) {
    std::size_t i = 0;
    while (i < s.size()) {
        const std::size_t n = printableCharLength(s, i);
        if (n > 0) {
            piece(s.substr(i, n));
            i += n;
        } else {
            char escaped[8];
            std::snprintf(escaped, sizeof escaped, "\\x%02x", static_cast<unsigned char>(s[i]));
            piece(std::string_view(escaped, 4));
            ++i;
        }
    }
}

}  // namespace

std::string printableUtf8(std::string_view text, std::size_t max_chars) {
    std::string out;
    out.reserve(std::min(text.size(), max_chars) + 3);
    bool cut = false;
    forEachShown(text, [&](std::string_view piece) {
        if (cut) return;
        if (out.size() + piece.size() > max_chars) {
            out += "...";
            cut = true;
            return;
        }
        out += piece;
    });
    return out;
}

std::string messageLine(std::string_view message, std::size_t max_chars) {
    // Whole characters only: remember where each shown character starts.
    std::string shown;
    std::vector<std::size_t> starts;
    shown.reserve(message.size());
    forEachShown(message, [&](std::string_view piece) {
        starts.push_back(shown.size());
        shown += piece;
    });
    if (shown.size() <= max_chars) return shown;
    constexpr std::string_view kGap = " ... ";
    const std::size_t budget = max_chars > kGap.size() ? max_chars - kGap.size() : 0;
    const std::size_t tail_budget = budget / 3, head_budget = budget - tail_budget;
    // The last character start at or before head_budget, the first at or after the tail's.
    const std::size_t head = *(std::upper_bound(starts.begin(), starts.end(), head_budget) - 1);
    const auto tail_it = std::lower_bound(starts.begin(), starts.end(), shown.size() - tail_budget);
    const std::size_t tail = tail_it == starts.end() ? shown.size() : *tail_it;
    return shown.substr(0, head) + std::string(kGap) + shown.substr(tail);
}

void printMessage(std::string_view label, std::string_view what) {
    const std::string line = "ladarvr: " + std::string(label) + ": " + messageLine(what) + "\n";
    std::fwrite(line.data(), 1, line.size(), stderr);
}

std::string regularFileProblem(const fs::path& path) {
    if (path.empty()) return "is an empty name";
    struct stat st{};
    if (::stat(path.c_str(), &st) == 0)
        return S_ISREG(st.st_mode) ? std::string() : std::string("is ") + kindName(st.st_mode);
    const int e = errno;
    switch (e) {
        case ENOENT: {
            struct stat lst{};
            if (::lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
                std::error_code ec;
                const fs::path target = fs::read_symlink(path, ec);
                return "is a dangling symbolic link (to '" + shownPath(target) + "', which does not exist)";
            }
            return "does not exist";
        }
        case ELOOP: return "is a symbolic link loop (too many levels of symbolic links)";
        case ENOTDIR: return "does not exist (a folder on its path is not a directory)";
        case EACCES: return "cannot be reached: " + errnoText(e);
        default: return "cannot be examined: " + errnoText(e);
    }
}

void checkInputFile(const fs::path& path, std::string_view what) {
    const std::string problem = regularFileProblem(path);
    if (!problem.empty())
        throw Error(std::string(what) + " " + problem +
                    (problem.rfind("is a", 0) == 0 ? "; allowed: a regular file" : ""));
}

namespace {
std::string readRegularFile(const fs::path& path, std::size_t max_bytes, std::string_view what, bool own_output) {
    const std::string allowed = "; allowed: a regular file of at most " + sizeText(max_bytes);
    const std::string problem = regularFileProblem(path);
    if (!problem.empty())
        throw Error(std::string(what) + " " + problem + (problem.rfind("is a", 0) == 0 ? allowed : ""));
    // O_NONBLOCK: should the name have become a FIFO since the check, open() must not wait.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY | (own_output ? O_NOFOLLOW : 0));
    if (fd < 0) throw Error(std::string(what) + " cannot be read: " + errnoText(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st{};
    if (::fstat(fd, &st) != 0) throw Error(std::string(what) + " cannot be read: " + errnoText(errno));
    if (!S_ISREG(st.st_mode)) throw Error(std::string(what) + " is " + kindName(st.st_mode) + allowed);
    if (st.st_size > 0 && std::uint64_t(st.st_size) > max_bytes)
        throw Error(std::string(what) + " is " + std::to_string(st.st_size) + " bytes" + allowed);
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::string text;
    text.resize(std::min<std::size_t>(max_bytes + 1, st.st_size > 0 ? std::size_t(st.st_size) + 1 : 65536));
    std::size_t used = 0;
    for (;;) {
        if (used == text.size()) {
            if (text.size() > max_bytes) break;
            text.resize(std::min(max_bytes + 1, text.size() * 2));
        }
        const ssize_t n = ::read(fd, text.data() + used, text.size() - used);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw Error(std::string(what) + " cannot be read: " + errnoText(errno));
        }
        if (n == 0) break;
        used += std::size_t(n);
    }
    if (used > max_bytes) throw Error(std::string(what) + " holds more than " + sizeText(max_bytes) + allowed);
    text.resize(used);
    return text;
}
}  // namespace

std::string readTextFile(const fs::path& path, std::size_t max_bytes, std::string_view what) {
    return readRegularFile(path, max_bytes, what, false);
}

void checkNoLinkBelow(const fs::path& dir, const fs::path& relative, std::string_view what) {
    int fd = ::open(dir.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;  // the reader names the missing folder
    fs::path walked;
    for (auto it = relative.begin(); it != relative.end(); ++it) {
        const std::string name = it->string();
        if (name.empty() || name == ".") continue;
        walked /= name;
        struct stat st{};
        const bool last = std::next(it) == relative.end();
        if (name == ".." || ::fstatat(fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) break;
        if (S_ISLNK(st.st_mode)) {
            ::close(fd);
            throw Error(std::string(what) + " '" + shownPath(dir / relative) + "': '" + shownPath(walked) +
                        "' in it is a symbolic link; allowed: the folder's own " + (last ? "file" : "folders") +
                        ", not a link");
        }
        if (last || !S_ISDIR(st.st_mode)) break;
        const int next = ::openat(fd, name.c_str(), O_PATH | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        ::close(fd);
        fd = next;
        if (fd < 0) return;
    }
    ::close(fd);
}

std::string readOwnOutput(const fs::path& path, std::size_t max_bytes, std::string_view what) {
    struct stat st{};
    if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode))
        throw Error(std::string(what) + " is a symbolic link; allowed: the regular file a run wrote");
    return readRegularFile(path, max_bytes, what, true);
}

int openOwnFile(const fs::path& path, int flags, std::string_view what) {
    const std::string head = std::string(what) + " " + shownPath(path) + ": ";
    const std::string allowed = "; allowed: a regular file this command created";
    const auto refuse = [&](const struct stat& st) {
        if (!S_ISREG(st.st_mode)) throw Error(head + "is " + kindName(st.st_mode) + allowed);
        if (st.st_uid != ::geteuid())
            throw Error(head + "belongs to user id " + std::to_string(st.st_uid) + ", not this one" + allowed);
    };
    struct stat st{};
    if (::lstat(path.c_str(), &st) == 0) refuse(st);
    const int fd = ::open(path.c_str(), flags | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC, 0666);
    if (fd < 0) {
        const int e = errno;
        if (e == ELOOP) throw Error(head + "is a symbolic link" + allowed);
        throw Error(head + "cannot open: " + errnoText(e));
    }
    if (::fstat(fd, &st) != 0) {
        const int e = errno;
        ::close(fd);
        throw Error(head + "cannot examine: " + errnoText(e));
    }
    try {
        refuse(st);
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

std::string readOwnFile(const fs::path& path, std::size_t max_bytes, std::string_view what) {
    const int fd = openOwnFile(path, O_RDONLY, what);
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    const std::string head = std::string(what) + " " + shownPath(path) + ": ";
    std::string text;
    char buffer[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw Error(head + "cannot be read: " + errnoText(errno));
        if (n == 0) break;
        text.append(buffer, std::size_t(n));
        if (text.size() > max_bytes)
            throw Error(head + "holds more than " + sizeText(max_bytes) + "; allowed: a file this command wrote");
    }
    return text;
}

void makeOwnFolder(const fs::path& path, std::string_view what) {
    const std::string head = std::string(what) + " " + shownPath(path) + ": ";
    if (::mkdir(path.c_str(), 0777) == 0) return;
    const int e = errno;
    struct stat st{};
    if (e != EEXIST || ::lstat(path.c_str(), &st) != 0) throw Error(head + "cannot create the folder: " + errnoText(e));
    if (!S_ISDIR(st.st_mode))
        throw Error(head + "is " + kindName(st.st_mode) + "; allowed: a folder this command made");
    if (st.st_uid != ::geteuid())
        throw Error(head + "belongs to user id " + std::to_string(st.st_uid) +
                    ", not this one; allowed: a folder this command made");
}

// ---------------------------------------------------------------------------------
// Path checks
// ---------------------------------------------------------------------------------

void checkPathLength(const fs::path& path, std::string_view what) {
    const std::string& text = path.native();
    const auto fail = [&](const std::string& why) {
        throw Error(std::string(what) + ": " + core::printable(text, 120, true) + ": " + why);
    };
    if (text.size() > kMaxPathBytes)
        fail("the path is " + std::to_string(text.size()) + " bytes long; allowed at most " +
             std::to_string(kMaxPathBytes) + " bytes");
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('/', start);
        if (end == std::string::npos) end = text.size();
        if (end - start > kMaxNameBytes)
            fail("a name in it is " + std::to_string(end - start) + " bytes long; allowed at most " +
                 std::to_string(kMaxNameBytes) + " bytes per name");
        start = end + 1;
    }
}

namespace {

// A run's path as the system resolves it: links in its existing part followed, "." and
// ".." gone; with the file's identity when it exists.
struct ResolvedPath {
    fs::path canonical;
    bool exists = false;
    dev_t dev = 0;
    ino_t ino = 0;
};

ResolvedPath resolveRunPath(const fs::path& path) {
    ResolvedPath r;
    std::error_code ec;
    fs::path absolute = fs::absolute(path, ec);
    if (ec) absolute = path;
    r.canonical = fs::weakly_canonical(absolute, ec);
    if (ec) r.canonical = absolute.lexically_normal();
    if (!r.canonical.has_filename() && r.canonical != r.canonical.root_path())
        r.canonical = r.canonical.parent_path();  // "dir/" and "dir" are one folder
    struct stat st{};
    if (::stat(path.c_str(), &st) == 0) {
        r.exists = true;
        r.dev = st.st_dev;
        r.ino = st.st_ino;
    }
    return r;
}

// The first name of `inner` below `outer` when `inner` lies inside it; else empty.
std::string firstNameInside(const fs::path& inner, const fs::path& outer) {
    auto i = inner.begin();
    for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
        if (o->empty()) continue;  // a trailing separator
        if (i == inner.end() || *i != *o) return {};
    }
    return i == inner.end() ? std::string() : i->string();
}

bool isInput(PathRole role) { return role == PathRole::Input || role == PathRole::InputFolder; }

}  // namespace

void checkDistinctPaths(std::string_view command, const std::vector<RunPath>& paths) {
    const std::string head = std::string(command) + ": ";
    std::vector<ResolvedPath> resolved(paths.size());
    for (std::size_t k = 0; k < paths.size(); ++k) {
        if (paths[k].path.empty()) continue;
        checkPathLength(paths[k].path, head + paths[k].option);
        resolved[k] = resolveRunPath(paths[k].path);
    }
    const auto named = [&](std::size_t k) { return paths[k].option + " '" + shownPath(paths[k].path) + "'"; };
    for (std::size_t a = 0; a < paths.size(); ++a) {
        if (paths[a].path.empty()) continue;
        for (std::size_t b = 0; b < paths.size(); ++b) {
            if (b == a || paths[b].path.empty()) continue;
            const ResolvedPath& ra = resolved[a];
            const ResolvedPath& rb = resolved[b];
            if (b > a && !(isInput(paths[a].role) && isInput(paths[b].role))) {
                const bool same =
                    ra.canonical == rb.canonical || (ra.exists && rb.exists && ra.dev == rb.dev && ra.ino == rb.ino);
                if (same)
                    throw Error(head + named(a) + " and " + named(b) +
                                " name the same file; allowed: a distinct path for each output, none of them an "
                                "input of the run");
            }
            const PathRole outer = paths[a].role;
            const bool writes_inside = outer == PathRole::OutputFolder;
            const bool reads_inside = outer == PathRole::InputFolder && !isInput(paths[b].role);
            if (!writes_inside && !reads_inside) continue;
            const std::string first = firstNameInside(rb.canonical, ra.canonical);
            if (first.empty() || (paths[a].names && !paths[a].names(first))) continue;
            if (writes_inside)
                throw Error(head + named(b) + " lies inside the output folder " + named(a) + ", " +
                            (paths[a].names ? "where this run writes '" + core::printable(first, 80, true) + "'"
                                            : std::string("which this run replaces as a whole")) +
                            "; allowed: a path outside it");
            throw Error(head + named(b) + " lies inside the input folder " + named(a) +
                        ", which this run reads; allowed: an output outside it");
        }
    }
}

// ---------------------------------------------------------------------------------
// Temporaries
// ---------------------------------------------------------------------------------

bool removeOwnFolder(int parent_fd, const std::string& name, const OwnedName& holds) {
    struct stat st{};
    if (::fstatat(parent_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISDIR(st.st_mode) ||
        st.st_uid != ::geteuid())
        return false;
    const int fd = ::openat(parent_fd, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return false;
    struct stat opened{};
    if (::fstat(fd, &opened) != 0 || opened.st_dev != st.st_dev || opened.st_ino != st.st_ino) {
        ::close(fd);
        return false;
    }
    // Look first, remove after: a folder holding anything we do not write there (another
    // folder, a link, a FIFO, a device, someone else's file) stays whole.
    std::vector<std::string> names;
    bool ours = true;
    if (DIR* d = ::fdopendir(::dup(fd))) {
        while (const dirent* e = ::readdir(d)) {
            const std::string entry = e->d_name;
            if (entry == "." || entry == "..") continue;
            struct stat est{};
            const bool known = tempNamePid(entry) > 0 || (holds && holds(entry));
            if (!known || ::fstatat(fd, entry.c_str(), &est, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(est.st_mode) ||
                est.st_uid != ::geteuid()) {
                ours = false;
                break;
            }
            names.push_back(entry);
        }
        ::closedir(d);
    } else {
        ours = false;
    }
    if (ours)
        for (const std::string& entry : names) ::unlinkat(fd, entry.c_str(), 0);
    ::close(fd);
    return ours && ::unlinkat(parent_fd, name.c_str(), AT_REMOVEDIR) == 0;
}

void removeStaleTemporaries(const fs::path& dir, const OwnedName& folder_holds) {
    const int dirfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirfd < 0) return;
    std::vector<std::string> stale;
    if (DIR* d = ::fdopendir(::dup(dirfd))) {
        while (const dirent* e = ::readdir(d)) {
            const pid_t pid = tempNamePid(e->d_name);
            if (pid <= 0 || pid == ::getpid()) continue;
            if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to ask)
            stale.emplace_back(e->d_name);
        }
        ::closedir(d);
    }
    for (const std::string& name : stale) {
        struct stat st{};
        if (::fstatat(dirfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0 || st.st_uid != ::geteuid()) continue;
        removeStaleEntry(dirfd, name, folder_holds);
    }
    ::close(dirfd);
}

TempFile::TempFile(fs::path destination) : destination_(std::move(destination)) {
    const auto [dir, base] = splitDestination(destination_);
    if (base.empty() || base == "." || base == "..")
        throw Error("output: " + shownPath(destination_) + ": is not a file name");
    removeStaleTemporaries(dir);
    dirfd_ = openFolder(dir, destination_);
    int fd = -1;
    try {
        name_ = createUnique(
            [&](const std::string& name) {
                fd = ::openat(dirfd_, name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
                return fd >= 0;
            },
            destination_, dir);
    } catch (...) {
        ::close(dirfd_);
        throw;
    }
    slot_ = detail::registerTemporary(dirfd_, name_.c_str(), false);
    file_ = ::fdopen(fd, "wb");
    if (!file_) {
        const int e = errno;
        ::close(fd);
        discard();
        ::close(dirfd_);
        throw Error("output: " + shownPath(destination_) + ": cannot open a stream: " + errnoText(e));
    }
}

TempFile::~TempFile() {
    discard();
    if (dirfd_ >= 0) ::close(dirfd_);
}

fs::path TempFile::path() const { return splitDestination(destination_).first / name_; }

void TempFile::discard() noexcept {
    if (file_) {
        std::fclose(file_);
        file_ = nullptr;
    }
    if (!name_.empty()) {
        ::unlinkat(dirfd_, name_.c_str(), 0);
        detail::unregisterTemporary(slot_);
        slot_ = -1;
        name_.clear();
    }
}

void TempFile::commit() {
    const std::string out = "output: " + shownPath(destination_) + ": ";
    if (name_.empty()) throw Error(out + "commit called twice");
    auto fail = [&](const std::string& what, int e) {
        discard();
        throw Error(out + what + (e ? ": " + errnoText(e) : std::string()));
    };
    if (file_) {
        const bool flushed = std::fflush(file_) == 0 && !std::ferror(file_);
        const int flush_errno = errno;
        const bool closed = std::fclose(file_) == 0;
        const int close_errno = errno;
        file_ = nullptr;
        if (!flushed || !closed) fail("write failed", flushed ? close_errno : flush_errno);
    }
    if (const char* hold = std::getenv(kHoldCommitVariable))
        holdOnFifo(hold, "held " + name_ + "\n", kHoldCommitVariable, "a FIFO");
    const std::string base = destination_.filename().string();
    for (int attempt = 0; attempt < 3; ++attempt) {
        struct stat st{};
        if (::fstatat(dirfd_, base.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
            if (!S_ISREG(st.st_mode))
                fail(std::string("is ") + kindName(st.st_mode) +
                         "; refusing to replace it (only a regular "
                         "file is replaced)",
                     0);
            if (::renameat(dirfd_, name_.c_str(), dirfd_, base.c_str()) != 0)
                fail("cannot rename the temporary file into place", errno);
        } else if (errno == ENOENT) {
            // Absent now: make sure nothing (a symlink, a device) appears under the name
            // between the check and the rename.
            if (::renameat2(dirfd_, name_.c_str(), dirfd_, base.c_str(), RENAME_NOREPLACE) != 0) {
                if (errno == EEXIST) continue;
                if (errno != EINVAL && errno != ENOSYS) fail("cannot rename the temporary file into place", errno);
                if (::renameat(dirfd_, name_.c_str(), dirfd_, base.c_str()) != 0)
                    fail("cannot rename the temporary file into place", errno);
            }
        } else {
            fail("cannot examine the destination", errno);
        }
        detail::unregisterTemporary(slot_);
        slot_ = -1;
        name_.clear();
        return;
    }
    fail("the destination keeps changing while it is replaced", 0);
}

std::FILE* openScratchFile(const fs::path& dir, std::string_view what) {
    const std::string where =
        "output: " + std::string(what) + ": cannot create a scratch file in '" + shownPath(dir) + "': ";
    int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
        // No O_TMPFILE here: an exclusive random name, unlinked before any data goes in.
        removeStaleTemporaries(dir);
        const int dirfd = openFolder(dir, fs::path(what));
        try {
            const std::string name = createUnique(
                [&](const std::string& n) {
                    fd = ::openat(dirfd, n.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
                    return fd >= 0;
                },
                fs::path(what), dir);
            ::unlinkat(dirfd, name.c_str(), 0);
        } catch (...) {
            ::close(dirfd);
            throw;
        }
        ::close(dirfd);
    }
    if (fd < 0) throw Error(where + errnoText(errno));
    std::FILE* f = ::fdopen(fd, "w+b");
    if (!f) {
        const int e = errno;
        ::close(fd);
        throw Error(where + errnoText(e));
    }
    return f;
}

std::uint64_t freeScratchBefore(std::FILE* scratch, std::uint64_t freed, std::uint64_t end) {
    const std::uint64_t page = 4096, upto = end / page * page;
    if (upto <= freed) return freed;
    (void)::fallocate(::fileno(scratch), FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, off_t(freed), off_t(upto - freed));
    return upto;
}

}  // namespace platform
