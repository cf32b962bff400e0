// tests/viewer/points/copc_source_test.cpp: a COPC file as a point source (no GL): the tree
// known at open from the hierarchy alone, nodes decoded by the worker only when the
// selection wants them, resident bytes within the cache with the least recently wanted
// evicted first, and an unreadable node skipped while the others arrive; a file from
// elsewhere's 8-bit colours and classes reach the points as a streamed file's do.
#include <viewer/copc_source.hpp>
#include <viewer/node_selection.hpp>

#include "../../io/copc_test_file.hpp"
#include "test_files.hpp"

#include <io/cloud_io.hpp>

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

namespace {

/// The hand-made file with its root page replaced: the page's first five entries (the
/// nodes 0-0-0-0, 1-0-0-0, 1-1-0-0, 2-3-3-3 and the empty 1-1-1-1; no child page) and
/// `extra` after them, the cube's halfsize set to `halfsize_m`.
std::string withRootPage(const std::string& extra, double halfsize_m = copc_test::kHalf) {
    const copc_test::File f = copc_test::make();
    std::string b = f.bytes.substr(0, f.root_page_at + 5 * 32) + extra;
    copc_test::put<std::uint64_t>(b, f.evlr_at + 20, 5 * 32 + extra.size());
    copc_test::put<std::uint64_t>(b, f.info_at + 48, 5 * 32 + extra.size());
    copc_test::put<double>(b, f.info_at + 24, halfsize_m);
    return b;
}

/// `n` entries of level `level`, their keys spread over the level so that their ancestors
/// differ below the first few levels; with no points, or each with the first node's chunk.
std::string spreadEntries(int n, int level, bool with_points) {
    const copc_test::File f = copc_test::make();
    const copc_test::Node& chunk = f.nodes[0];
    // Odd multipliers modulo 2^level: distinct keys, their high bits (the ancestors) mixed.
    const std::uint64_t mask = (std::uint64_t(1) << level) - 1;
    std::string out;
    for (int i = 0; i < n; ++i) {
        const std::uint64_t u = std::uint64_t(i);
        const io::CopcKey k{level, std::int32_t((u * 0x9E3779B1u) & mask), std::int32_t((u * 0x85EBCA77u) & mask),
                            std::int32_t((u * 0xC2B2AE3Du) & mask)};
        out += with_points ? copc_test::entry(k, chunk.chunk_at, std::int32_t(chunk.chunk_bytes),
                                              std::int32_t(chunk.points.size()))
                           : copc_test::entry(k, 0, 0, 0);
    }
    return out;
}

// A cube 2^13 times wider than the hand-made one: at a scale of 1 mm its cells resolve all
// 30 levels of COPC's keys.
constexpr double kWideHalf_m = copc_test::kHalf * 8192.0;

}  // namespace

TEST_CASE("copc source: entries with no points make no nodes, however many and deep") {
    test_support::TempDir dir("copc_source_empty");
    CopcSourceOptions o;
    o.quiet = true;
    CopcSource s(writeFile(dir, withRootPage(spreadEntries(20000, 30, false), kWideHalf_m)), o);
    // The four nodes with points and 1-1-1-1 above 2-3-3-3; not one node per empty entry
    // and its ancestors (about 27 each).
    CHECK(s.nodeCount() == 5);
    CHECK(s.stats()->hierarchy_bytes < 4096);
}

TEST_CASE("copc source: a root page past the hierarchy's bound is refused in one line") {
    test_support::TempDir dir("copc_source_bound");
    // 750 nodes with points at level 30 make about 27 nodes each; 4 MiB holds a few
    // thousand nodes, and pages of at most 819 entries with one worker.
    const std::filesystem::path p = writeFile(dir, withRootPage(spreadEntries(750, 30, true), kWideHalf_m));
    CopcSourceOptions o;
    o.quiet = true;
    o.workers = 1;
    o.hierarchy_bytes = std::size_t(4) << 20;
    const std::string m = test_support::errorOf([&] { CopcSource s(p, o); });
    INFO(m);
    CHECK(m.rfind("copc: " + p.string() +
                      ": the root hierarchy page: its 754 entries with points or child pages "
                      "would take the tree past ",
                  0) == 0);
    CHECK(m.find("allowed the hierarchy's 4 MiB (--memory-mb)") != std::string::npos);
    CHECK(m.find('\n') == std::string::npos);
    // A page of more entries than a quarter of the bound holds is refused by the reader
    // before its nodes are counted.
    const std::filesystem::path q = writeFile(dir, withRootPage(spreadEntries(2000, 30, true), kWideHalf_m));
    const std::string big = test_support::errorOf([&] { CopcSource s(q, o); });
    CHECK(big.find("hierarchy-page: the root hierarchy page has 2005 entries; allowed at most 819 in one page (its "
                   "share of the hierarchy's 4 MiB, --memory-mb)") != std::string::npos);
    // Within the default bound the same file opens, its tree counted in full.
    o.hierarchy_bytes = CopcSourceOptions{}.hierarchy_bytes;
    CopcSource s(p, o);
    CHECK(s.nodeCount() > 750 * 20);
    CHECK(s.stats()->hierarchy_bytes <= o.hierarchy_bytes);
}

TEST_CASE("copc source: nodes below the levels the cube resolves are refused") {
    test_support::TempDir dir("copc_source_depth");
    // A cube of halfsize 64 m at a scale of 1 mm: level 17's cells are under 1 mm wide.
    CopcSourceOptions o;
    o.quiet = true;
    CopcSource ok(writeFile(dir, withRootPage(spreadEntries(1, 17, true))), o);
    CHECK(ok.nodeCount() == 5 + 16);  // 2-0-0-0 to 17-0-0-0 below 1-0-0-0
    const std::filesystem::path p = writeFile(dir, withRootPage(spreadEntries(1, 18, true)));
    const std::string m = test_support::errorOf([&] { CopcSource s(p, o); });
    CHECK(m == "copc: " + p.string() +
                   ": the root hierarchy page: node 18-0-0-0 is at level 18; allowed levels 0 to 17 (deeper cells of "
                   "its cube of halfsize 64 m are narrower than the file's coordinate step)");
}

TEST_CASE("copc source: a child page past the hierarchy's bound is left out, the rest arrives") {
    test_support::TempDir dir("copc_source_child_bound");
    // The child page of 1-0-1-0 (last in the file) grown by 750 nodes with points at level
    // 30 inside its subtree, in a cube wide enough to resolve them: about 26 new nodes each.
    const copc_test::File f = copc_test::make();
    std::string b = f.bytes;
    const copc_test::Node& chunk = f.nodes[0];
    const std::uint64_t half = std::uint64_t(1) << 29;
    for (std::uint64_t i = 1; i <= 750; ++i) {
        const io::CopcKey k{30, std::int32_t((i * 0x9E3779B1u) % half), std::int32_t(half + (i * 0x85EBCA77u) % half),
                            std::int32_t((i * 0xC2B2AE3Du) % half)};
        b += copc_test::entry(k, chunk.chunk_at, std::int32_t(chunk.chunk_bytes), std::int32_t(chunk.points.size()));
    }
    copc_test::put<std::int32_t>(b, f.pointer_entry_at + 24, std::int32_t(f.child_page_size + 750 * 32));
    copc_test::put<std::uint64_t>(b, f.evlr_at + 20, copc_test::get<std::uint64_t>(b, f.evlr_at + 20) + 750 * 32);
    copc_test::put<double>(b, f.info_at + 24, kWideHalf_m);
    CopcSourceOptions o;
    o.quiet = true;
    o.workers = 1;
    o.hierarchy_bytes = std::size_t(4) << 20;
    CopcSource s(writeFile(dir, b), o);
    const std::size_t at_open = s.nodeCount();
    settlePaged(s, SourceView{{}, glm::dvec3(0.0), 0});
    CHECK(s.stats()->pages_failed == 1);
    CHECK(s.stats()->pages_unread == 0);
    CHECK(s.nodeCount() == at_open);  // none of the page's nodes made
    CHECK(s.stats()->hierarchy_bytes <= o.hierarchy_bytes);
    CHECK(s.pointsArrived() > 0);  // the root page's nodes are drawn
}

TEST_CASE("copc source: a file from elsewhere shows its 8-bit colours and carries its classes to the colour modes") {
    test_support::TempDir dir("copc_source_foreign");
    core::PointCloud cloud;
    cloud.origin = {400000.0, 6000000.0, 50.0};
    cloud.fields = core::CloudFields{};
    cloud.fields.label = cloud.fields.view = cloud.fields.range = false;
    cloud.fields.intensity = cloud.fields.returns = true;
    cloud.foreign.emplace();
    cloud.foreign->header.point_format = 7;
    const std::uint8_t classes[3] = {2, 5, 6};
    for (int i = 0; i < 300; ++i) {
        core::CloudPoint p;
        p.position = {float(i % 20), float(i / 20), float(i % 7)};
        cloud.points.push_back(p);
        core::ForeignPoint f;
        f.rgb[0] = 200;  // 8-bit values in the 16-bit fields
        f.rgb[1] = 180;
        f.rgb[2] = 40;
        f.classification = classes[i % 3];
        const auto* bytes = reinterpret_cast<const unsigned char*>(&f);
        cloud.foreign->records.insert(cloud.foreign->records.end(), bytes, bytes + sizeof f);
    }
    const std::filesystem::path file = dir.path / "survey.copc.laz";
    io::writeCloud(file, cloud, io::CloudFormat::Copc);
    CopcSource s(file, {});
    settle(s, SourceView{{}, glm::dvec3(0.0), 0});
    std::size_t seen = 0, by_class[256] = {};
    for (const PointNode* n : allNodes(s))
        if (const auto points = n->points())
            for (const core::CloudPoint& p : points->points) {
                ++seen;
                CHECK(p.rgb == core::packRgb(200, 180, 40));
                ++by_class[std::uint32_t(p.height_above_ground_m) & 0xFFu];  // point_attributes.hpp
            }
    CHECK(seen == 300);
    CHECK(by_class[2] == 100);
    CHECK(by_class[5] == 100);
    CHECK(by_class[6] == 100);
}
