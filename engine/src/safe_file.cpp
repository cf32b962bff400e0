// safe_file: the one place where the project opens outside files and creates its own
// (contract in engine/safe_file.hpp). Every name goes through *at() calls relative to an
// open folder, so a folder swapped for a symlink half-way cannot redirect a write.
#include <engine/cleanup.hpp>
#include <engine/error.hpp>
#include <engine/safe_file.hpp>

#include "text.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <system_error>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

namespace engine {
namespace fs = std::filesystem;

namespace {

std::string shownPath(const fs::path& p) { return detail::shown(p.string(), 400, true); }

std::string errnoText(int e) { return std::strerror(e); }

const char* kindName(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    if (S_ISLNK(mode)) return "a symbolic link";
    return "not a regular file";
}

std::string sizeText(std::size_t bytes) {
    if (bytes >= (1u << 20) && bytes % (1u << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
    if (bytes >= (1u << 10) && bytes % (1u << 10) == 0) return std::to_string(bytes >> 10) + " KiB";
    return std::to_string(bytes) + " bytes";
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

int openFolder(const fs::path& dir, const fs::path& for_output) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        throw Error("output: " + shownPath(for_output) + ": cannot open the folder '" + shownPath(dir) +
                    "': " + errnoText(errno));
    return fd;
}

// Files read as inputs of this run, by device and inode.
struct InputFile {
    dev_t dev;
    ino_t ino;
    std::string path;
};
// Folders read as inputs, with the outputs that may still go inside them.
struct InputFolder {
    fs::path canonical;
    std::string path;
    OwnedName may_write;
};
std::mutex g_inputs_mutex;
std::vector<InputFile> g_inputs;
std::vector<InputFolder> g_input_folders;

void rememberInput(const struct stat& st, const fs::path& path) {
    std::lock_guard lock(g_inputs_mutex);
    for (const InputFile& f : g_inputs)
        if (f.dev == st.st_dev && f.ino == st.st_ino) return;
    g_inputs.push_back({st.st_dev, st.st_ino, path.string()});
}

// Removes the previous version of an output folder that resolveOutputFolder accepted
// (not following links: remove_all never follows symlinks inside).
void removeReplacedFolder(const std::string& name, const fs::path& dir) {
    std::error_code ec;
    fs::remove_all(dir / name, ec);
}

// Removes a temporary file (regular, ours) or folder (removeOwnFolder's checks) by name
// inside `dirfd`; anything else stays.
void removeEntry(int dirfd, const std::string& name, const OwnedName& folder_holds) {
    struct stat st {};
    if (::fstatat(dirfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0 || st.st_uid != ::geteuid()) return;
    if (S_ISDIR(st.st_mode))
        removeOwnFolder(dirfd, name, folder_holds);
    else if (S_ISREG(st.st_mode))
        ::unlinkat(dirfd, name.c_str(), 0);
}

// Creates a fresh temporary name in `dirfd` with `make(name)`, retrying on EEXIST.
template <class Make>
std::string createUnique(Make make, const fs::path& for_output, const fs::path& dir) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = randomTempName();
        if (make(name)) return name;
        if (errno != EEXIST)
            throw Error("output: " + shownPath(for_output) + ": cannot create a temporary in '" +
                        shownPath(dir) + "': " + errnoText(errno));
    }
    throw Error("output: " + shownPath(for_output) + ": cannot find a free temporary name in '" +
                shownPath(dir) + "'");
}

bool writeAll(int fd, std::string_view data) {
    while (!data.empty()) {
        const ssize_t n = ::write(fd, data.data(), data.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        data.remove_prefix(std::size_t(n));
    }
    return true;
}

}  // namespace

std::string printable(std::string_view text, std::size_t max_chars) {
    return detail::shown(text, max_chars, false);
}

std::string regularFileProblem(const fs::path& path) {
    if (path.empty()) return "is an empty name";
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0)
        return S_ISREG(st.st_mode) ? std::string() : std::string("is ") + kindName(st.st_mode);
    const int e = errno;
    switch (e) {
        case ENOENT: {
            struct stat lst {};
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
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) rememberInput(st, path);
}

std::string readTextFile(const fs::path& path, std::size_t max_bytes, std::string_view what) {
    const std::string allowed = "; allowed: a regular file of at most " + sizeText(max_bytes);
    const std::string problem = regularFileProblem(path);
    if (!problem.empty())
        throw Error(std::string(what) + " " + problem + (problem.rfind("is a", 0) == 0 ? allowed : ""));
    // O_NONBLOCK: should the name have become a FIFO since the check, open() must not wait.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) throw Error(std::string(what) + " cannot be read: " + errnoText(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st {};
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
    if (used > max_bytes)
        throw Error(std::string(what) + " holds more than " + sizeText(max_bytes) + allowed);
    text.resize(used);
    rememberInput(st, path);
    return text;
}

void rememberInputFolder(const fs::path& dir, const OwnedName& may_write) {
    std::error_code ec;
    fs::path canonical = fs::canonical(dir, ec);
    if (ec) return;  // absent: nothing in it to protect
    std::lock_guard lock(g_inputs_mutex);
    g_input_folders.push_back({std::move(canonical), dir.string(), may_write});
}

void checkNotAnInput(const fs::path& path) {
    std::lock_guard lock(g_inputs_mutex);
    if (!g_input_folders.empty()) {
        std::error_code ec;
        const fs::path full = fs::weakly_canonical(fs::absolute(path, ec), ec);
        for (const InputFolder& f : g_input_folders) {
            if (ec) break;
            const fs::path rel = full.lexically_relative(f.canonical);
            if (rel.empty() || *rel.begin() == "..") continue;
            if (rel == "." || !f.may_write || !f.may_write(rel.generic_string()))
                throw Error("output: " + shownPath(path) + ": is '" + detail::shown(rel.generic_string(), 120, true) +
                            "' inside the input folder '" + shownPath(f.path) +
                            "' of this run, which this command reads; give another name");
        }
    }
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return;
    for (const InputFile& f : g_inputs)
        if (f.dev == st.st_dev && f.ino == st.st_ino)
            throw Error("output: " + shownPath(path) + ": is the input file '" + shownPath(f.path) +
                        "' of this run; give another name");
}

int openOwnFile(const fs::path& path, int flags, std::string_view what) {
    const std::string head = std::string(what) + " " + shownPath(path) + ": ";
    const std::string allowed = "; allowed: a regular file this command created";
    const auto refuse = [&](const struct stat& st) {
        if (!S_ISREG(st.st_mode)) throw Error(head + "is " + kindName(st.st_mode) + allowed);
        if (st.st_uid != ::geteuid())
            throw Error(head + "belongs to user id " + std::to_string(st.st_uid) + ", not this one" + allowed);
    };
    struct stat st {};
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
    struct stat st {};
    if (e != EEXIST || ::lstat(path.c_str(), &st) != 0) throw Error(head + "cannot create the folder: " + errnoText(e));
    if (!S_ISDIR(st.st_mode)) throw Error(head + "is " + kindName(st.st_mode) + "; allowed: a folder this command made");
    if (st.st_uid != ::geteuid())
        throw Error(head + "belongs to user id " + std::to_string(st.st_uid) +
                    ", not this one; allowed: a folder this command made");
}

// ---------------------------------------------------------------------------------
// Temporaries
// ---------------------------------------------------------------------------------

bool removeOwnFolder(int parent_fd, const std::string& name, const OwnedName& holds) {
    struct stat st {};
    if (::fstatat(parent_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISDIR(st.st_mode) ||
        st.st_uid != ::geteuid())
        return false;
    const int fd = ::openat(parent_fd, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) return false;
    struct stat opened {};
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
            struct stat est {};
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
        struct stat st {};
        if (::fstatat(dirfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0 || st.st_uid != ::geteuid())
            continue;
        removeEntry(dirfd, name, folder_holds);
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
        name_ = createUnique([&](const std::string& name) {
            fd = ::openat(dirfd_, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
            return fd >= 0;
        }, destination_, dir);
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
    const std::string base = destination_.filename().string();
    for (int attempt = 0; attempt < 3; ++attempt) {
        struct stat st {};
        if (::fstatat(dirfd_, base.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
            if (!S_ISREG(st.st_mode))
                fail(std::string("is ") + kindName(st.st_mode) + "; refusing to replace it (only a regular "
                     "file is replaced)", 0);
            try {
                checkNotAnInput(destination_);
            } catch (const Error&) {
                discard();
                throw;
            }
            if (::renameat(dirfd_, name_.c_str(), dirfd_, base.c_str()) != 0)
                fail("cannot rename the temporary file into place", errno);
        } else if (errno == ENOENT) {
            // Absent now: make sure nothing (a symlink, a device) appears under the name
            // between the check and the rename.
            if (::renameat2(dirfd_, name_.c_str(), dirfd_, base.c_str(), RENAME_NOREPLACE) != 0) {
                if (errno == EEXIST) continue;
                if (errno != EINVAL && errno != ENOSYS)
                    fail("cannot rename the temporary file into place", errno);
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
    const std::string where = "output: " + std::string(what) + ": cannot create a scratch file in '" +
                              shownPath(dir) + "': ";
    int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
        // No O_TMPFILE here: an exclusive random name, unlinked before any data goes in.
        removeStaleTemporaries(dir);
        const int dirfd = openFolder(dir, fs::path(what));
        try {
            const std::string name = createUnique([&](const std::string& n) {
                fd = ::openat(dirfd, n.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
                return fd >= 0;
            }, fs::path(what), dir);
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

// ---------------------------------------------------------------------------------
// Output folders
// ---------------------------------------------------------------------------------

namespace {

// The folder to replace (links to a folder resolved), after the checks of
// checkOutputFolder. Missing parent folders are made when `make_parents`, else the
// nearest existing one must be a writable folder.
fs::path resolveOutputFolder(const fs::path& dir, const OwnedName& ours, bool make_parents) {
    const std::string out = "output: " + shownPath(dir) + ": ";
    if (dir.empty()) throw Error("output: the output folder name is empty; give a folder name");
    fs::path target = dir.lexically_normal();
    if (target.filename().empty()) target = target.parent_path();
    const std::string base = target.filename().string();
    if (base.empty() || base == "." || base == "..")
        throw Error(out + "cannot replace this folder as a whole; give a sub-folder for the results");
    struct stat st {};
    if (::lstat(target.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
        if (::stat(target.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
            throw Error(out + "is a symbolic link to something that is not a folder");
        std::error_code ec;
        target = fs::canonical(target, ec);
        if (ec) throw Error(out + "cannot resolve the symbolic link: " + ec.message());
        return resolveOutputFolder(target, ours, make_parents);
    }
    fs::path parent = target.parent_path();
    if (parent.empty()) parent = ".";
    struct stat pst {};
    if (make_parents && ::stat(parent.c_str(), &pst) != 0) {
        std::error_code ec;
        fs::create_directories(parent, ec);
        if (ec) throw Error(out + "cannot create the folder '" + shownPath(parent) + "': " + ec.message());
    }
    while (!make_parents && ::stat(parent.c_str(), &pst) != 0 && errno == ENOENT && parent.has_relative_path())
        parent = parent.parent_path().empty() ? fs::path(".") : parent.parent_path();  // made later
    if (::stat(parent.c_str(), &pst) != 0)
        throw Error(out + "folder '" + shownPath(parent) + "' does not exist");
    if (!S_ISDIR(pst.st_mode)) throw Error(out + "'" + shownPath(parent) + "' is not a directory");
    if (::access(parent.c_str(), W_OK) != 0)
        throw Error(out + "folder '" + shownPath(parent) + "' is not writable");
    if (::lstat(target.c_str(), &st) != 0) return target;  // absent: created by the swap
    if (!S_ISDIR(st.st_mode)) throw Error(out + "is " + kindName(st.st_mode) + ", not a folder");
    std::error_code ec;
    for (fs::directory_iterator it(target, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (!ours(name))
            throw Error(out + "holds '" + detail::shown(name, 80, true) + "', which this command does not "
                        "write; refusing to replace the folder (give a new or empty folder)");
    }
    if (ec) throw Error(out + "cannot list the folder: " + ec.message());
    return target;
}

}  // namespace

void checkOutputFolder(const fs::path& dir, const OwnedName& ours) { resolveOutputFolder(dir, ours, false); }

void writeFolderAtomic(const fs::path& dir, const std::vector<std::pair<std::string, std::string>>& files,
                       const OwnedName& ours) {
    const fs::path target = resolveOutputFolder(dir, ours, true);
    fs::path parent = target.parent_path();
    if (parent.empty()) parent = ".";
    const std::string base = target.filename().string();
    removeStaleTemporaries(parent, ours);
    const int pfd = openFolder(parent, dir);
    std::string tmp;
    int tfd = -1, tslot = -1;
    std::vector<std::pair<std::string, int>> made;  // file name, cleanup slot
    auto cleanUp = [&] {
        for (const auto& [name, slot] : made) {
            ::unlinkat(tfd, name.c_str(), 0);
            detail::unregisterTemporary(slot);
        }
        if (tfd >= 0) ::close(tfd);
        if (!tmp.empty()) removeEntry(pfd, tmp, ours);
        detail::unregisterTemporary(tslot);
        ::close(pfd);
    };
    try {
        tmp = createUnique([&](const std::string& n) { return ::mkdirat(pfd, n.c_str(), 0777) == 0; }, dir, parent);
        tslot = detail::registerTemporary(pfd, tmp.c_str(), true);
        tfd = ::openat(pfd, tmp.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (tfd < 0)
            throw Error("output: " + shownPath(dir) + ": cannot open the temporary folder: " + errnoText(errno));
        for (const auto& [name, content] : files) {
            const int fd = ::openat(tfd, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
            if (fd < 0)
                throw Error("output: " + shownPath(dir / name) + ": cannot create: " + errnoText(errno));
            made.emplace_back(name, detail::registerTemporary(tfd, name.c_str(), false));
            const bool wrote = writeAll(fd, content);
            const int write_errno = errno;
            const bool closed = ::close(fd) == 0;
            if (!wrote || !closed)
                throw Error("output: " + shownPath(dir / name) + ": write failed: " +
                            errnoText(wrote ? errno : write_errno));
        }
        // The swap. The folder may have changed since the check: look again.
        resolveOutputFolder(target, ours, false);
        for (const auto& [name, slot] : made) detail::unregisterTemporary(slot);
        made.clear();
        struct stat st {};
        bool swapped_old = false;
        if (::fstatat(pfd, base.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
            if (::renameat2(pfd, tmp.c_str(), pfd, base.c_str(), RENAME_NOREPLACE) != 0 &&
                ((errno != EINVAL && errno != ENOSYS) || ::renameat(pfd, tmp.c_str(), pfd, base.c_str()) != 0))
                throw Error("output: " + shownPath(dir) + ": cannot move the new folder into place: " +
                            errnoText(errno));
        } else if (::renameat2(pfd, tmp.c_str(), pfd, base.c_str(), RENAME_EXCHANGE) == 0) {
            swapped_old = true;  // the previous folder now has the temporary name
        } else if (errno == EINVAL || errno == ENOSYS) {
            // No atomic exchange here: the old folder steps aside, then the new one moves in.
            const std::string old = createUnique([&](const std::string& n) {
                struct stat probe {};
                if (::fstatat(pfd, n.c_str(), &probe, AT_SYMLINK_NOFOLLOW) == 0) {
                    errno = EEXIST;
                    return false;
                }
                return ::renameat(pfd, base.c_str(), pfd, n.c_str()) == 0;
            }, dir, parent);
            if (::renameat(pfd, tmp.c_str(), pfd, base.c_str()) != 0) {
                const int e = errno;
                ::renameat(pfd, old.c_str(), pfd, base.c_str());
                throw Error("output: " + shownPath(dir) + ": cannot move the new folder into place: " + errnoText(e));
            }
            tmp = old;
            swapped_old = true;
        } else {
            throw Error("output: " + shownPath(dir) + ": cannot swap the new folder into place: " + errnoText(errno));
        }
        detail::unregisterTemporary(tslot);
        tslot = -1;
        ::close(tfd);
        tfd = -1;
        if (swapped_old) removeReplacedFolder(tmp, parent);
        ::close(pfd);
    } catch (...) {
        cleanUp();
        throw;
    }
}

}  // namespace engine
