// Tests of io::checkCopc: the hand-made valid COPC file passes; each rule, broken alone in
// a copy of it, gives that rule's finding (and only the rules that follow from it); files
// that are not COPC (our LAS and LAZ, the LAS fuzz regressions, cut files) give findings
// and never a crash.
#include <doctest/doctest.h>

#include <io/cloud_io.hpp>
#include <io/copc.hpp>

#include "copc_test_file.hpp"
#include "test_files.hpp"
#include <test_paths.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>

namespace {

using copc_test::get;
using copc_test::put;

const copc_test::File& valid() {
    static const copc_test::File f = copc_test::make();
    return f;
}

std::string shown(const std::vector<io::CopcFinding>& fs) {
    std::string s;
    for (const io::CopcFinding& f : fs) s += "\n  " + f.rule + ": " + f.message;
    return s.empty() ? "(none)" : s;
}

std::vector<io::CopcFinding> checkBytes(const std::string& bytes, const std::string& name = "t.copc.laz") {
    test_support::TempDir dir("copc_check");
    const std::filesystem::path p = dir.path / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return io::checkCopc(p);
}

// Breaks the valid file with `edit`, and expects `rule` among the findings and nothing
// outside `allowed` (which holds `rule`).
void expectRule(const char* rule, std::set<std::string> allowed, const std::function<void(std::string&)>& edit) {
    std::string b = valid().bytes;
    edit(b);
    const std::vector<io::CopcFinding> fs = checkBytes(b);
    allowed.insert(rule);
    INFO("findings:" << shown(fs));
    CHECK(std::any_of(fs.begin(), fs.end(), [&](const io::CopcFinding& f) { return f.rule == rule; }));
    for (const io::CopcFinding& f : fs) {
        CHECK_MESSAGE(allowed.count(f.rule), "unexpected rule " << f.rule);
        // The caller names the file; a finding names what in it is wrong, on one line.
        CHECK(f.message.find("t.copc.laz") == std::string::npos);
        CHECK(f.message.find('\n') == std::string::npos);
    }
}

const copc_test::Node& nodeOf(const io::CopcKey& k) {
    for (const copc_test::Node& n : valid().nodes)
        if (n.key == k) return n;
    throw std::runtime_error("no such node");
}

}  // namespace

TEST_CASE("copc check: the hand-made file is valid COPC") {
    const std::vector<io::CopcFinding> fs = checkBytes(valid().bytes);
    INFO("findings:" << shown(fs));
    CHECK(fs.empty());
}

TEST_CASE("copc check: a file of 73 nodes (a chunk table whose coder adapts) is valid COPC") {
    const std::vector<io::CopcFinding> fs = checkBytes(copc_test::make({}, true).bytes);
    INFO("findings:" << shown(fs));
    CHECK(fs.empty());
}

TEST_CASE("copc check: the LAS header rules") {
    SUBCASE("minor-version") {
        expectRule("minor-version", {"las", "chunk-decode"}, [](std::string& b) { b[25] = 3; });
    }
    SUBCASE("header-length") {
        expectRule("header-length", {"copc-info", "vlr-count", "laszip-encoded", "las", "copc-hierarchy"},
                   [](std::string& b) { put<std::uint16_t>(b, 94, 376); });
    }
    SUBCASE("point-format") {
        expectRule("point-format", {"las", "laszip-encoded"}, [](std::string& b) { b[104] = char(1 | 0x80); });
    }
    SUBCASE("laszip-encoded: a fixed chunk size") {
        expectRule("laszip-encoded", {"las"},
                   [](std::string& b) { put<std::uint32_t>(b, valid().laszip_vlr_at + 54 + 12, 50000u); });
    }
    SUBCASE("laszip-encoded: no LASzip VLR") {
        expectRule("laszip-encoded", {"las"},
                   [](std::string& b) { std::memcpy(b.data() + valid().laszip_vlr_at + 2, "laszip encodex", 14); });
    }
    SUBCASE("point-count") {
        expectRule("point-count", {"las"},
                   [](std::string& b) { put<std::uint64_t>(b, 247, get<std::uint64_t>(b, 247) + 1); });
    }
    SUBCASE("point-count-by-return") {
        expectRule("point-count-by-return", {}, [](std::string& b) {
            put<std::uint64_t>(b, 255, get<std::uint64_t>(b, 255) + 1);
            put<std::uint64_t>(b, 263, get<std::uint64_t>(b, 263) - 1);
        });
    }
    SUBCASE("legacy-point-count") {
        // The LAS reader reads a non-zero legacy count as the count.
        expectRule("legacy-point-count", {"las"}, [](std::string& b) { put<std::uint32_t>(b, 107, 5u); });
        expectRule("legacy-point-count", {}, [](std::string& b) { put<std::uint32_t>(b, 111, 7u); });
    }
    SUBCASE("header-bounds") {
        expectRule("header-bounds", {}, [](std::string& b) { put<double>(b, 179, get<double>(b, 179) - 0.5); });
    }
    SUBCASE("header-scale") {
        expectRule("header-scale", {"las"}, [](std::string& b) { put<double>(b, 131, 0.0); });
        expectRule("header-scale", {"las"}, [](std::string& b) { put<double>(b, 155 + 16, std::nan("")); });
    }
    SUBCASE("offsets: the point data past the file's end") {
        expectRule("offsets", {"las"}, [](std::string& b) { put<std::uint32_t>(b, 96, std::uint32_t(b.size() + 1)); });
    }
    SUBCASE("offsets: the first EVLR past the file's end") {
        expectRule("offsets", {"las", "copc-hierarchy"},
                   [](std::string& b) { put<std::uint64_t>(b, 235, std::uint64_t(b.size()) + 60); });
    }
    SUBCASE("offsets: an EVLR longer than what follows it") {
        expectRule("offsets", {"las", "copc-hierarchy"}, [](std::string& b) {
            const std::uint64_t at = get<std::uint64_t>(b, 235);
            put<std::uint64_t>(b, at + 20, std::uint64_t(b.size()) - at);
        });
    }
    SUBCASE("legacy counts equal to the 64-bit ones are allowed") {
        std::string b = valid().bytes;
        put<std::uint32_t>(b, 107, std::uint32_t(get<std::uint64_t>(b, 247)));
        for (std::size_t r = 0; r < 5; ++r)
            put<std::uint32_t>(b, 111 + 4 * r, std::uint32_t(get<std::uint64_t>(b, 255 + 8 * r)));
        const std::vector<io::CopcFinding> fs = checkBytes(b);
        INFO("findings:" << shown(fs));
        CHECK(fs.empty());
    }
}

TEST_CASE("copc check: the info VLR rules") {
    const std::size_t info = valid().info_at;
    SUBCASE("copc-info: missing") {
        expectRule("copc-info", {}, [&](std::string& b) { std::memcpy(b.data() + info - 54 + 2, "copx", 4); });
    }
    SUBCASE("copc-info: not the first VLR") {
        // The LASzip VLR renamed to a second info VLR: the first is still in place.
        expectRule("copc-info", {"laszip-encoded", "las"}, [](std::string& b) {
            std::memcpy(b.data() + valid().laszip_vlr_at + 2, "copc\0\0\0\0\0\0\0\0\0\0\0\0", 16);
            put<std::uint16_t>(b, valid().laszip_vlr_at + 18, 1);
        });
    }
    SUBCASE("info-reserved") {
        expectRule("info-reserved", {}, [&](std::string& b) { put<std::uint64_t>(b, info + 72 + 8 * 3, 1u); });
    }
    SUBCASE("info-values") {
        expectRule("info-values", {}, [&](std::string& b) { put<double>(b, info + 32, 0.0); });
        expectRule("info-values", {"gps-time"}, [&](std::string& b) { put<double>(b, info + 56, 2000.0); });
    }
    SUBCASE("bounds-within-cube") {
        expectRule("bounds-within-cube", {"header-bounds"},
                   [&](std::string& b) { put<double>(b, 179, copc_test::kCenter[0] + copc_test::kHalf + 1.0); });
    }
    SUBCASE("gps-time") {
        expectRule("gps-time", {}, [&](std::string& b) { put<double>(b, info + 64, copc_test::kGpsMin + 5.0); });
    }
}

TEST_CASE("copc check: the hierarchy rules") {
    const copc_test::File& v = valid();
    SUBCASE("copc-hierarchy") {
        expectRule("copc-hierarchy", {}, [&](std::string& b) { put<std::uint16_t>(b, v.evlr_at + 18, 1001); });
    }
    SUBCASE("hierarchy-page: root page size not a multiple of 32") {
        expectRule("hierarchy-page", {"hierarchy-dead-space", "point-count", "chunk-unreferenced"},
                   [&](std::string& b) { put<std::uint64_t>(b, v.info_at + 48, 100u); });
    }
    SUBCASE("hierarchy-page: a child page outside the hierarchy EVLR") {
        expectRule("hierarchy-page", {"hierarchy-dead-space", "point-count", "chunk-unreferenced"},
                   [&](std::string& b) { put<std::uint64_t>(b, v.pointer_entry_at + 16, 400u); });
    }
    SUBCASE("hierarchy-page: a child page overlapping the root page") {
        expectRule("hierarchy-page", {"hierarchy-dead-space", "point-count", "chunk-unreferenced"},
                   [&](std::string& b) { put<std::uint64_t>(b, v.pointer_entry_at + 16, v.root_page_at + 32); });
    }
    SUBCASE("hierarchy-dead-space: a child page shorter than its bytes") {
        expectRule("hierarchy-dead-space", {"point-count", "chunk-unreferenced"},
                   [&](std::string& b) { put<std::int32_t>(b, v.pointer_entry_at + 24, 64); });
    }
    SUBCASE("hierarchy-dead-space: bytes after the last page") {
        expectRule("hierarchy-dead-space", {}, [&](std::string& b) {
            put<std::uint64_t>(b, v.evlr_at + 20, get<std::uint64_t>(b, v.evlr_at + 20) + 32);
            b.append(32, '\0');
        });
    }
    SUBCASE("node-key: a cell beyond its level") {
        expectRule("node-key", {"point-count", "chunk-unreferenced"},
                   [&](std::string& b) { put<std::int32_t>(b, nodeOf({1, 1, 0, 0}).entry_at + 4, 2); });
    }
    SUBCASE("node-key: no parent") {
        expectRule("node-key", {"xyz"}, [&](std::string& b) {
            const std::size_t e = nodeOf({2, 3, 3, 3}).entry_at;
            put<std::int32_t>(b, e + 4, 2);
            put<std::int32_t>(b, e + 8, 0);
        });
    }
    SUBCASE("node-key: two entries of one key") {
        expectRule("node-key", {"point-count", "chunk-unreferenced"},
                   [&](std::string& b) { put<std::int32_t>(b, nodeOf({1, 1, 0, 0}).entry_at + 4, 0); });
    }
    SUBCASE("hierarchy-entry: an empty node with an offset") {
        expectRule("hierarchy-entry", {}, [&](std::string& b) { put<std::uint64_t>(b, v.empty_entry_at + 16, 5u); });
    }
    SUBCASE("node-chunk: a byte size not that of the chunk") {
        expectRule("node-chunk", {}, [&](std::string& b) {
            const std::size_t e = nodeOf({1, 0, 0, 0}).entry_at;
            put<std::int32_t>(b, e + 24, get<std::int32_t>(b, e + 24) - 1);
        });
    }
    SUBCASE("node-chunk: an offset inside a chunk") {
        expectRule("node-chunk", {"chunk-unreferenced"}, [&](std::string& b) {
            const std::size_t e = nodeOf({1, 0, 0, 0}).entry_at;
            put<std::uint64_t>(b, e + 16, get<std::uint64_t>(b, e + 16) + 4);
            put<std::int32_t>(b, e + 24, get<std::int32_t>(b, e + 24) - 4);
        });
    }
    SUBCASE("node-chunk: an offset outside the file") {
        expectRule("node-chunk", {"chunk-unreferenced", "point-count"}, [&](std::string& b) {
            put<std::uint64_t>(b, nodeOf({2, 0, 2, 0}).entry_at + 16, std::uint64_t(1) << 40);
        });
    }
    SUBCASE("chunk-unreferenced") {
        expectRule("chunk-unreferenced", {"point-count"}, [&](std::string& b) {
            const std::size_t e = nodeOf({2, 3, 3, 3}).entry_at;
            put<std::uint64_t>(b, e + 16, 0u);
            put<std::int32_t>(b, e + 24, 0);
            put<std::int32_t>(b, e + 28, 0);
        });
    }
    SUBCASE("chunk-table: a count beyond the chunks") {
        expectRule("chunk-table", {"las", "node-chunk", "chunk-unreferenced"},
                   [&](std::string& b) { put<std::uint32_t>(b, v.table_at + 4, 8u); });
    }
    SUBCASE("chunk-table: its place outside the file") {
        expectRule("chunk-table", {"las"},
                   [&](std::string& b) { put<std::int64_t>(b, v.data_at, std::int64_t(b.size()) + 100); });
    }
}

TEST_CASE("copc check: the point rules") {
    SUBCASE("xyz: two nodes' keys swapped") {
        expectRule("xyz", {}, [](std::string& b) {
            const std::size_t a = nodeOf({1, 0, 0, 0}).entry_at, c = nodeOf({1, 1, 0, 0}).entry_at;
            put<std::int32_t>(b, a + 4, 1);
            put<std::int32_t>(b, c + 4, 0);
        });
    }
    SUBCASE("return-number") {
        copc_test::File f = copc_test::make([](std::vector<copc_test::Node>& nodes) {
            nodes[1].points[3].return_number = 3;
            nodes[1].points[3].returns = 2;
        });
        const std::vector<io::CopcFinding> fs = checkBytes(f.bytes);
        INFO("findings:" << shown(fs));
        REQUIRE(fs.size() == 1);
        CHECK(fs[0].rule == "return-number");
        CHECK(fs[0].message.find("node 1-0-0-0") != std::string::npos);
        CHECK(fs[0].message.find("point 3, return 3 of 2") != std::string::npos);
    }
    SUBCASE("chunk-decode: layer sizes beyond the chunk") {
        expectRule("chunk-decode", {"las"}, [](std::string& b) {
            // After the chunk's raw first point (36 bytes) and its point count.
            put<std::uint32_t>(b, nodeOf({1, 1, 0, 0}).chunk_at + 36 + 4, 0x7FFFFFFFu);
        });
    }
}

TEST_CASE("copc check: files that are not COPC give findings, never a crash") {
    test_support::TempDir dir("copc_check_foreign");
    SUBCASE("not LAS at all") {
        CHECK(checkBytes("hello\n").front().rule == "not-las");
        CHECK(checkBytes("").front().rule == "not-las");
        const std::vector<io::CopcFinding> fs = io::checkCopc(dir.path / "missing.copc.laz");
        REQUIRE(fs.size() == 1);
        CHECK(fs[0].rule == "not-las");
        CHECK(fs[0].message == "file does not exist");
    }
    SUBCASE("our LAS and LAZ, and the LAS fuzz regressions") {
        core::PointCloud c;
        c.origin = {1000.0, 2000.0, 0.0};
        for (int i = 0; i < 100; ++i) {
            core::CloudPoint p;
            p.position = {float(i), float(i % 7), 1.0f};
            c.points.push_back(p);
        }
        std::vector<std::filesystem::path> files = {dir.path / "c.las", dir.path / "c.laz"};
        io::writeCloud(files[0], c, io::CloudFormat::Las);
        io::writeCloud(files[1], c, io::CloudFormat::Laz);
        for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(test_support::dataDir()) / "io" /
                                                                 "fuzz_regressions"))
            if (e.path().extension() == ".las" || e.path().extension() == ".laz") files.push_back(e.path());
        for (const auto& p : files) {
            const std::vector<io::CopcFinding> fs = io::checkCopc(p);
            INFO(p.string() << ":" << shown(fs));
            CHECK(std::any_of(fs.begin(), fs.end(), [](const io::CopcFinding& f) { return f.rule == "copc-info"; }));
        }
    }
    SUBCASE("the valid file cut short anywhere") {
        const std::string& b = valid().bytes;
        for (std::size_t cut = 0; cut < b.size(); cut += 1 + cut / 8) {
            const std::vector<io::CopcFinding> fs = checkBytes(b.substr(0, cut));
            INFO("cut at " << cut << ":" << shown(fs));
            CHECK(!fs.empty());
        }
    }
}

TEST_CASE("copc check: a cube too large to compute with is refused by its rule, with no nan") {
    const std::size_t info = valid().info_at;
    // A halfsize whose double overflows: every node's cube would be nan.
    expectRule("info-values", {}, [&](std::string& b) { put<double>(b, info + 24, 1e308); });
    // A cube past the world coordinates, on one axis.
    expectRule("info-values", {}, [&](std::string& b) { put<double>(b, info + 8, 2e9); });
    std::string b = valid().bytes;
    put<double>(b, info + 24, 1e308);
    const std::vector<io::CopcFinding> fs = checkBytes(b);
    INFO("findings:" << shown(fs));
    REQUIRE(fs.size() == 1);
    CHECK(fs[0].message ==
          "the info VLR's cube reaches x = 500064 +- 1e+308; allowed: |centre| + halfsize <= 1000000000 m (world "
          "coordinates)");
    for (const io::CopcFinding& f : fs) CHECK(f.message.find("nan") == std::string::npos);
    // The reader refuses it too: no node of it is read with a cube of nan.
    test_support::TempDir dir("copc_check_cube");
    const std::filesystem::path p = dir.path / "t.copc.laz";
    std::ofstream(p, std::ios::binary) << b;
    CHECK(test_support::errorOf([&] {
              io::CopcReader r(p, io::CopcHierarchy::by_page);
          }).find("info-values: the info VLR's cube reaches x") != std::string::npos);
}
