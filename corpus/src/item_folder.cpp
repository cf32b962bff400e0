// corpus: the temporary item folder and its move into place.
#include "item_folder.hpp"

#include <corpus/item.hpp>

#include <engine/atomic_file.hpp>
#include <engine/cleanup.hpp>
#include <engine/error.hpp>
#include <engine/safe_file.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace corpus::detail {

namespace fs = std::filesystem;

namespace {
std::string shown(const fs::path& p) { return engine::printable(p.string()); }
}  // namespace

ItemFolder::ItemFolder(const fs::path& items, const std::string& id)
    : items_(items), final_(items / id), id_(id) {
    temp_name_ = std::string(engine::kTempPrefix) + std::to_string(::getpid()) + "-" + id;
    temp_ = items / temp_name_;
    // DIR/items itself, never a link in its place.
    items_fd_ = ::open(items.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (items_fd_ < 0) throw engine::Error("output: " + shown(items) + ": cannot open the folder: " + std::strerror(errno));
    if (::mkdirat(items_fd_, temp_name_.c_str(), 0777) != 0) {
        const int e = errno;
        ::close(items_fd_);
        throw engine::Error("output: " + shown(temp_) + ": cannot create the item's folder: " + std::strerror(e));
    }
    slots_.push_back(engine::detail::registerTemporary(items_fd_, temp_name_.c_str(), true));
    temp_fd_ = ::openat(items_fd_, temp_name_.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (temp_fd_ < 0) {
        const int e = errno;
        ::unlinkat(items_fd_, temp_name_.c_str(), AT_REMOVEDIR);
        engine::detail::unregisterTemporary(slots_.back());
        ::close(items_fd_);
        throw engine::Error("output: " + shown(temp_) + ": cannot open the item's folder: " + std::strerror(e));
    }
}

ItemFolder::~ItemFolder() {
    for (int slot : slots_) engine::detail::unregisterTemporary(slot);
    if (!committed_) engine::removeOwnFolder(items_fd_, temp_name_, isItemFile);
    if (temp_fd_ >= 0) ::close(temp_fd_);
    if (items_fd_ >= 0) ::close(items_fd_);
}

fs::path ItemFolder::path(const std::string& name) const { return temp_ / name; }

void ItemFolder::track(const std::string& name) {
    // Registered after its own temporary was renamed: a signal now removes it too, so
    // that the folder is empty and its registration removes it as well.
    const int slot = engine::detail::registerTemporary(temp_fd_, name.c_str(), false);
    slots_.insert(slots_.begin(), slot);  // files before the folder
}

void ItemFolder::writeText(const std::string& name, std::string_view content) {
    engine::writeFileAtomic(temp_ / name, content);
    track(name);
}

void ItemFolder::writeCloud(const std::string& name, const engine::PointCloud& cloud, engine::CloudFormat format) {
    engine::writeCloud(temp_ / name, cloud, format);
    track(name);
}

void ItemFolder::commit() {
    const std::string base = final_.filename().string();
    struct stat st {};
    if (::fstatat(items_fd_, base.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
        // A folder a killed run moved into place before its manifest line: swap, then remove it.
        if (!S_ISDIR(st.st_mode))
            throw engine::Error("output: " + shown(final_) + ": exists and is not a folder; allowed: a folder this "
                                "command made, or nothing");
        if (::renameat2(items_fd_, temp_name_.c_str(), items_fd_, base.c_str(), RENAME_EXCHANGE) != 0)
            throw engine::Error("output: " + shown(final_) + ": cannot move the new item into place: " +
                                std::strerror(errno));
        committed_ = true;
        // The old folder, now under the temporary name; left (hidden) if it holds
        // anything an item does not.
        engine::removeOwnFolder(items_fd_, temp_name_, isItemFile);
        return;
    }
    if (::renameat2(items_fd_, temp_name_.c_str(), items_fd_, base.c_str(), RENAME_NOREPLACE) != 0)
        throw engine::Error("output: " + shown(final_) + ": cannot move the item into place: " + std::strerror(errno));
    committed_ = true;
}

}  // namespace corpus::detail
