// atomic_file: every output of the project goes through a temporary sibling and a
// rename, so a failed or interrupted run never leaves a truncated file behind.
#include <engine/atomic_file.hpp>
#include <engine/error.hpp>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include <unistd.h>

namespace engine {

std::filesystem::path tempSibling(const std::filesystem::path& path) {
    return std::filesystem::path(path.string() + ".tmp-" + std::to_string(::getpid()));
}

void checkWritableDestination(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    if (path.empty()) throw Error("output: the output path is empty; give a file name");
    fs::path dir = path.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::exists(dir, ec))
        throw Error("output: " + path.string() + ": directory '" + dir.string() +
                    "' does not exist");
    if (!fs::is_directory(dir, ec))
        throw Error("output: " + path.string() + ": '" + dir.string() + "' is not a directory");
    if (::access(dir.c_str(), W_OK) != 0)
        throw Error("output: " + path.string() + ": directory '" + dir.string() +
                    "' is not writable");
    if (fs::is_directory(path, ec))
        throw Error("output: " + path.string() + ": is a directory; give a file name");
}

void writeFileAtomic(const std::filesystem::path& path, std::string_view content) {
    checkWritableDestination(path);
    const std::filesystem::path tmp = tempSibling(path);
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f)
        throw Error("output: " + path.string() + ": cannot create '" + tmp.string() +
                    "': " + std::strerror(errno));
    const bool wrote = std::fwrite(content.data(), 1, content.size(), f) == content.size();
    const int write_errno = errno;
    const bool closed = std::fclose(f) == 0;
    if (!wrote || !closed) {
        std::remove(tmp.c_str());
        throw Error("output: " + path.string() + ": write failed: " +
                    std::strerror(wrote ? errno : write_errno));
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int rename_errno = errno;
        std::remove(tmp.c_str());
        throw Error("output: " + path.string() + ": cannot rename the temporary file into place: " +
                    std::strerror(rename_errno));
    }
}

}  // namespace engine
