// tests/viewer/copc_source_test.cpp: a COPC file as a point source (no GL): the tree
// known at open from the hierarchy alone, nodes decoded by the worker only when the
// selection wants them, resident bytes within the cache with the least recently wanted
// evicted first, and an unreadable node skipped while the others arrive.
#include <viewer/copc_source.hpp>
#include <viewer/node_selection.hpp>

#include "../io/copc_test_file.hpp"
#include "test_files.hpp"

#include <doctest/doctest.h>

#include <algorithm>
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

/// Selects and polls until a choice is all resident with no page it reached unread
/// (finished(), the worker's event), selecting each round as the frame loop does, so
/// that pages read open the tree below them.
void settlePaged(CopcSource& s, const SourceView& view) {
    for (long spins = 0; spins < 100000000; ++spins) {
        s.select(view);
        s.poll();
        if (s.finished() && s.pagesWanted() == 0) return;
        std::this_thread::yield();
    }
    FAIL("the source never settled");
}

/// A frustum that is the axis-aligned box `b` (normals inwards).
render::Frustum boxFrustum(const core::Bounds& b) {
    render::Frustum f;
    f.planes[0] = glm::dvec4(1, 0, 0, -b.lo.x);
    f.planes[1] = glm::dvec4(-1, 0, 0, b.hi.x);
    f.planes[2] = glm::dvec4(0, 1, 0, -b.lo.y);
    f.planes[3] = glm::dvec4(0, -1, 0, b.hi.y);
    f.planes[4] = glm::dvec4(0, 0, 1, -b.lo.z);
    f.planes[5] = glm::dvec4(0, 0, -1, b.hi.z);
    return f;
}

}  // namespace

TEST_CASE("copc source: the hierarchy read page by page, a page only when the view reaches it") {
    test_support::TempDir dir("copc_source_pages");
    const copc_test::File f = copc_test::make();  // a root page and the child page of 1-0-1-0
    std::size_t total = 0, in_child = 0;
    for (const copc_test::Node& n : f.nodes) {
        total += n.points.size();
        if (n.entry_at >= f.child_page_at) in_child += n.points.size();
    }
    REQUIRE(in_child > 0);
    {
        CopcSource s(writeFile(dir, f.bytes), {});
        // At open: the root page's keys and their ancestors (0-0-0-0, 1-0-0-0, 1-1-0-0,
        // 1-1-1-1, 2-3-3-3) and the unexplored 1-0-1-0; the points are the header's.
        CHECK(s.nodeCount() == 6);
        CHECK(s.totalPoints() == total);
        CHECK(s.stats()->pages_read == 1);
        CHECK(s.stats()->pages_unread == 1);
        const auto nodes = allNodes(s);
        const auto unexplored =
            std::count_if(nodes.begin(), nodes.end(), [](const PointNode* n) { return n->unexplored(); });
        CHECK(unexplored == 1);
        // A view of the 1-1-0-0 octant alone reads no page, and settles.
        core::Bounds octant = s.roots()[0]->bounds();
        octant.lo += glm::dvec3(65.0, 1.0, 1.0);
        octant.hi = octant.lo + glm::dvec3(62.0);
        settlePaged(s, SourceView{{boxFrustum(octant)}, octant.lo, 0});
        CHECK(s.stats()->pages_read == 1);
        CHECK(s.pointsArrived() < total - in_child + 1);
    }
    // The whole view: the page is read, the nodes it lists join the tree and arrive.
    CopcSource s(writeFile(dir, f.bytes), {});
    settlePaged(s, SourceView{{}, glm::dvec3(0.0), 0});
    CHECK(s.stats()->pages_read == 2);
    CHECK(s.stats()->pages_unread == 0);
    CHECK(s.nodeCount() == 8);
    CHECK(s.pointsArrived() == total);
    for (const PointNode* n : allNodes(s)) {
        CHECK(!n->unexplored());
        if (n->pointCount() > 0) CHECK(n->resident());
    }
    CHECK(s.stats()->hierarchy_bytes > 0);
}

TEST_CASE("copc source: a child page that does not read leaves its subtree out, the rest arrives") {
    test_support::TempDir dir("copc_source_bad_page");
    const copc_test::File f = copc_test::make();
    std::string b = f.bytes;
    // The child page's first entry moved outside its subtree (a broken node-key rule).
    std::size_t in_child = 0, total = 0;
    for (const copc_test::Node& n : f.nodes) {
        total += n.points.size();
        if (n.entry_at >= f.child_page_at) in_child += n.points.size();
    }
    copc_test::put<std::int32_t>(b, f.child_page_at + 4, 1);
    CopcSourceOptions o;
    o.quiet = true;
    CopcSource s(writeFile(dir, b), o);
    settlePaged(s, SourceView{{}, glm::dvec3(0.0), 0});
    CHECK(s.stats()->pages_failed == 1);
    CHECK(s.stats()->pages_unread == 0);
    CHECK(s.pointsArrived() == total - in_child);
    for (const PointNode* n : allNodes(s)) CHECK(!n->unexplored());
}

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
    // The header gives the local frame: candidate boxes can be placed before any node is in.
    CHECK(s.originFinal());
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

TEST_CASE("copc source: several workers read the same pages and nodes as one") {
    test_support::TempDir dir("copc_source_workers");
    for (const bool many : {true, false}) {
        const copc_test::File f = copc_test::make({}, many);
        const std::filesystem::path path = writeFile(dir, f.bytes);
        CopcSourceOptions one, three;
        one.workers = 1;
        three.workers = 3;
        CopcSource a(path, one), b(path, three);
        settlePaged(a, SourceView{{}, glm::dvec3(0.0), 0});
        settlePaged(b, SourceView{{}, glm::dvec3(0.0), 0});
        CHECK(b.pointsArrived() == b.totalPoints());
        CHECK(b.stats()->nodes_loaded == a.stats()->nodes_loaded);
        const auto na = allNodes(a), nb = allNodes(b);
        REQUIRE(na.size() == nb.size());
        for (std::size_t i = 0; i < na.size(); ++i) {
            CHECK(na[i]->bounds().lo == nb[i]->bounds().lo);
            REQUIRE(na[i]->resident() == nb[i]->resident());
            if (!na[i]->resident()) continue;
            const auto& pa = na[i]->points()->points;
            const auto& pb = nb[i]->points()->points;
            REQUIRE(pa.size() == pb.size());
            CHECK(
                std::equal(pa.begin(), pa.end(), pb.begin(), [](const core::CloudPoint& x, const core::CloudPoint& y) {
                    return x.position == y.position && x.rgb == y.rgb;
                }));
        }
    }
}
