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

#include <sys/stat.h>

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

TEST_CASE("output_folder: an entry named as ours but not a regular file is refused, nothing moved or left") {
    // A link, a folder or a FIFO under a name the command writes would be swapped out with
    // the previous folder and, not removable as ours, left hidden beside the new one.
    for (const char* kind : {"link", "folder", "fifo"}) {
        CAPTURE(kind);
        TempDir tmp("atomic_folder_kinds");
        const fs::path dir = tmp.path / "out";
        fs::create_directory(dir);
        tmp.write("out/a.txt", "old a");
        tmp.write("victim.txt", "someone's");
        std::string what;
        if (std::string(kind) == "link") {
            fs::create_symlink(tmp.path / "victim.txt", dir / "b.txt");
            what = "which is a symbolic link, not a file this command writes";
        } else if (std::string(kind) == "folder") {
            fs::create_directory(dir / "b.txt");
            tmp.write("out/b.txt/thesis.tex", "years of work");
            what = "which is a directory, not a file this command writes";
        } else {
            REQUIRE(::mkfifo((dir / "b.txt").c_str(), 0600) == 0);
            what = "which is a FIFO (named pipe), not a file this command writes";
        }
        const std::string m =
            test_support::errorOf([&] { platform::writeFolderAtomic(dir, {{"a.txt", "new"}}, ours); });
        CHECK(m == "output: " + dir.string() + ": holds 'b.txt', " + what +
                       "; refusing to replace the folder (give a new or empty folder)");
        CHECK(test_support::errorOf([&] { platform::checkOutputFolder(dir, ours); }) == m);
        CHECK(names(dir) == std::set<std::string>{"a.txt", "b.txt"});
        CHECK(test_support::slurp(dir / "a.txt") == "old a");
        CHECK(names(tmp.path) == std::set<std::string>{"out", "victim.txt"});  // no hidden folder beside
    }
}

TEST_CASE("output_folder: a link planted while the new folder is written stops the swap, leaving no hidden folder") {
    TempDir tmp("atomic_folder_race");
    const fs::path dir = tmp.path / "out";
    fs::create_directory(dir);
    tmp.write("out/a.txt", "old a");
    tmp.write("victim.txt", "someone's");
    // The check at commit() sees the link (or, were it planted just after that check, the
    // removal of the previous folder finds it): either way the previous folder stays in place.
    {
        platform::AtomicFolder folder(dir, ours);
        folder.writeFile("a.txt", "new a");
        fs::create_symlink(tmp.path / "victim.txt", dir / "b.txt");
        CHECK(test_support::errorOf([&] { folder.commit(); }).find("holds 'b.txt', which is a symbolic link") !=
              std::string::npos);
    }
    CHECK(names(dir) == std::set<std::string>{"a.txt", "b.txt"});
    CHECK(test_support::slurp(dir / "a.txt") == "old a");
    CHECK(names(tmp.path) == std::set<std::string>{"out", "victim.txt"});

    // Planted after commit()'s check, into the previous folder once it is swapped out and
    // before it is removed: the name test, asked then, plants the link.
    fs::remove(dir / "b.txt");
    bool planted = false;
    const platform::OwnedName planting = [&](const std::string& name) {
        for (const auto& e : fs::directory_iterator(tmp.path)) {
            const fs::path old_a = e.path() / "a.txt";
            if (!planted && e.path().filename().string().starts_with(".ladarvr-tmp-") && fs::exists(old_a) &&
                test_support::slurp(old_a) == "old a") {
                planted = true;
                fs::create_symlink(tmp.path / "victim.txt", e.path() / "b.txt");
            }
        }
        return ours(name);
    };
    {
        platform::AtomicFolder folder(dir, planting);
        folder.writeFile("a.txt", "new a");
        CHECK(test_support::errorOf([&] {
                  folder.commit();
              }).find("the folder changed while the new one was written") != std::string::npos);
    }
    CHECK(planted);
    CHECK(fs::is_symlink(dir / "b.txt"));                                  // back in place, visible
    CHECK(names(tmp.path) == std::set<std::string>{"out", "victim.txt"});  // nothing hidden beside
}
