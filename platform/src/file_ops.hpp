// platform/src/file_ops.hpp (internal): what safe_file.cpp and output_folder.cpp share:
// names of files in messages, and the *at() steps on an open folder.
#pragma once
#include <core/error.hpp>

#include <cerrno>
#include <filesystem>
#include <string>

#include <sys/types.h>

namespace platform {

/// A path fit for a message (UTF-8 kept, at most 400 characters).
std::string shownPath(const std::filesystem::path& p);
/// strerror(e).
std::string errnoText(int e);
/// "a directory", "a FIFO (named pipe)", ... for a file's mode.
const char* kindName(mode_t mode);
/// ".ladarvr-tmp-<pid>-" followed by six random letters and digits.
std::string randomTempName();
/// Opens `dir` (O_DIRECTORY). Throws Error("output: <for_output>: cannot open the folder ...").
int openFolder(const std::filesystem::path& dir, const std::filesystem::path& for_output);

/// Creates a fresh temporary name with `make(name)` (a mkdirat or openat with O_EXCL in
/// the folder `dir`), retrying on EEXIST. Throws Error("output: <for_output>: ...").
template <class Make>
std::string createUnique(Make make, const std::filesystem::path& for_output, const std::filesystem::path& dir) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = randomTempName();
        if (make(name)) return name;
        if (errno != EEXIST)
            throw core::Error("output: " + shownPath(for_output) + ": cannot create a temporary in '" + shownPath(dir) +
                              "': " + errnoText(errno));
    }
    throw core::Error("output: " + shownPath(for_output) + ": cannot find a free temporary name in '" + shownPath(dir) +
                      "'");
}

}  // namespace platform
