// The cache folder: where it is, how it is made and refused, keys from a file's identity,
// reuse marking, and the size bound (only our names, least recently used first).
#include <test_files.hpp>
#include <core/error.hpp>
#include <platform/cache_folder.hpp>

#include <doctest/doctest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using test_support::errorOf;
using test_support::TempDir;

// Sets an environment variable for one scope, restoring the old value after.
struct ScopedEnv {
    std::string name;
    std::string old;
    bool had = false;
    ScopedEnv(const char* n, const char* value) : name(n) {
        if (const char* v = std::getenv(n)) had = true, old = v;
        if (value)
            ::setenv(n, value, 1);
        else
            ::unsetenv(n);
    }
    ~ScopedEnv() {
        if (had)
            ::setenv(name.c_str(), old.c_str(), 1);
        else
            ::unsetenv(name.c_str());
    }
};

void writeBytes(const fs::path& p, std::size_t n) { std::ofstream(p, std::ios::binary) << std::string(n, 'x'); }

// Sets a file's modification time to `seconds` after the epoch.
void setMtime(const fs::path& p, long seconds) {
    const timespec t[2] = {{seconds, 0}, {seconds, 0}};
    REQUIRE(::utimensat(AT_FDCWD, p.c_str(), t, AT_SYMLINK_NOFOLLOW) == 0);
}

bool isIndexName(const std::string& n) { return n.rfind("index-", 0) == 0; }

}  // namespace

TEST_CASE("cache_folder: XDG_CACHE_HOME when absolute, else HOME/.cache, else an error") {
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "/x/cache");
        CHECK(platform::userCacheFolder("ladarvr", "view") == fs::path("/x/cache/ladarvr"));
    }
    {
        ScopedEnv xdg("XDG_CACHE_HOME", "relative/cache");
        ScopedEnv home("HOME", "/home/op");
        CHECK(platform::userCacheFolder("ladarvr", "view") == fs::path("/home/op/.cache/ladarvr"));
    }
    {
        ScopedEnv xdg("XDG_CACHE_HOME", nullptr);
        ScopedEnv home("HOME", nullptr);
        CHECK(errorOf([] { platform::userCacheFolder("ladarvr", "view"); }) ==
              "view: no cache folder: neither XDG_CACHE_HOME nor HOME is an absolute path");
    }
}

TEST_CASE("cache_folder: made 0700 with its parents, a link, a file or a missing parent path refused") {
    TempDir dir("cachefolder");
    const fs::path made = dir.path / "a" / "b" / "ladarvr";
    platform::makeCacheFolder(made, "view: cache folder");
    struct stat st{};
    REQUIRE(::lstat(made.c_str(), &st) == 0);
    CHECK(S_ISDIR(st.st_mode));
    CHECK((st.st_mode & 0777) == 0700);
    REQUIRE(::lstat((dir.path / "a").c_str(), &st) == 0);
    CHECK((st.st_mode & 0777) == 0700);
    platform::makeCacheFolder(made, "view: cache folder");  // there already: fine

    fs::create_directory(dir.path / "elsewhere");
    fs::create_symlink(dir.path / "elsewhere", dir.path / "link");
    const std::string link_error = errorOf([&] { platform::makeCacheFolder(dir.path / "link", "view: cache folder"); });
    CHECK(link_error.find("is a symbolic link; allowed: a folder of this user") != std::string::npos);
    writeBytes(dir.path / "file", 3);
    CHECK(errorOf([&] {
              platform::makeCacheFolder(dir.path / "file", "view: cache folder");
          }).find("is a regular file; allowed: a folder of this user") != std::string::npos);
}

TEST_CASE("cache_folder: the key follows every field of a file's identity") {
    TempDir dir("cachekey");
    const fs::path f = dir.path / "cloud.pcd";
    writeBytes(f, 10);
    const platform::FileIdentity a = platform::fileIdentity(f, "view: cloud");
    CHECK(a.size_bytes == 10);
    CHECK(a.canonical == fs::canonical(f));
    const std::string key = platform::identityKey(a, "v1");
    CHECK(key.size() == 32);
    CHECK(key.find_first_not_of("0123456789abcdef") == std::string::npos);
    CHECK(platform::identityKey(platform::fileIdentity(f, "view: cloud"), "v1") == key);
    CHECK(platform::identityKey(a, "v2") != key);
    auto changed = a;
    changed.mtime_ns += 1;
    CHECK(platform::identityKey(changed, "v1") != key);
    changed = a;
    changed.size_bytes += 1;
    CHECK(platform::identityKey(changed, "v1") != key);
    changed = a;
    changed.inode += 1;
    CHECK(platform::identityKey(changed, "v1") != key);
    changed = a;
    changed.canonical = dir.path / "other.pcd";
    CHECK(platform::identityKey(changed, "v1") != key);
    // A link to the file is the same file.
    fs::create_symlink(f, dir.path / "alias.pcd");
    CHECK(platform::identityKey(platform::fileIdentity(dir.path / "alias.pcd", "view: cloud"), "v1") == key);
}

TEST_CASE("cache_folder: useCachedFile marks a file used and refuses what is not one") {
    TempDir dir("cacheuse");
    const fs::path f = dir.path / "index-a.copc.laz";
    CHECK_FALSE(platform::useCachedFile(f, "view: index"));
    writeBytes(f, 4);
    setMtime(f, 1000);
    CHECK(platform::useCachedFile(f, "view: index"));
    struct stat st{};
    REQUIRE(::stat(f.c_str(), &st) == 0);
    CHECK(st.st_mtim.tv_sec > 1000);
    fs::create_symlink(f, dir.path / "index-b.copc.laz");
    CHECK(errorOf([&] {
              platform::useCachedFile(dir.path / "index-b.copc.laz", "view: index");
          }).find("is a symbolic link; allowed: a regular file this command created") != std::string::npos);
}

TEST_CASE("cache_folder: the bound removes our least recently used files first and nothing else") {
    TempDir dir("cachebound");
    writeBytes(dir.path / "index-old.copc.laz", 100);
    writeBytes(dir.path / "index-mid.copc.laz", 100);
    writeBytes(dir.path / "index-new.copc.laz", 100);
    writeBytes(dir.path / "notes.txt", 1000);  // not our name: never counted or removed
    fs::create_directory(dir.path / "index-dir.copc.laz");
    fs::create_symlink(dir.path / "notes.txt", dir.path / "index-link.copc.laz");
    setMtime(dir.path / "index-old.copc.laz", 1000);
    setMtime(dir.path / "index-mid.copc.laz", 2000);
    setMtime(dir.path / "index-new.copc.laz", 3000);

    // Within the bound: nothing goes.
    CHECK(platform::boundCacheFolder(dir.path, isIndexName, 300, "").empty());
    // 250 bytes: the oldest goes.
    CHECK(platform::boundCacheFolder(dir.path, isIndexName, 250, "") == std::vector<std::string>{"index-old.copc.laz"});
    // 0 bytes with the oldest kept (the one in use): the other goes, the kept one stays.
    CHECK(platform::boundCacheFolder(dir.path, isIndexName, 0, "index-mid.copc.laz") ==
          std::vector<std::string>{"index-new.copc.laz"});
    CHECK(fs::exists(dir.path / "index-mid.copc.laz"));
    CHECK(fs::exists(dir.path / "notes.txt"));
    CHECK(fs::is_directory(dir.path / "index-dir.copc.laz"));
    CHECK(fs::is_symlink(dir.path / "index-link.copc.laz"));
}
