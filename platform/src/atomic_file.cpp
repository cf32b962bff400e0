// atomic_file: every output of the project goes through a temporary in the same folder
// and a rename, so a failed or interrupted run never leaves a truncated file behind.
#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>
#include <platform/safe_file.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include <sys/stat.h>
#include <unistd.h>

namespace platform {

using core::Error;
using core::printable;

void checkWritableDestination(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    if (path.empty()) throw Error("output: the output path is empty; give a file name");
    checkPathLength(path, "output");
    const std::string shown = printable(path.string(), 400);
    fs::path dir = path.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::exists(dir, ec))
        throw Error("output: " + shown + ": directory '" + printable(dir.string(), 400) + "' does not exist");
    if (!fs::is_directory(dir, ec))
        throw Error("output: " + shown + ": '" + printable(dir.string(), 400) + "' is not a directory");
    if (::access(dir.c_str(), W_OK) != 0)
        throw Error("output: " + shown + ": directory '" + printable(dir.string(), 400) + "' is not writable");
    struct stat st{};
    if (::lstat(path.c_str(), &st) == 0) {
        if (S_ISDIR(st.st_mode)) throw Error("output: " + shown + ": is a directory; give a file name");
        if (S_ISLNK(st.st_mode))
            throw Error("output: " + shown +
                        ": is a symbolic link; refusing to replace it (give the path of "
                        "a regular file or a new name)");
        if (!S_ISREG(st.st_mode)) {
            std::string problem = regularFileProblem(path);
            throw Error("output: " + shown + ": " + problem +
                        "; refusing to replace it (only a regular "
                        "file is replaced)");
        }
    }
}

void checkWritableDestination(const std::filesystem::path& path, const InputSet& inputs) {
    checkWritableDestination(path);
    inputs.checkNotAnInput(path);
}

void writeFileAtomic(const std::filesystem::path& path, std::string_view content) {
    checkWritableDestination(path);
    TempFile tmp(path);
    if (std::fwrite(content.data(), 1, content.size(), tmp.file()) != content.size()) {
        const int write_errno = errno;
        tmp.discard();
        throw Error("output: " + printable(path.string(), 400) + ": write failed: " + std::strerror(write_errno));
    }
    tmp.commit();
}

}  // namespace platform
