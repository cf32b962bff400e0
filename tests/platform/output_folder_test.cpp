// tests/platform/output_folder_test.cpp: platform::AtomicFolder, the one writer of whole
// output folders (the metric's report folder, corpus items): files written or adopted,
// the swap with a previous folder, and nothing left behind on failure.
#include <test_files.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/output_folder.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <set>
#include <string>

namespace fs = std::filesystem;
using test_support::TempDir;

namespace {

bool ours(const std::string& name) { return name == "a.txt" || name == "b.txt"; }

std::set<std::string> names(const fs::path& dir) {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
    return out;
}

}  // namespace

TEST_CASE("output_folder: written and adopted files move into place together, nothing left beside") {
    TempDir tmp("atomic_folder_new");
    const fs::path dir = tmp.path / "out";
    {
        platform::AtomicFolder folder(dir, ours);
        folder.writeFile("a.txt", "first");
        platform::writeFileAtomic(folder.path("b.txt"), "second");  // another writer's file
        folder.adopt("b.txt");
        CHECK_FALSE(fs::exists(dir));  // not before commit
        folder.commit();
    }
    CHECK(names(dir) == std::set<std::string>{"a.txt", "b.txt"});
    CHECK(test_support::slurp(dir / "a.txt") == "first");
    CHECK(test_support::slurp(dir / "b.txt") == "second");
    CHECK(names(tmp.path) == std::set<std::string>{"out"});
}

TEST_CASE("output_folder: a previous folder is replaced as a whole") {
    TempDir tmp("atomic_folder_swap");
    const fs::path dir = tmp.path / "out";
    fs::create_directory(dir);
    tmp.write("out/a.txt", "old a");
    tmp.write("out/b.txt", "old b");
    platform::AtomicFolder folder(dir, ours);
    folder.writeFile("a.txt", "new a");
    folder.commit();
    CHECK(names(dir) == std::set<std::string>{"a.txt"});  // the old b.txt went with its folder
    CHECK(test_support::slurp(dir / "a.txt") == "new a");
    CHECK(names(tmp.path) == std::set<std::string>{"out"});
}

TEST_CASE("output_folder: uncommitted, the temporary folder goes and the previous one stays") {
    TempDir tmp("atomic_folder_discard");
    const fs::path dir = tmp.path / "out";
    fs::create_directory(dir);
    tmp.write("out/a.txt", "old");
    {
        platform::AtomicFolder folder(dir, ours);
        folder.writeFile("a.txt", "new");
        platform::writeFileAtomic(folder.path("b.txt"), "new b");
        folder.adopt("b.txt");
        CHECK(names(tmp.path).size() == 2);  // out and the temporary folder
    }
    CHECK(names(tmp.path) == std::set<std::string>{"out"});
    CHECK(names(dir) == std::set<std::string>{"a.txt"});
    CHECK(test_support::slurp(dir / "a.txt") == "old");
}

TEST_CASE("output_folder: a folder holding names we do not write is refused, before and at the swap") {
    TempDir tmp("atomic_folder_foreign");
    const fs::path dir = tmp.path / "out";
    fs::create_directory(dir);
    tmp.write("out/notes.txt", "keep me");
    CHECK(test_support::errorOf([&] { platform::AtomicFolder folder(dir, ours); }).find("holds 'notes.txt'") !=
          std::string::npos);
    CHECK(names(tmp.path) == std::set<std::string>{"out"});

    // A foreign file that appears while the new folder is written stops the swap.
    fs::remove(dir / "notes.txt");
    {
        platform::AtomicFolder folder(dir, ours);
        folder.writeFile("a.txt", "new");
        tmp.write("out/notes.txt", "keep me");
        CHECK(test_support::errorOf([&] { folder.commit(); }).find("holds 'notes.txt'") != std::string::npos);
    }
    CHECK(names(dir) == std::set<std::string>{"notes.txt"});
    CHECK(names(tmp.path) == std::set<std::string>{"out"});
}

TEST_CASE("output_folder: writeFolderAtomic makes missing parent folders and writes every file") {
    TempDir tmp("atomic_folder_parents");
    const fs::path dir = tmp.path / "x" / "y" / "out";
    platform::writeFolderAtomic(dir, {{"a.txt", "1"}, {"b.txt", "2"}}, ours);
    CHECK(names(dir) == std::set<std::string>{"a.txt", "b.txt"});
    CHECK(test_support::slurp(dir / "b.txt") == "2");
    CHECK(names(dir.parent_path()) == std::set<std::string>{"out"});
}
