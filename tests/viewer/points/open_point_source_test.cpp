// Tests of viewer::choosePath and viewer::openPointSource: a COPC file is read node by node,
// another cloud file through its index when the indexer wants one and whole otherwise, and
// an index that does not open is asked for again once.
#include <viewer/open_point_source.hpp>

#include <core/error.hpp>

#include "../../io/copc_test_file.hpp"
#include "test_files.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <string>
#include <thread>
#include <vector>

using namespace viewer;

namespace {

std::filesystem::path writeFile(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
}

/// An indexer that answers from a script: whether it wants an index, and the index to give
/// on each call (recording the failures it was told of).
struct ScriptedIndexer final : CloudIndexer {
    bool wants = false;
    std::vector<std::filesystem::path> answers;
    std::vector<std::string> failures;
    bool wantsIndex(const std::filesystem::path&) override { return wants; }
    std::filesystem::path index(const std::filesystem::path&, const std::string& failed_open) override {
        failures.push_back(failed_open);
        if (answers.empty()) return {};
        std::filesystem::path next = answers.front();
        answers.erase(answers.begin());
        return next;
    }
};

}  // namespace

TEST_CASE("open point source: the path a file takes") {
    test_support::TempDir dir("open_source_path");
    const std::filesystem::path copc = writeFile(dir.path / "a.copc.laz", copc_test::make().bytes);
    const std::filesystem::path other = writeFile(dir.path / "b.pcd", "not a cloud");
    ScriptedIndexer indexer;
    CHECK(choosePath(copc, nullptr) == SourcePath::Copc);
    CHECK(choosePath(other, nullptr) == SourcePath::Whole);
    CHECK(choosePath(other, &indexer) == SourcePath::Whole);
    indexer.wants = true;
    CHECK(choosePath(other, &indexer) == SourcePath::Indexed);
    CHECK(choosePath(copc, &indexer) == SourcePath::Copc);  // a COPC file is never indexed
    // Every point needed (a study's hits): streamed whole, COPC or not, never indexed.
    CHECK(choosePath(copc, &indexer, EveryPoint::Needed) == SourcePath::Whole);
    CHECK(choosePath(other, &indexer, EveryPoint::Needed) == SourcePath::Whole);
    CHECK(indexer.failures.empty());  // choosing writes nothing
}

TEST_CASE("open point source: COPC node by node, another file streamed whole") {
    test_support::TempDir dir("open_source_open");
    const copc_test::File f = copc_test::make();
    const std::filesystem::path copc = writeFile(dir.path / "a.copc.laz", f.bytes);
    OpenSourceOptions o;
    OpenedCloud c = openPointSource(copc, SourcePath::Copc, o);
    REQUIRE(c.copc);
    CHECK_FALSE(c.feed);
    CHECK(c.file == copc);
    CHECK(c.copc->nodeCount() > 0);

    const std::filesystem::path missing = dir.path / "missing.pcd";
    OpenedCloud w = openPointSource(missing, SourcePath::Whole, o);
    REQUIRE(w.feed);
    CHECK_FALSE(w.copc);
    CHECK(w.file == missing);
    // The loader's error comes through the feed, not as a throw.
    for (long spins = 0; spins < 100000000 && !w.feed->finished(); ++spins) std::this_thread::yield();
    CHECK(w.feed->finished());
    CHECK_FALSE(w.feed->error().empty());
}

TEST_CASE("open point source: an index that does not open is asked for once more") {
    test_support::TempDir dir("open_source_index");
    const std::filesystem::path cloud = writeFile(dir.path / "big.pcd", "points");
    const std::filesystem::path good = writeFile(dir.path / "good.copc.laz", copc_test::make().bytes);
    const std::filesystem::path damaged = writeFile(dir.path / "damaged.copc.laz", "LASF and nothing else");
    ScriptedIndexer indexer;
    indexer.wants = true;
    OpenSourceOptions o;
    o.indexer = &indexer;

    indexer.answers = {damaged, good};
    OpenedCloud c = openPointSource(cloud, SourcePath::Indexed, o);
    REQUIRE(c.copc);
    CHECK(c.file == good);
    REQUIRE(indexer.failures.size() == 2);
    CHECK(indexer.failures[0].empty());
    CHECK(indexer.failures[1].find("damaged.copc.laz") != std::string::npos);

    // The indexer gives up: the index's own error is thrown.
    indexer.failures.clear();
    indexer.answers = {damaged};
    CHECK_THROWS_WITH_AS(openPointSource(cloud, SourcePath::Indexed, o), doctest::Contains("damaged.copc.laz"),
                         core::Error);
    CHECK(indexer.failures.size() == 2);

    // No indexer for the Indexed path: one line, no crash.
    o.indexer = nullptr;
    CHECK_THROWS_AS(openPointSource(cloud, SourcePath::Indexed, o), core::Error);
}
