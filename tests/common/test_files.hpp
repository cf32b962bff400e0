// tests/common/test_files.hpp: scratch folders and file reading for tests.
#pragma once
#include <unistd.h>

#include <core/error.hpp>

#include <filesystem>
#include <functional>
#include <fstream>
#include <iterator>
#include <string>

namespace test_support {

/// A fresh folder under the system temp dir, "ladarvr_test_<name>_<pid>", removed on
/// destruction (one per test process, so parallel ctest entries never share one).
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& name)
        : path(std::filesystem::temp_directory_path() / ("ladarvr_test_" + name + "_" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    /// How many entries the folder holds (temporary files left behind count).
    std::size_t entries() const {
        return std::size_t(
            std::distance(std::filesystem::directory_iterator(path), std::filesystem::directory_iterator()));
    }
    /// Writes `text` to path/name and returns that path.
    std::filesystem::path write(const std::string& name, const std::string& text) const {
        std::ofstream(path / name) << text;
        return path / name;
    }
};

/// The whole file as bytes; empty if it cannot be read.
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

/// The message of the core::Error that `f` throws, or "(no error)".
inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const core::Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace test_support
