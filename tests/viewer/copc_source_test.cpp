// tests/viewer/copc_source_test.cpp: a COPC file as a point source (no GL): the tree
// known at open from the hierarchy alone, nodes decoded by the worker only when the
// selection wants them, resident bytes within the cache with the least recently wanted
// evicted first, and an unreadable node skipped while the others arrive.
#include <viewer/copc_source.hpp>
#include <viewer/node_selection.hpp>

#include "../io/copc_test_file.hpp"
#include "test_files.hpp"

#include <doctest/doctest.h>

#include <fstream>
#include <thread>

using namespace viewer;

namespace {

std::filesystem::path writeFile(const test_support::TempDir& dir, const std::string& bytes) {
    const std::filesystem::path p = dir.path / "t.copc.laz";
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
}

/// Selects for `view`, then polls until every node that choice wants is resident (the
/// worker's event; finished() latches once the first choice is all in).
void settle(CopcSource& s, const SourceView& view) {
    s.select(view);
    const NodeSelection sel =
        selectNodes(s.roots(), view.frusta, view.eye_local, {view.point_budget, s.stats()->cache_bytes});
    for (long spins = 0; spins < 100000000; ++spins) {
        s.poll();
        bool all = true;
        for (const PointNode* n : sel.wanted) all = all && (n->resident() || n->pointCount() == 0);
        if (s.finished() && all) return;
        std::this_thread::yield();
    }
    FAIL("the source never settled");
}

}  // namespace

TEST_CASE("copc source: the tree from the hierarchy, nothing decoded at open") {
    test_support::TempDir dir("copc_source_tree");
    const copc_test::File f = copc_test::make({}, true);
    CopcSource s(writeFile(dir, f.bytes), {});
    REQUIRE(s.roots().size() == 1);
    CHECK(s.nodeCount() == 73);
    std::size_t total = 0;
    for (const copc_test::Node& n : f.nodes) total += n.points.size();
    CHECK(s.totalPoints() == total);
    const PointNode* root = s.roots()[0];
    CHECK(root->children().size() == 8);
    CHECK(root->children()[0]->children().size() == 8);
    CHECK(root->bounds().size().x == doctest::Approx(128.0));
    CHECK(root->children()[3]->bounds().size().x == doctest::Approx(64.0));
    s.poll();
    CHECK(s.pointsArrived() == 0);
    CHECK(!s.finished());
    for (const PointNode* n : allNodes(s)) CHECK(!n->resident());
}

TEST_CASE("copc source: every node arrives with a large cache, points inside their cubes") {
    test_support::TempDir dir("copc_source_all");
    const copc_test::File f = copc_test::make({}, true);
    CopcSource s(writeFile(dir, f.bytes), {});
    settle(s, SourceView{{}, glm::dvec3(0.0), 0});
    CHECK(s.finished());
    CHECK(s.pointsArrived() == s.totalPoints());
    std::size_t resident = 0;
    for (const PointNode* n : allNodes(s)) {
        if (!n->resident()) continue;
        ++resident;
        CHECK(n->points()->points.size() == n->pointCount());
        core::Bounds grown = n->bounds();
        grown.lo -= glm::dvec3(0.01);
        grown.hi += glm::dvec3(0.01);
        for (const core::CloudPoint& p : n->points()->points) {
            const glm::dvec3 q(p.position);
            CHECK((q.x >= grown.lo.x && q.y >= grown.lo.y && q.z >= grown.lo.z && q.x <= grown.hi.x &&
                   q.y <= grown.hi.y && q.z <= grown.hi.z));
        }
    }
    CHECK(resident == 73);
    CHECK(s.stats()->nodes_loaded == 73);
    CHECK(s.stats()->resident_bytes <= s.stats()->cache_bytes);
}

TEST_CASE("copc source: a small cache holds the wanted nodes and evicts the least recently wanted") {
    test_support::TempDir dir("copc_source_cache");
    const copc_test::File f = copc_test::make({}, true);
    CopcSourceOptions o;
    o.cache_bytes = 12 * nodeBytes(54);  // a dozen of the 73 nodes at most
    CopcSource s(writeFile(dir, f.bytes), o);
    const glm::dvec3 near_lo = s.roots()[0]->bounds().lo + glm::dvec3(1.0);
    const glm::dvec3 near_hi = s.roots()[0]->bounds().hi - glm::dvec3(1.0);
    settle(s, SourceView{{}, near_lo, 0});
    const SourceStats first = *s.stats();
    CHECK(first.nodes_loaded > 1);
    CHECK(first.nodes_loaded < 73);
    CHECK(first.resident_bytes_peak <= o.cache_bytes);
    // The eye moves to the opposite corner: other nodes are wanted, old ones make room.
    settle(s, SourceView{{}, near_hi, 0});
    const SourceStats second = *s.stats();
    CHECK(second.nodes_evicted > 0);
    CHECK(second.resident_bytes_peak <= o.cache_bytes);
    CHECK(second.resident_bytes <= o.cache_bytes);
    const NodeSelection sel = selectNodes(s.roots(), {}, near_hi, {0, o.cache_bytes});
    for (const PointNode* n : sel.wanted) CHECK(n->resident());
}
