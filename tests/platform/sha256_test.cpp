// tests/platform/sha256_test.cpp: SHA-256 against the FIPS 180-4 examples, in one piece and
// fed in odd chunks (block boundaries, padding that spills into a second block); a file's
// digest read in chunks, and the files it refuses.
#include <test_files.hpp>
#include <platform/sha256.hpp>

#include <doctest/doctest.h>

#include <filesystem>
#include <string>

TEST_CASE("sha256: FIPS 180-4 known answers") {
    CHECK(platform::sha256Hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    CHECK(platform::sha256Hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    CHECK(platform::sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
          "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    platform::Sha256 million;
    const std::string chunk(1000, 'a');
    for (int i = 0; i < 1000; ++i) million.update(chunk);
    CHECK(million.hex() == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST_CASE("sha256: any split of the input gives the same digest") {
    std::string text;
    for (int i = 0; i < 300; ++i) text += char('a' + i % 26);
    const std::string whole = platform::sha256Hex(text);
    for (std::size_t step : {1u, 7u, 55u, 56u, 63u, 64u, 65u}) {
        platform::Sha256 s;
        for (std::size_t at = 0; at < text.size(); at += step) s.update(std::string_view(text).substr(at, step));
        CHECK(s.hex() == whole);
    }
}

TEST_CASE("sha256: a file's size and digest, and the missing file or link it refuses by name") {
    const test_support::TempDir dir("sha256");
    // Past the 1 MiB read chunk, so the file is fed in more than one piece.
    const std::string text((std::size_t(1) << 20) + 3, 'a');
    const std::filesystem::path file = dir.write("a.bin", text);
    const platform::FileDigest d = platform::sha256File(file, "corpus");
    CHECK(d.bytes == text.size());
    CHECK(d.sha256 == platform::sha256Hex(text));
    CHECK(test_support::errorOf([&] { platform::sha256File(dir.path / "none.bin", "corpus"); }) ==
          "corpus: " + (dir.path / "none.bin").string() + ": cannot read: No such file or directory");
    std::filesystem::create_symlink(file, dir.path / "link.bin");
    CHECK(test_support::errorOf([&] { platform::sha256File(dir.path / "link.bin", "corpus"); }) ==
          "corpus: " + (dir.path / "link.bin").string() + ": cannot read: Too many levels of symbolic links");
}
