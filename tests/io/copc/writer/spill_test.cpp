// The COPC writer's spill (io/src/copc/writer/spill.hpp): bytes kept in memory up to its
// head, the rest in an anonymous scratch file, read back across the two, freed once read.
#include <test_files.hpp>
#include <core/error.hpp>

#include "../../../../io/src/copc/writer/spill.hpp"

#include <doctest/doctest.h>

#include <string>

namespace {

using io::detail::copc_writer::Spill;
using test_support::errorOf;
using test_support::TempDir;

std::string pattern(std::size_t n, std::size_t from = 0) {
    std::string s(n, '\0');
    for (std::size_t i = 0; i < n; ++i) s[i] = char((from + i) % 251);
    return s;
}

}  // namespace

TEST_CASE("copc spill: the first bytes stay in memory, the rest go to a scratch file, and read back as one") {
    TempDir dir("copc_spill_unit");
    Spill spill(dir.path, "out.copc.laz", 100);
    const std::string data = pattern(250);
    spill.write(data.data(), 60);
    spill.write(data.data() + 60, 60);  // crosses the head's end
    spill.write(data.data() + 120, 130);
    spill.flush();
    CHECK(dir.entries() == 0);  // the scratch file has no name
    std::string got(250, '\0');
    spill.readAt(got.data(), got.size(), 0);
    CHECK(got == data);
    std::string mid(100, '\0');
    spill.readAt(mid.data(), mid.size(), 50);  // half in memory, half in the file
    CHECK(mid == data.substr(50, 100));
    // Freed up to 150: the head's memory goes; what lies past it still reads.
    spill.discardBefore(150);
    spill.readAt(mid.data(), mid.size(), 150);
    CHECK(mid == data.substr(150));
}

TEST_CASE("copc spill: within its head there is no file, and reading past what was written is one error") {
    TempDir dir("copc_spill_head");
    Spill spill(dir.path, "out.copc.laz", 1000);
    const std::string data = pattern(250);
    spill.write(data.data(), data.size());
    spill.flush();
    std::string got(20, '\0');
    spill.readAt(got.data(), got.size(), 230);
    CHECK(got == data.substr(230));
    CHECK(errorOf([&] { spill.readAt(got.data(), got.size(), 240); }) ==
          "output: out.copc.laz: reading past the spilled points");
}
