// platform/src/input_set.cpp: the inputs of one run (platform/input_set.hpp), files by
// device and inode, folders by their canonical path.
#include <platform/input_set.hpp>

#include <core/error.hpp>

#include "file_ops.hpp"

#include <system_error>
#include <utility>

#include <sys/stat.h>

namespace platform {

namespace fs = std::filesystem;

void InputSet::addFile(const fs::path& path) {
    struct stat st{};
    if (::stat(path.c_str(), &st) != 0) return;
    for (const File& f : files_)
        if (f.dev == std::uint64_t(st.st_dev) && f.ino == std::uint64_t(st.st_ino)) return;
    files_.push_back({std::uint64_t(st.st_dev), std::uint64_t(st.st_ino), path.string()});
}

void InputSet::addFolder(const fs::path& dir, OwnedName may_write) {
    std::error_code ec;
    fs::path canonical = fs::canonical(dir, ec);
    if (ec) return;  // absent: nothing in it to protect
    folders_.push_back({std::move(canonical), dir.string(), std::move(may_write)});
}

void InputSet::checkNotAnInput(const fs::path& output) const {
    if (!folders_.empty()) {
        std::error_code ec;
        const fs::path full = fs::weakly_canonical(fs::absolute(output, ec), ec);
        for (const Folder& f : folders_) {
            if (ec) break;
            const fs::path rel = full.lexically_relative(f.canonical);
            if (rel.empty() || *rel.begin() == "..") continue;
            if (rel == "." || !f.may_write || !f.may_write(rel.generic_string()))
                throw core::Error("output: " + shownPath(output) + ": is '" +
                                  core::printable(rel.generic_string(), 120, true) + "' inside the input folder '" +
                                  shownPath(f.path) + "' of this run, which this command reads; give another name");
        }
    }
    struct stat st{};
    if (::stat(output.c_str(), &st) != 0) return;
    for (const File& f : files_)
        if (f.dev == std::uint64_t(st.st_dev) && f.ino == std::uint64_t(st.st_ino))
            throw core::Error("output: " + shownPath(output) + ": is the input file '" + shownPath(f.path) +
                              "' of this run; give another name");
}

}  // namespace platform
