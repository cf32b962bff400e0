// Scratch files: anonymous in the chosen folder, appended, read back at offsets and in
// sequence, bounded reads at the end, freed pages, messages naming the output.
#include <test_files.hpp>
#include <core/error.hpp>
#include <platform/scratch_file.hpp>

#include <doctest/doctest.h>

#include <string>
#include <utility>

namespace {

using test_support::errorOf;
using test_support::TempDir;

// 0, 1, 2, ... as bytes (mod 251, so no page repeats another).
std::string pattern(std::size_t n, std::size_t from = 0) {
    std::string s(n, '\0');
    for (std::size_t i = 0; i < n; ++i) s[i] = char((from + i) % 251);
    return s;
}

}  // namespace

TEST_CASE("scratch_file: nothing of it is in the folder, while open or after") {
    TempDir dir("scratch_anon");
    {
        platform::ScratchFile f(dir.path, "out.copc.laz");
        const std::string data = pattern(100000);
        f.append(data.data(), data.size());
        f.flush();
        CHECK(dir.entries() == 0);
        CHECK(f.size() == data.size());
    }
    CHECK(dir.entries() == 0);
}

TEST_CASE("scratch_file: appended pieces read back at any offset, across pieces, from several calls") {
    TempDir dir("scratch_at");
    platform::ScratchFile f(dir.path, "out.copc.laz");
    const std::string a = pattern(5000), b = pattern(70000, 5000);
    f.append(a.data(), a.size());
    f.append(b.data(), b.size());
    CHECK(f.tryAppend(nullptr, 0) == 0);
    CHECK(f.size() == 75000);
    f.flush();
    std::string got(10000, '\0');
    f.readAt(got.data(), got.size(), 1000);  // spans both pieces
    CHECK(got == pattern(10000, 1000));
    f.readAt(got.data(), 10, 74990);  // the last bytes
    CHECK(got.substr(0, 10) == pattern(10, 74990));
    CHECK(errorOf([&] { f.readAt(got.data(), 11, 74990); }) ==
          "output: out.copc.laz: reading a scratch file back failed");
}

TEST_CASE("scratch_file: rewound, it reads in sequence, a bounded read stops at the end") {
    TempDir dir("scratch_seq");
    platform::ScratchFile f(dir.path, "out.pcd");
    const std::string data = pattern(9000);
    f.append(data.data(), data.size());
    f.rewind();
    std::string first(4000, '\0');
    f.read(first.data(), first.size());
    CHECK(first == data.substr(0, 4000));
    std::string rest(8000, '\0');
    CHECK(f.readUpTo(rest.data(), rest.size()) == 5000);
    CHECK(rest.substr(0, 5000) == data.substr(4000));
    CHECK(f.readUpTo(rest.data(), rest.size()) == 0);
    CHECK(errorOf([&] { f.read(rest.data(), 1); }) == "output: out.pcd: reading a scratch file back failed");
    // A second pass from the start gives the same bytes.
    CHECK(f.tryRewind() == 0);
    CHECK(f.readUpTo(rest.data(), 3) == 3);
    CHECK(rest.substr(0, 3) == data.substr(0, 3));
}

TEST_CASE("scratch_file: freeing what was read keeps the bytes after it") {
    TempDir dir("scratch_free");
    platform::ScratchFile f(dir.path, "out.copc.laz");
    const std::string data = pattern(5 * 4096 + 100);
    f.append(data.data(), data.size());
    f.rewind();
    std::string got(2 * 4096 + 10, '\0');
    f.read(got.data(), got.size());
    f.discardRead();            // frees the first two pages
    f.discardBefore(3 * 4096);  // and the third
    f.discardBefore(4096);      // an earlier end frees nothing more
    std::string rest(data.size() - got.size(), '\0');
    f.read(rest.data(), rest.size());
    CHECK(rest == data.substr(got.size()));
    std::string tail(100, '\0');
    f.readAt(tail.data(), tail.size(), 5 * 4096);
    CHECK(tail == data.substr(5 * 4096));
}

TEST_CASE("scratch_file: a moved file keeps its bytes and its count") {
    TempDir dir("scratch_move");
    platform::ScratchFile a(dir.path, "out.laz");
    const std::string data = pattern(300);
    a.append(data.data(), data.size());
    platform::ScratchFile b(std::move(a));
    platform::ScratchFile c(dir.path, "other.laz");
    c = std::move(b);
    CHECK(c.size() == 300);
    CHECK(c.what() == "out.laz");
    c.flush();
    std::string got(300, '\0');
    c.readAt(got.data(), got.size(), 0);
    CHECK(got == data);
}

TEST_CASE("scratch_file: a folder that is missing is named in the message") {
    TempDir dir("scratch_missing");
    const std::string e = errorOf([&] { platform::ScratchFile f(dir.path / "absent", "out.copc.laz"); });
    CHECK(e.rfind("output: out.copc.laz: cannot create a scratch file in '", 0) == 0);
    CHECK(e.find("absent") != std::string::npos);
}
