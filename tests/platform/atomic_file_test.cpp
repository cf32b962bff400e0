// Atomic writes: temp sibling + rename, destination checks, nothing partial left behind.
#include <test_files.hpp>
#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <doctest/doctest.h>

#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using test_support::slurp;
using test_support::TempDir;

}  // namespace

TEST_CASE("atomic_file: the temporary is a hidden .ladarvr-tmp-<pid>-XXXXXX beside the destination") {
    TempDir dir("tempname");
    platform::TempFile t(dir.path / "cloud.pcd");
    const std::string name = t.path().filename().string();
    const std::string head = ".ladarvr-tmp-" + std::to_string(::getpid()) + "-";
    CHECK(t.path().parent_path() == dir.path);
    REQUIRE(name.size() == head.size() + 6);
    CHECK(name.compare(0, head.size(), head) == 0);
    CHECK(fs::exists(t.path()));
}

TEST_CASE("atomic_file: writeFileAtomic writes, replaces, and leaves no temporary") {
    TempDir dir("write");
    const fs::path p = dir.path / "summary.json";
    platform::writeFileAtomic(p, "first");
    CHECK(slurp(p) == "first");
    platform::writeFileAtomic(p, std::string("sec\0ond", 7));
    CHECK(slurp(p) == std::string("sec\0ond", 7));
    CHECK(dir.entries() == 1);
}

TEST_CASE("atomic_file: bad destinations are refused and nothing is written") {
    TempDir dir("dest");
    const fs::path missing = dir.path / "no" / "such" / "out.pcd";
    CHECK_THROWS_WITH_AS(
        platform::writeFileAtomic(missing, "x"),
        ("output: " + missing.string() + ": directory '" + missing.parent_path().string() + "' does not exist").c_str(),
        core::Error);
    CHECK_THROWS_WITH_AS(platform::checkWritableDestination(dir.path),
                         ("output: " + dir.path.string() + ": is a directory; give a file name").c_str(), core::Error);
    std::ofstream(dir.path / "file") << "keep";
    CHECK_THROWS_WITH_AS(platform::checkWritableDestination(dir.path / "file" / "out.pcd"),
                         doctest::Contains("is not a directory"), core::Error);
    CHECK_THROWS_WITH_AS(platform::checkWritableDestination(""), doctest::Contains("output: the output path is empty"),
                         core::Error);
    CHECK_NOTHROW(platform::checkWritableDestination(dir.path / "new.pcd"));
    CHECK(slurp(dir.path / "file") == "keep");
    CHECK(dir.entries() == 1);
}

TEST_CASE("atomic_file: a failed rename keeps the existing file and removes the temporary") {
    TempDir dir("rename");
    // The destination is a non-empty directory: rename(2) fails after the data are written.
    fs::create_directories(dir.path / "taken" / "inside");
    CHECK_THROWS_AS(platform::writeFileAtomic(dir.path / "taken", "data"), core::Error);
    CHECK(fs::is_directory(dir.path / "taken" / "inside"));
    CHECK(dir.entries() == 1);
}
