// tests/io/fuzz_regression_test.cpp: inputs found by the libFuzzer targets (fuzz/,
// docs/stress.md) and the fuzz seeds, replayed through the same entry points: each must
// give a result or an core::Error whose message is one printable line (the house rule
// for errors), never another exception.
#include <test_files.hpp>
#include <test_paths.hpp>
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/copc.hpp>
#include <io/scene_file.hpp>
#include <io/strict_json.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kData = test_support::dataDir();
const fs::path kRegressions = kData / "io" / "fuzz_regressions";
const fs::path kSeeds = test_support::fuzzSeedsDir();

using test_support::slurp;

/// One line of printable text: no control character, no DEL; bytes >= 0x80 only where
/// `allow_utf8` (names from JSON); short.
bool printableLine(const std::string& m, bool allow_utf8) {
    for (const char ch : m) {
        const unsigned char c = static_cast<unsigned char>(ch);
        if (c < 0x20 || c == 0x7f || (c >= 0x80 && !allow_utf8)) return false;
    }
    return m.size() < 1000;
}

/// "ok" or the core::Error's message; other exceptions escape and fail the test.
std::string readCloudOutcome(const fs::path& p) {
    try {
        io::readCloudData(slurp(p), "fuzz.pcd");
        return "ok";
    } catch (const core::Error& e) {
        return e.what();
    }
}

std::string loadSceneOutcome(const fs::path& p) {
    try {
        io::loadSceneJson(slurp(p), kData / "scenes" / "basic" / "fuzz.json");
        return "ok";
    } catch (const core::Error& e) {
        return e.what();
    }
}

}  // namespace

TEST_CASE("fuzz regression: a binary byte where a PCD header should start is not quoted at all") {
    const std::string m = readCloudOutcome(kRegressions / "cloud_message_binary_byte.pcd");
    CHECK(m ==
          "pcd: fuzz.pcd: line 1: not a PCD file (a PCD header starts with '#' comments and keywords such as "
          "VERSION or FIELDS)");
}

TEST_CASE("fuzz regression: nlohmann's 'last read' bytes are escaped in a JSON syntax error") {
    // The file starts with neither '{' nor '[': nothing of it is quoted.
    const std::string m = loadSceneOutcome(kRegressions / "scene_message_del_byte.json");
    CHECK(m.find("fuzz.json: not JSON: the text starts with neither '{' nor '['; allowed: a JSON object") !=
          std::string::npos);
    CHECK(printableLine(m, false));
    // Inside an object the bytes nlohmann last read are quoted, escaped.
    const std::string inside = test_support::errorOf(
        [] { io::loadSceneJson(std::string("{\"\x7f", 3), kData / "scenes" / "basic" / "fuzz.json"); });
    CHECK(inside.find("JSON syntax error: parse error at line 1, column ") != std::string::npos);
    CHECK(inside.find("last read: '\"\\x7f'") != std::string::npos);
    INFO(inside);
    CHECK(printableLine(inside, false));
}

TEST_CASE("fuzz regression: a newline and an escape sequence in a mesh name stay on one line") {
    const std::string m = loadSceneOutcome(kRegressions / "scene_newline_in_file_name.json");
    CHECK(m.find("meshes[0] ('no\\x0asuch\\x1b[31m.obj'): mesh file '") != std::string::npos);
    CHECK(m.find("' does not exist") != std::string::npos);
    CHECK(printableLine(m, false));
}

TEST_CASE("fuzz regression: a fault deep in nested objects names the innermost part of its path, in one short line") {
    const std::string m = loadSceneOutcome(kRegressions / "json_deep_duplicate_key.json");
    INFO(m);
    CHECK(printableLine(m, false));
    CHECK(m.find(": ...") != std::string::npos);
    CHECK(m.find("level29_") != std::string::npos);  // the innermost key is kept
    CHECK(m.find("level00_") == std::string::npos);  // the outermost is cut
    CHECK(m.find("duplicate key 'a'; allowed: each key once per object") != std::string::npos);
    // A cut never splits a character of a key: the path's bytes stay UTF-8.
    std::string deep;
    for (int i = 0; i < 30; ++i) deep += "{\"\xC3\xA9\xC3\xA9\xC3\xA9\xC3\xA9\xC3\xA9" + std::to_string(i) + "\": ";
    deep += "{\"a\": 1, \"a\": 2}" + std::string(30, '}');
    const std::string cut = test_support::errorOf([&] { io::parseStrictJson(deep, "d.json"); });
    INFO(cut);
    CHECK(cut.size() < 400);
    const std::size_t dots = cut.find("d.json: ...");
    REQUIRE(dots != std::string::npos);
    CHECK((static_cast<unsigned char>(cut[dots + 11]) & 0xC0) != 0x80);  // not a continuation byte
}

TEST_CASE("every kept fuzz input and seed: a result or a one-line core::Error") {
    int clouds = 0, scenes = 0, accepted = 0;
    for (const fs::path& dir : {kRegressions, kSeeds / "cloud", kSeeds / "scene", kSeeds / "las"}) {
        REQUIRE(fs::is_directory(dir));
        for (const auto& entry : fs::directory_iterator(dir)) {
            const fs::path& p = entry.path();
            if (p.extension() == ".md") continue;
            const bool scene = p.extension() == ".json";
            const std::string m = scene ? loadSceneOutcome(p) : readCloudOutcome(p);
            INFO(p.filename().string() << ": " << m);
            CHECK(printableLine(m, scene));
            if (m == "ok") {
                ++accepted;
            } else {
                const bool known = m.rfind("ply: ", 0) == 0 || m.rfind("las: ", 0) == 0 || m.rfind("pcd: ", 0) == 0;
                CHECK((scene ? m.rfind("scene: ", 0) == 0 : known));
            }
            (scene ? scenes : clouds) += 1;
        }
    }
    CHECK(clouds >= 10);
    CHECK(scenes >= 5);
    // Every cloud seed and two scene seeds are valid input (they seed the fuzzer's corpus).
    CHECK(accepted >= 13);
}

TEST_CASE("every COPC seed is valid COPC that reads node by node, whole and by page") {
    int seeds = 0;
    int paged = 0;
    for (const auto& entry : fs::directory_iterator(kSeeds / "copc")) {
        const fs::path& p = entry.path();
        INFO(p.filename().string());
        const std::vector<io::CopcFinding> findings = io::checkCopc(p);
        for (const io::CopcFinding& f : findings) INFO(f.rule << ": " << f.message);
        CHECK(findings.empty());
        io::CopcReader reader(p);
        std::size_t points = 0;
        for (const io::CopcNode& node : reader.nodes()) {
            const core::PointCloud cloud = reader.readNode(node.key);
            CHECK(cloud.points.size() == std::size_t(node.point_count));
            points += cloud.points.size();
        }
        CHECK(points > 0);
        // By page, as the viewer reads it: the child pages reach the same nodes.
        io::CopcReader by_page(p, io::CopcHierarchy::by_page, 4096);
        std::vector<io::CopcNode> nodes = by_page.nodes();
        std::vector<io::CopcPage> pages = by_page.pages();
        if (!pages.empty()) ++paged;
        while (!pages.empty()) {
            const io::CopcPage page = pages.back();
            pages.pop_back();
            const io::CopcPageEntries entries = by_page.readPage(page);
            nodes.insert(nodes.end(), entries.nodes.begin(), entries.nodes.end());
            pages.insert(pages.end(), entries.pages.begin(), entries.pages.end());
        }
        std::vector<io::CopcKey> keys, whole;
        for (const io::CopcNode& n : nodes) keys.push_back(n.key);
        for (const io::CopcNode& n : reader.nodes()) whole.push_back(n.key);
        std::sort(keys.begin(), keys.end());
        std::sort(whole.begin(), whole.end());
        CHECK(keys == whole);
        for (const io::CopcNode& node : nodes)
            CHECK(by_page.readNodeEntry(node, io::SideRecords::Keep).points.size() == std::size_t(node.point_count));
        ++seeds;
    }
    CHECK(seeds >= 5);
    // The fuzzer starts from files with a child page too (copc_tool's), so its mutations
    // reach the by-page reads.
    CHECK(paged >= 2);
}

TEST_CASE("shown bytes: a long binary token is cut, escaped and marked") {
    std::string pcd = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE ";
    pcd += std::string(100, '\x01');
    pcd += "\n";
    std::string m;
    try {
        io::readCloudData(pcd, "long.pcd");
    } catch (const core::Error& e) {
        m = e.what();
    }
    // At most 20 characters shown: five bytes, each as \x01, then "...".
    std::string expected = "pcd: long.pcd: line 4: SIZE '";
    for (int i = 0; i < 5; ++i) expected += "\\x01";
    expected += "...' is not one of 1, 2, 4, 8";
    CHECK(m == expected);
}
