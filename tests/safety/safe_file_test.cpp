// tests/safety/safe_file_test.cpp: outputs never replace what is not ours, temporaries
// cannot be hijacked and never outlive the run, inputs are regular files of bounded size.
// Special files are made in a scratch folder (mknod only as root), never in /dev.
#include <test_files.hpp>
#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/cleanup.hpp>
#include <platform/input_set.hpp>
#include <platform/output_folder.hpp>
#include <platform/safe_file.hpp>

#include <doctest/doctest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <thread>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using test_support::slurp;
using test_support::TempDir;

using test_support::errorOf;

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Names in `dir` that look like our temporaries.
int temporariesIn(const fs::path& dir) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().rfind(".ladarvr-tmp-", 0) == 0) ++n;
    return n;
}

// Runs `child` in a forked process; returns its wait status.
int inChild(const std::function<void()>& child) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        child();
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
}

// A pid that is certainly not alive: a child that has exited and been reaped.
pid_t deadPid() {
    const pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    ::waitpid(pid, nullptr, 0);
    return pid;
}

}  // namespace

TEST_CASE("an existing destination that is not a regular file is refused and left as it is") {
    TempDir dir("special");
    SUBCASE("a FIFO (never opened: the call returns at once)") {
        const fs::path fifo = dir.path / "fifo";
        REQUIRE(::mkfifo(fifo.c_str(), 0666) == 0);
        CHECK(contains(errorOf([&] { platform::writeFileAtomic(fifo, "data"); }),
                       "is a FIFO (named pipe); refusing to replace it"));
        CHECK(fs::is_fifo(fifo));
    }
    SUBCASE("a character device (mknod, as root)") {
        const fs::path node = dir.path / "null";
        if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
            MESSAGE("mknod needs root: character-device case skipped");
            return;
        }
        CHECK(contains(errorOf([&] { platform::writeFileAtomic(node, "data"); }),
                       "is a character device; refusing to replace it"));
        CHECK(fs::is_character_file(node));
    }
    SUBCASE("a symbolic link, to a file or dangling") {
        const fs::path victim = dir.write("victim", "keep");
        fs::create_symlink(victim, dir.path / "link");
        fs::create_symlink(dir.path / "nowhere", dir.path / "dangling");
        CHECK(contains(errorOf([&] { platform::writeFileAtomic(dir.path / "link", "data"); }),
                       "is a symbolic link; refusing to replace it"));
        CHECK(
            contains(errorOf([&] { platform::writeFileAtomic(dir.path / "dangling", "data"); }), "is a symbolic link"));
        CHECK(slurp(victim) == "keep");
        CHECK(fs::is_symlink(dir.path / "link"));
        CHECK_FALSE(fs::exists(dir.path / "nowhere"));
    }
    CHECK(temporariesIn(dir.path) == 0);
}

TEST_CASE("a destination that turns into a FIFO after the check is still not replaced") {
    TempDir dir("race");
    const fs::path out = dir.path / "out.txt";
    platform::TempFile tmp(out);
    std::fputs("data", tmp.file());
    REQUIRE(::mkfifo(out.c_str(), 0666) == 0);  // appears while the data are written
    CHECK(contains(errorOf([&] { tmp.commit(); }), "is a FIFO (named pipe); refusing to replace it"));
    CHECK(fs::is_fifo(out));
    CHECK(temporariesIn(dir.path) == 0);
}

TEST_CASE("temporaries have random names and never follow a planted symbolic link") {
    TempDir dir("planted");
    const fs::path victim = dir.write("victim", "unrelated");
    const fs::path out = dir.path / "out.pcd";
    // The names an attacker could predict before: <out>.tmp-<pid> and <out>.spool-<pid>.
    fs::create_symlink(victim, out.string() + ".tmp-" + std::to_string(::getpid()));
    fs::create_symlink(victim, out.string() + ".spool-" + std::to_string(::getpid()));
    platform::TempFile a(out), b(out);
    CHECK(a.path() != b.path());
    CHECK(fs::is_regular_file(fs::symlink_status(a.path())));
    std::fputs("new", a.file());
    a.commit();
    CHECK(slurp(out) == "new");
    CHECK(slurp(victim) == "unrelated");
    b.discard();
    CHECK(temporariesIn(dir.path) == 0);
}

TEST_CASE("the scratch file is anonymous: nothing of it is in the folder, even while open") {
    TempDir dir("scratch");
    std::FILE* f = platform::openScratchFile(dir.path, "out.pcd");
    REQUIRE(f != nullptr);
    CHECK(dir.entries() == 0);
    const std::string data(100000, 'x');
    REQUIRE(std::fwrite(data.data(), 1, data.size(), f) == data.size());
    std::rewind(f);
    std::string back(data.size(), '\0');
    CHECK(std::fread(back.data(), 1, back.size(), f) == back.size());
    CHECK(back == data);
    std::fclose(f);
    CHECK(dir.entries() == 0);
}

TEST_CASE("an output that is an input of the run is refused, through links too") {
    TempDir dir("input");
    const fs::path scene = dir.write("scene.json", "{}");
    CHECK(platform::readTextFile(scene, 1000, "scene") == "{}");
    platform::InputSet inputs;
    inputs.addFile(scene);
    fs::create_hard_link(scene, dir.path / "hard");
    fs::create_directories(dir.path / "real");
    fs::create_symlink(dir.path, dir.path / "real" / "up");
    for (const fs::path& out : {scene, dir.path / "hard", dir.path / "real" / "up" / "scene.json"}) {
        CAPTURE(out);
        CHECK(contains(errorOf([&] { platform::checkWritableDestination(out, inputs); }), "is the input file"));
    }
    CHECK(slurp(scene) == "{}");
    CHECK_NOTHROW(platform::checkWritableDestination(dir.path / "other.json", inputs));
    CHECK_NOTHROW(platform::writeFileAtomic(dir.path / "other.json", "fine"));
}

TEST_CASE("text inputs: regular files only, size capped, messages say what the name is") {
    TempDir dir("text");
    const std::string what = "test: the file";
    CHECK(contains(errorOf([&] { platform::readTextFile("/dev/zero", 1024, what); }),
                   "test: the file is a character device; allowed: a regular file of at most 1 KiB"));
    CHECK(contains(errorOf([&] { platform::readTextFile(dir.path, 1024, what); }), "is a directory"));
    const fs::path fifo = dir.path / "fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0666) == 0);
    CHECK(contains(errorOf([&] { platform::readTextFile(fifo, 1024, what); }), "is a FIFO (named pipe)"));
    fs::create_symlink("loop", dir.path / "loop");
    CHECK(contains(errorOf([&] { platform::readTextFile(dir.path / "loop", 1024, what); }), "is a symbolic link loop"));
    fs::create_symlink("gone", dir.path / "dangling");
    CHECK(contains(errorOf([&] { platform::readTextFile(dir.path / "dangling", 1024, what); }),
                   "is a dangling symbolic link (to 'gone'"));
    CHECK(contains(errorOf([&] { platform::readTextFile(dir.path / "none", 1024, what); }), "does not exist"));
    const fs::path exact = dir.write("exact", std::string(1024, 'a'));
    CHECK(platform::readTextFile(exact, 1024, what).size() == 1024);
    const fs::path big = dir.write("big", std::string(1025, 'a'));
    CHECK(contains(errorOf([&] { platform::readTextFile(big, 1024, what); }), "is 1025 bytes; allowed"));
    // A sparse file claiming 4 GiB is refused from its size, without reading it.
    const fs::path sparse = dir.path / "sparse";
    { std::ofstream(sparse) << ""; }
    fs::resize_file(sparse, std::uintmax_t(4) << 30);
    CHECK(contains(errorOf([&] { platform::readTextFile(sparse, 1 << 20, what); }), "bytes; allowed"));
    CHECK(core::printable(std::string("a\x01\xff\x1b[31m", 8)) == "a\\x01\\xff\\x1b[31m");
}

TEST_CASE("a folder's own entries: a link planted on the way down is refused, the folder's own path may link") {
    TempDir dir("below");
    fs::create_directories(dir.path / "corpus/items/0001");
    dir.write("corpus/items/0001/cloud.pcd", "x");
    const std::string what = "test: item 0001";
    CHECK_NOTHROW(platform::checkNoLinkBelow(dir.path / "corpus", "items/0001/cloud.pcd", what));
    // The folder named by the user may itself be a link.
    fs::create_directory_symlink(dir.path / "corpus", dir.path / "alias");
    CHECK_NOTHROW(platform::checkNoLinkBelow(dir.path / "alias", "items/0001/cloud.pcd", what));
    // Absent names are the reader's to report.
    CHECK_NOTHROW(platform::checkNoLinkBelow(dir.path / "corpus", "items/0002/cloud.pcd", what));
    fs::create_directories(dir.path / "other/items/0001");
    fs::create_directory_symlink(dir.path / "corpus/items/0001", dir.path / "other/items/0003");
    CHECK(contains(errorOf([&] { platform::checkNoLinkBelow(dir.path / "other", "items/0003/cloud.pcd", what); }),
                   "': 'items/0003' in it is a symbolic link; allowed: the folder's own folders, not a link"));
    fs::create_symlink("/proc/self/environ", dir.path / "other/items/0001/cloud.pcd");
    const std::string e =
        errorOf([&] { platform::checkNoLinkBelow(dir.path / "other", "items/0001/cloud.pcd", what); });
    CHECK(contains(e, "test: item 0001 '"));
    CHECK(
        contains(e, "': 'items/0001/cloud.pcd' in it is a symbolic link; allowed: the folder's own file, not a link"));
    fs::remove_all(dir.path / "other/items");
    fs::create_directory_symlink(dir.path / "corpus/items", dir.path / "other/items");
    CHECK(contains(errorOf([&] { platform::checkNoLinkBelow(dir.path / "other", "items/0001/cloud.pcd", what); }),
                   "': 'items' in it is a symbolic link"));
}

TEST_CASE("messages: control characters and invalid bytes escaped, UTF-8 kept, long lines cut in the middle") {
    // C0, DEL and C1 (U+009B is a one-character CSI on some terminals) escaped byte by byte.
    CHECK(platform::printableUtf8("a\nb\x1b[2J\x7f\xc2\x9b") == "a\\x0ab\\x1b[2J\\x7f\\xc2\\x9b");
    // Valid UTF-8 kept; a stray continuation, an overlong form, a surrogate and a cut sequence escaped.
    CHECK(platform::printableUtf8("gr\xc3\xbcn \xe2\x82\xac \xf0\x9f\x99\x82") ==
          "gr\xc3\xbcn \xe2\x82\xac \xf0\x9f\x99\x82");
    CHECK(platform::printableUtf8("\x80\xc0\xaf\xed\xa0\x80\xe2\x82") == "\\x80\\xc0\\xaf\\xed\\xa0\\x80\\xe2\\x82");
    // The cap never splits a character, escaped or not.
    CHECK(platform::printableUtf8("ab\xc3\xbc", 3) == "ab...");
    CHECK(platform::printableUtf8("ab\x1b", 5) == "ab...");
    // Escaped text is left as it is: a message that quoted printable() is unchanged.
    const std::string once = core::printable("x\x1b[31m\xff");
    CHECK(platform::messageLine(once) == once);
    // A megabyte: the start and the end stay, the middle goes, the line is at most the cap.
    const std::string huge = "module: file: '" + std::string(1 << 20, '\x1b') + "'; allowed: what is allowed";
    const std::string line = platform::messageLine(huge);
    CHECK(line.size() <= platform::kMaxMessageChars);
    CHECK(line.size() > platform::kMaxMessageChars - 8);
    CHECK(line.starts_with("module: file: '\\x1b\\x1b"));
    CHECK(line.ends_with("\\x1b'; allowed: what is allowed"));
    CHECK(line.find("\\x1b ... \\x1b") != std::string::npos);
    CHECK(line.find('\x1b') == std::string::npos);
    CHECK(platform::messageLine("short") == "short");
}

TEST_CASE("the next run removes temporaries of dead processes, and only those") {
    TempDir dir("stale");
    const std::string dead = std::to_string(deadPid());
    const std::string stale = ".ladarvr-tmp-" + dead + "-";
    const fs::path stale_file = dir.write(stale + "AbC123", "partial cloud");
    const fs::path item_file = dir.write(stale + "00012", "a corpus item's id as the tag");
    // A folder of ours holds our files only: a dead run's temporary folder goes.
    fs::create_directories(dir.path / (stale + "Own456"));
    std::ofstream(dir.path / (stale + "Own456") / (stale + "Q1w2E3")) << "x";
    // Whatever we cannot have made stays: a folder tree, a FIFO, a link, a folder with a
    // file the command does not write there.
    fs::create_directories(dir.path / (stale + "Dir456") / "inside");
    const fs::path fifo = dir.path / (stale + "fifo01");
    REQUIRE(::mkfifo(fifo.c_str(), 0666) == 0);
    fs::create_symlink("cloud.pcd", dir.path / (stale + "link01"));
    fs::create_directories(dir.path / (stale + "Mix789"));
    std::ofstream(dir.path / (stale + "Mix789") / "notes.txt") << "a user's";
    const fs::path alive = dir.write(".ladarvr-tmp-1-XyZ789", "init's, alive");  // pid 1 lives
    const fs::path lookalike = dir.write(stale + "not.ours", "not our pattern");
    const fs::path user = dir.write("cloud.pcd", "a user's file");
    platform::writeFileAtomic(dir.path / "new.txt", "x");
    CHECK_FALSE(fs::exists(stale_file));
    CHECK_FALSE(fs::exists(item_file));
    CHECK_FALSE(fs::exists(dir.path / (stale + "Own456")));
    CHECK(fs::exists(dir.path / (stale + "Dir456") / "inside"));
    CHECK(fs::is_fifo(fifo));
    CHECK(fs::is_symlink(dir.path / (stale + "link01")));
    CHECK(slurp(dir.path / (stale + "Mix789") / "notes.txt") == "a user's");
    CHECK(fs::exists(alive));
    CHECK(fs::exists(lookalike));
    CHECK(slurp(user) == "a user's file");
    // With the names a folder of the command holds, such a folder goes too.
    platform::removeStaleTemporaries(dir.path, [](const std::string& name) { return name == "notes.txt"; });
    CHECK_FALSE(fs::exists(dir.path / (stale + "Mix789")));
    CHECK(fs::exists(dir.path / (stale + "Dir456") / "inside"));
}

TEST_CASE("SIGTERM, SIGINT and SIGHUP remove the temporaries and end the process by the signal") {
    TempDir dir("signal");
    for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
        CAPTURE(sig);
        const int status = inChild([&] {
            // As in the CLI: default dispositions (the test runner catches signals itself).
            for (int s : {SIGTERM, SIGINT, SIGHUP}) std::signal(s, SIG_DFL);
            platform::TempFile a(dir.path / "a.pcd"), b(dir.path / "b.json");
            std::FILE* spool = platform::openScratchFile(dir.path, "a.pcd");
            std::fputs("partial", a.file());
            std::fflush(a.file());
            (void)spool;
            ::kill(::getpid(), sig);
            ::sleep(5);  // the handler ends the process before this returns
            ::_exit(3);
        });
        REQUIRE(WIFSIGNALED(status));
        CHECK(WTERMSIG(status) == sig);  // the shell reports 128 + sig: 143, 130, 129
        CHECK(dir.entries() == 0);
    }
}

TEST_CASE("the watchdog ends a run stuck past its deadline, removing its temporaries") {
    TempDir dir("watchdog");
    const int status = inChild([&] {
        platform::TempFile a(dir.path / "a.json");
        platform::Watchdog w(0.3, "test: --timeout 0.3 s reached", 1);
        ::sleep(10);  // stuck start-up
        ::_exit(5);
    });
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);  // the watchdog's status, not the 5 of a start-up that ended
    CHECK(dir.entries() == 0);
    // Cancelled by going out of scope in time.
    { platform::Watchdog w(0.05, "never", 1); }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
}

namespace {
bool ours(const std::string& name) { return name == "a.txt" || name == "b.txt" || name == "c.txt"; }
}  // namespace

TEST_CASE("an output folder is replaced as a whole: never a mix of two runs") {
    TempDir dir("folder");
    const fs::path out = dir.path / "report";
    platform::writeFolderAtomic(out, {{"a.txt", "run1 a"}, {"b.txt", "run1 b"}, {"c.txt", "run1 c"}}, ours);
    CHECK(slurp(out / "b.txt") == "run1 b");
    SUBCASE("a smaller second set leaves no stale sibling") {
        platform::writeFolderAtomic(out, {{"a.txt", "run2 a"}, {"c.txt", "run2 c"}}, ours);
        CHECK(slurp(out / "a.txt") == "run2 a");
        CHECK_FALSE(fs::exists(out / "b.txt"));
        CHECK(slurp(out / "c.txt") == "run2 c");
    }
    SUBCASE("a failed write (file size limit) leaves the previous set whole") {
        struct rlimit old{};
        ::getrlimit(RLIMIT_FSIZE, &old);
        const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
        struct rlimit small = old;
        small.rlim_cur = 4096;
        ::setrlimit(RLIMIT_FSIZE, &small);
        const std::string m = errorOf([&] {
            platform::writeFolderAtomic(
                out, {{"a.txt", "run2 a"}, {"b.txt", std::string(10000, 'b')}, {"c.txt", "run2 c"}}, ours);
        });
        ::setrlimit(RLIMIT_FSIZE, &old);
        std::signal(SIGXFSZ, old_handler);
        CHECK(contains(m, "b.txt: write failed"));
        CHECK(slurp(out / "a.txt") == "run1 a");
        CHECK(slurp(out / "b.txt") == "run1 b");
        CHECK(slurp(out / "c.txt") == "run1 c");
    }
    SUBCASE("a folder holding a file we do not write is refused") {
        std::ofstream(out / "thesis.tex") << "years of work";
        CHECK(contains(errorOf([&] { platform::writeFolderAtomic(out, {{"a.txt", "x"}}, ours); }),
                       "holds 'thesis.tex', which this command does not write"));
        CHECK(contains(errorOf([&] { platform::checkOutputFolder(out, ours); }), "refusing to replace the folder"));
        CHECK(slurp(out / "thesis.tex") == "years of work");
        CHECK(slurp(out / "a.txt") == "run1 a");
    }
    SUBCASE("a link to a folder is refused: neither the link nor the folder it points to changes") {
        fs::create_directory_symlink(out, dir.path / "link");
        CHECK(contains(errorOf([&] { platform::writeFolderAtomic(dir.path / "link", {{"a.txt", "via link"}}, ours); }),
                       "is a symbolic link; refusing to follow it"));
        CHECK(contains(errorOf([&] { platform::checkOutputFolder(dir.path / "link", ours); }),
                       "is a symbolic link; refusing to follow it"));
        CHECK(fs::is_symlink(dir.path / "link"));
        CHECK(slurp(out / "a.txt") == "run1 a");
        CHECK(slurp(out / "b.txt") == "run1 b");
    }
    SUBCASE("a regular file is named as one") {
        std::ofstream(dir.path / "file.txt") << "text";
        CHECK(contains(errorOf([&] { platform::checkOutputFolder(dir.path / "file.txt", ours); }),
                       "is a regular file, not a folder"));
    }
    SUBCASE("missing parent folders are made") {
        platform::checkOutputFolder(dir.path / "x" / "y" / "report", ours);
        platform::writeFolderAtomic(dir.path / "x" / "y" / "report", {{"a.txt", "deep"}}, ours);
        CHECK(slurp(dir.path / "x" / "y" / "report" / "a.txt") == "deep");
    }
    CHECK(temporariesIn(dir.path) == 0);
}

TEST_CASE("a run's paths: no output onto an input or another output, none inside an output folder") {
    using platform::PathRole;
    TempDir dir("distinct");
    const fs::path scene = dir.path / "scene.json";
    std::ofstream(scene) << "{}";
    const auto check = [](const std::vector<platform::RunPath>& paths) {
        return errorOf([&] { platform::checkDistinctPaths("cmd", paths); });
    };
    SUBCASE("two outputs under one name, also spelt differently or absent yet") {
        CHECK(contains(check({{"--out", dir.path / "x.pcd", PathRole::Output, {}},
                              {"--dtm", dir.path / "." / "x.pcd", PathRole::Output, {}}}),
                       "cmd: --out '" + (dir.path / "x.pcd").string() + "' and --dtm '"));
        CHECK(contains(check({{"--out", dir.path / "x.pcd", PathRole::Output, {}},
                              {"--dtm", dir.path / "x.pcd", PathRole::Output, {}}}),
                       "name the same file; allowed: a distinct path for each output"));
    }
    SUBCASE("an output onto an input, through a symbolic link or a hard link") {
        fs::create_symlink(scene, dir.path / "soft.json");
        fs::create_hard_link(scene, dir.path / "hard.asc");
        CHECK(contains(
            check({{"--scene", scene, PathRole::Input, {}}, {"--dtm", dir.path / "soft.json", PathRole::Output, {}}}),
            "name the same file"));
        CHECK(contains(
            check({{"--scene", scene, PathRole::Input, {}}, {"--dtm", dir.path / "hard.asc", PathRole::Output, {}}}),
            "name the same file"));
    }
    SUBCASE("one input given twice is allowed; empty paths are skipped") {
        CHECK(check({{"--p1", scene, PathRole::Input, {}},
                     {"--p2", scene, PathRole::Input, {}},
                     {"--dtm", "", PathRole::Output, {}},
                     {"--out", "", PathRole::Output, {}}}) == "(no error)");
    }
    SUBCASE("an input inside an output folder replaced as a whole") {
        fs::create_directories(dir.path / "report");
        std::ofstream(dir.path / "report" / "view_0_i1.png") << "cloud";
        CHECK(contains(check({{"--out", dir.path / "report", PathRole::OutputFolder, {}},
                              {"--p1", dir.path / "report" / "view_0_i1.png", PathRole::Input, {}}}),
                       "lies inside the output folder --out '" + (dir.path / "report").string() +
                           "', which this run replaces as a whole"));
    }
    SUBCASE("an output folder that writes some names: only those conflict") {
        const platform::OwnedName study = [](const std::string& n) { return n.rfind("trace_", 0) == 0; };
        CHECK(contains(check({{"--out", dir.path / "d", PathRole::OutputFolder, study},
                              {"--log-json", dir.path / "d" / "trace_1.csv", PathRole::Output, {}}}),
                       "where this run writes 'trace_1.csv'"));
        CHECK(check({{"--out", dir.path / "d", PathRole::OutputFolder, study},
                     {"--log-json", dir.path / "d" / "log.json", PathRole::Output, {}}}) == "(no error)");
    }
    SUBCASE("an output inside an input folder") {
        CHECK(contains(check({{"--stats", dir.path, PathRole::InputFolder, {}},
                              {"--histogram", dir.path / "manifest.jsonl", PathRole::Output, {}}}),
                       "lies inside the input folder --stats"));
        CHECK(check({{"--stats", dir.path, PathRole::InputFolder, {}},
                     {"--p1", dir.path / "a.pcd", PathRole::Input, {}}}) == "(no error)");
    }
    SUBCASE("a path longer than the system opens: one line, the path shortened") {
        const std::string long_path = "/tmp/" + std::string(4300, 'a');
        const std::string m = check({{"--out", long_path, PathRole::Output, {}}});
        CHECK(contains(m, "cmd: --out: /tmp/aaa"));
        CHECK(contains(m, "the path is 4305 bytes long; allowed at most 4095 bytes"));
        CHECK(m.size() < 300);
        CHECK(contains(check({{"--out", "/tmp/" + std::string(300, 'b') + "/x", PathRole::Output, {}}}),
                       "a name in it is 300 bytes long; allowed at most 255 bytes per name"));
        CHECK(contains(errorOf([&] { platform::checkWritableDestination(long_path); }), "allowed at most 4095 bytes"));
    }
}
