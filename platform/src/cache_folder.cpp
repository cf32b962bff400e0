// cache_folder: the user's cache folder, keys from a file's identity, and the size bound
// (contract in platform/cache_folder.hpp). Names inside the folder go through *at() calls
// on the open folder with AT_SYMLINK_NOFOLLOW, so nothing is followed out of it.
#include <core/error.hpp>
#include <platform/cache_folder.hpp>

#include "file_ops.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <tuple>

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace platform {

using core::Error;
namespace fs = std::filesystem;

fs::path userCacheFolder(std::string_view name, std::string_view what) {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg != nullptr && xdg[0] == '/') return fs::path(xdg) / std::string(name);
    const char* home = std::getenv("HOME");
    if (home != nullptr && home[0] == '/') return fs::path(home) / ".cache" / std::string(name);
    throw Error(std::string(what) + ": no cache folder: neither XDG_CACHE_HOME nor HOME is an absolute path");
}

void makeCacheFolder(const fs::path& dir, std::string_view what) {
    const std::string head = std::string(what) + " " + shownPath(dir) + ": ";
    struct stat st{};
    if (::lstat(dir.c_str(), &st) != 0) {
        if (errno != ENOENT) throw Error(head + "cannot stat the folder: " + errnoText(errno));
        // Missing parents first (0700: the XDG rule for folders it makes), then the folder.
        fs::path partial;
        for (const fs::path& part : dir) {
            partial /= part;
            if (partial == dir) break;
            if (::mkdir(partial.c_str(), 0700) != 0 && errno != EEXIST)
                throw Error(head + "cannot create the folder " + shownPath(partial) + ": " + errnoText(errno));
        }
        if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST)
            throw Error(head + "cannot create the folder: " + errnoText(errno));
        if (::lstat(dir.c_str(), &st) != 0) throw Error(head + "cannot stat the folder: " + errnoText(errno));
    }
    if (!S_ISDIR(st.st_mode)) throw Error(head + "is " + kindName(st.st_mode) + "; allowed: a folder of this user");
    if (st.st_uid != ::geteuid())
        throw Error(head + "belongs to user id " + std::to_string(st.st_uid) +
                    ", not this one; allowed: a folder of this user");
}

FileIdentity fileIdentity(const fs::path& path, std::string_view what) {
    struct stat st{};
    if (::stat(path.c_str(), &st) != 0)
        throw Error(std::string(what) + " " + shownPath(path) + ": cannot stat: " + errnoText(errno));
    FileIdentity id;
    id.device = st.st_dev;
    id.inode = st.st_ino;
    id.size_bytes = std::uint64_t(st.st_size);
    id.mtime_ns = std::int64_t(st.st_mtim.tv_sec) * 1000000000 + std::int64_t(st.st_mtim.tv_nsec);
    std::error_code ec;
    id.canonical = fs::canonical(path, ec);
    if (ec) throw Error(std::string(what) + " " + shownPath(path) + ": cannot resolve the path: " + ec.message());
    return id;
}

namespace {

std::uint64_t fnv1a(std::string_view text, std::uint64_t basis) {
    std::uint64_t h = basis;
    for (const char c : text) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ull;
    }
    return h;
}

}  // namespace

std::string identityKey(const FileIdentity& id, std::string_view salt) {
    // Every field as text, separated so that no two identities give the same text.
    std::string text(salt);
    text += '\n' + std::to_string(std::uint64_t(id.device)) + '\n' + std::to_string(std::uint64_t(id.inode)) + '\n' +
            std::to_string(id.size_bytes) + '\n' + std::to_string(id.mtime_ns) + '\n' + id.canonical.native();
    char hex[33];
    std::snprintf(hex, sizeof hex, "%016llx%016llx",
                  static_cast<unsigned long long>(fnv1a(text, 0xcbf29ce484222325ull)),
                  static_cast<unsigned long long>(fnv1a(text, 0x84222325cbf29ce4ull)));
    return hex;
}

bool useCachedFile(const fs::path& path, std::string_view what) {
    const std::string head = std::string(what) + " " + shownPath(path) + ": ";
    struct stat st{};
    if (::lstat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) return false;
        throw Error(head + "cannot stat: " + errnoText(errno));
    }
    if (!S_ISREG(st.st_mode) || st.st_uid != ::geteuid())
        throw Error(head + "is " + (S_ISREG(st.st_mode) ? "another user's file" : kindName(st.st_mode)) +
                    "; allowed: a regular file this command created");
    const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        if (errno == ENOENT) return false;  // removed meanwhile by another run's bound
        throw Error(head + "cannot open: " + errnoText(errno));
    }
    struct stat fst{};
    const bool regular = ::fstat(fd, &fst) == 0 && S_ISREG(fst.st_mode) && fst.st_uid == ::geteuid();
    if (regular) ::futimens(fd, nullptr);  // used now: the bound removes it last
    ::close(fd);
    if (!regular)
        throw Error(head + "is not a regular file of this user; allowed: a regular file this command created");
    return true;
}

std::vector<std::string> boundCacheFolder(const fs::path& dir, const OwnedName& ours, std::uint64_t max_bytes,
                                          const std::string& keep) {
    std::vector<std::string> removed;
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (dfd < 0) return removed;
    struct Entry {
        std::int64_t mtime_ns;
        std::string name;
        std::uint64_t bytes;
    };
    std::vector<Entry> entries;
    std::uint64_t total = 0;
    if (DIR* d = ::fdopendir(::dup(dfd))) {
        while (const dirent* e = ::readdir(d)) {
            const std::string name = e->d_name;
            if (name == "." || name == ".." || !ours(name)) continue;
            struct stat st{};
            if (::fstatat(dfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
            if (!S_ISREG(st.st_mode) || st.st_uid != ::geteuid()) continue;
            total += std::uint64_t(st.st_size);
            if (name == keep) continue;
            entries.push_back(
                {std::int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec, name, std::uint64_t(st.st_size)});
        }
        ::closedir(d);
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        return std::tie(a.mtime_ns, a.name) < std::tie(b.mtime_ns, b.name);
    });
    for (const Entry& e : entries) {
        if (total <= max_bytes) break;
        // Checked again right before: a name swapped for a link or a folder stays.
        struct stat st{};
        if (::fstatat(dfd, e.name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode) ||
            st.st_uid != ::geteuid())
            continue;
        if (::unlinkat(dfd, e.name.c_str(), 0) == 0) {
            total -= std::min(total, e.bytes);
            removed.push_back(e.name);
        }
    }
    ::close(dfd);
    return removed;
}

}  // namespace platform
