// output_folder: folders written as a whole (contract in platform/output_folder.hpp). Every
// step goes through *at() calls relative to the open parent and temporary folders, so a
// folder swapped for a symlink half-way cannot redirect a write.
#include <core/error.hpp>
#include <platform/cleanup.hpp>
#include <platform/output_folder.hpp>
#include <platform/safe_file.hpp>

#include "file_ops.hpp"

#include <cerrno>
#include <system_error>

#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

namespace platform {
namespace fs = std::filesystem;
using core::Error;

namespace {

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

std::string foreignEntry(const fs::path& path, const std::string& name, const OwnedName& ours);

// The folder to replace, after the checks of
// checkOutputFolder. Missing parent folders are made when `make_parents`, else the
// nearest existing one must be a writable folder.
fs::path resolveOutputFolder(const fs::path& dir, const OwnedName& ours, bool make_parents) {
    const std::string out = "output: " + shownPath(dir) + ": ";
    checkPathLength(dir, "output");
    if (dir.empty()) throw Error("output: the output folder name is empty; give a folder name");
    fs::path target = dir.lexically_normal();
    if (target.filename().empty()) target = target.parent_path();
    const std::string base = target.filename().string();
    if (base.empty() || base == "." || base == "..")
        throw Error(out + "cannot replace this folder as a whole; give a sub-folder for the results");
    struct stat st{};
    // A link is never followed: what it points to is not ours to replace.
    if (::lstat(target.c_str(), &st) == 0 && S_ISLNK(st.st_mode))
        throw Error(out +
                    "is a symbolic link; refusing to follow it (allowed: a new folder, or a folder this "
                    "command wrote, given by its own path)");
    fs::path parent = target.parent_path();
    if (parent.empty()) parent = ".";
    struct stat pst{};
    if (make_parents && ::stat(parent.c_str(), &pst) != 0) {
        std::error_code ec;
        fs::create_directories(parent, ec);
        if (ec) throw Error(out + "cannot create the folder '" + shownPath(parent) + "': " + ec.message());
    }
    while (!make_parents && ::stat(parent.c_str(), &pst) != 0 && errno == ENOENT && parent.has_relative_path())
        parent = parent.parent_path().empty() ? fs::path(".") : parent.parent_path();  // made later
    if (::stat(parent.c_str(), &pst) != 0) throw Error(out + "folder '" + shownPath(parent) + "' does not exist");
    if (!S_ISDIR(pst.st_mode)) throw Error(out + "'" + shownPath(parent) + "' is not a directory");
    if (::access(parent.c_str(), W_OK) != 0) throw Error(out + "folder '" + shownPath(parent) + "' is not writable");
    if (::lstat(target.c_str(), &st) != 0) return target;  // absent: created by the swap
    if (!S_ISDIR(st.st_mode)) throw Error(out + "is " + kindName(st.st_mode) + ", not a folder");
    std::error_code ec;
    for (fs::directory_iterator it(target, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (const std::string why = foreignEntry(it->path(), name, ours); !why.empty())
            throw Error(out + "holds '" + core::printable(name, 80, true) + "', " + why +
                        "; refusing to replace the folder (give a new or empty folder)");
    }
    if (ec) throw Error(out + "cannot list the folder: " + ec.message());
    return target;
}

// Why the entry `name` (at `path`) of a folder to replace is not one of the files this
// command wrote there, in words that follow "holds 'NAME', "; empty when it is one. Only
// regular files of this user with a name `ours` accepts pass: the same entries that
// removeOwnFolder removes, so the previous folder, once swapped out, is always removed
// and never left hidden beside the new one with someone's things inside.
std::string foreignEntry(const fs::path& path, const std::string& name, const OwnedName& ours) {
    if (!ours(name)) return "which this command does not write";
    struct stat st{};
    if (::lstat(path.c_str(), &st) != 0) return "which cannot be examined: " + errnoText(errno);
    if (!S_ISREG(st.st_mode))
        return std::string("which is ") + kindName(st.st_mode) + ", not a file this command writes";
    if (st.st_uid != ::geteuid()) return "a file of another user, not one this command wrote";
    return {};
}

}  // namespace

void checkOutputFolder(const fs::path& dir, const OwnedName& ours) { resolveOutputFolder(dir, ours, false); }

AtomicFolder::AtomicFolder(fs::path dir, OwnedName ours) : dir_(std::move(dir)), ours_(std::move(ours)) {
    target_ = resolveOutputFolder(dir_, ours_, true);
    parent_ = target_.parent_path();
    if (parent_.empty()) parent_ = ".";
    parent_fd_ = openFolder(parent_, dir_);
    try {
        temp_name_ = createUnique([&](const std::string& n) { return ::mkdirat(parent_fd_, n.c_str(), 0777) == 0; },
                                  dir_, parent_);
        temp_slot_ = detail::registerTemporary(parent_fd_, temp_name_.c_str(), true);
        temp_fd_ = ::openat(parent_fd_, temp_name_.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (temp_fd_ < 0)
            throw Error("output: " + shownPath(dir_) + ": cannot open the temporary folder: " + errnoText(errno));
    } catch (...) {
        removeTemporary();
        throw;
    }
}

AtomicFolder::~AtomicFolder() { removeTemporary(); }

void AtomicFolder::removeTemporary() noexcept {
    for (const auto& [name, slot] : files_) {
        if (!committed_) ::unlinkat(temp_fd_, name.c_str(), 0);
        detail::unregisterTemporary(slot);
    }
    files_.clear();
    if (temp_fd_ >= 0) ::close(temp_fd_);
    temp_fd_ = -1;
    if (!committed_ && !temp_name_.empty()) removeOwnFolder(parent_fd_, temp_name_, ours_);
    temp_name_.clear();
    detail::unregisterTemporary(temp_slot_);
    temp_slot_ = -1;
    if (parent_fd_ >= 0) ::close(parent_fd_);
    parent_fd_ = -1;
}

fs::path AtomicFolder::path(const std::string& name) const { return parent_ / temp_name_ / name; }

void AtomicFolder::writeFile(const std::string& name, std::string_view content) {
    const int fd = ::openat(temp_fd_, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0) throw Error("output: " + shownPath(dir_ / name) + ": cannot create: " + errnoText(errno));
    adopt(name);
    const bool wrote = writeAll(fd, content);
    const int write_errno = errno;
    const bool closed = ::close(fd) == 0;
    if (!wrote || !closed)
        throw Error("output: " + shownPath(dir_ / name) + ": write failed: " + errnoText(wrote ? errno : write_errno));
}

void AtomicFolder::adopt(const std::string& name) {
    files_.emplace_back(name, detail::registerTemporary(temp_fd_, name.c_str(), false));
}

void AtomicFolder::commit() {
    if (committed_ || temp_fd_ < 0) throw Error("output: " + shownPath(dir_) + ": commit called twice");
    // The folder may have changed since the check: look again.
    resolveOutputFolder(target_, ours_, false);
    // From the swap on, the files are the output: a signal must not remove them.
    for (const auto& [name, slot] : files_) detail::unregisterTemporary(slot);
    files_.clear();
    const int pfd = parent_fd_;
    const std::string base = target_.filename().string();
    std::string tmp = temp_name_;
    struct stat st{};
    bool swapped_old = false;
    if (::fstatat(pfd, base.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
        if (::renameat2(pfd, tmp.c_str(), pfd, base.c_str(), RENAME_NOREPLACE) != 0 &&
            ((errno != EINVAL && errno != ENOSYS) || ::renameat(pfd, tmp.c_str(), pfd, base.c_str()) != 0))
            throw Error("output: " + shownPath(dir_) + ": cannot move the new folder into place: " + errnoText(errno));
    } else if (::renameat2(pfd, tmp.c_str(), pfd, base.c_str(), RENAME_EXCHANGE) == 0) {
        swapped_old = true;  // the previous folder now has the temporary name
    } else if (errno == EINVAL || errno == ENOSYS) {
        // No atomic exchange here: the old folder steps aside, then the new one moves in.
        const std::string old = createUnique(
            [&](const std::string& n) {
                struct stat probe{};
                if (::fstatat(pfd, n.c_str(), &probe, AT_SYMLINK_NOFOLLOW) == 0) {
                    errno = EEXIST;
                    return false;
                }
                return ::renameat(pfd, base.c_str(), pfd, n.c_str()) == 0;
            },
            dir_, parent_);
        if (::renameat(pfd, tmp.c_str(), pfd, base.c_str()) != 0) {
            const int e = errno;
            ::renameat(pfd, old.c_str(), pfd, base.c_str());
            throw Error("output: " + shownPath(dir_) + ": cannot move the new folder into place: " + errnoText(e));
        }
        tmp = old;
        swapped_old = true;
    } else {
        throw Error("output: " + shownPath(dir_) + ": cannot swap the new folder into place: " + errnoText(errno));
    }
    // The previous folder, now under the name `tmp`, goes. It was checked just before the
    // swap; should something not ours have slipped into it since, it moves back into place
    // and the new folder is dropped, rather than hiding that thing under a temporary name.
    if (swapped_old && !removeOwnFolder(pfd, tmp, ours_)) {
        const bool back = tmp == temp_name_ ? ::renameat2(pfd, tmp.c_str(), pfd, base.c_str(), RENAME_EXCHANGE) == 0
                                            : ::renameat(pfd, base.c_str(), pfd, temp_name_.c_str()) == 0 &&
                                                  ::renameat(pfd, tmp.c_str(), pfd, base.c_str()) == 0;
        if (back)
            throw Error("output: " + shownPath(dir_) +
                        ": the folder changed while the new one was written (it holds something this command "
                        "does not write); left as it was");
    }
    committed_ = true;
    removeTemporary();
}

void writeFolderAtomic(const fs::path& dir, const std::vector<std::pair<std::string, std::string>>& files,
                       const OwnedName& ours) {
    {
        // The temporaries of dead runs beside the folder go first.
        fs::path parent = resolveOutputFolder(dir, ours, true).parent_path();
        removeStaleTemporaries(parent.empty() ? fs::path(".") : parent, ours);
    }
    AtomicFolder folder(dir, ours);
    for (const auto& [name, content] : files) folder.writeFile(name, content);
    folder.commit();
}

}  // namespace platform
