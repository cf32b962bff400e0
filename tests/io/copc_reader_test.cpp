// Tests of io::CopcReader on the hand-made COPC file: the info and every node as written,
// each node's points decoded alone and equal to what was compressed, the whole file read
// as a plain LAZ (LASzip through the variable chunk table), and one-line errors.
#include <doctest/doctest.h>

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/copc.hpp>

#include "copc_test_file.hpp"
#include "test_files.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

namespace {

std::filesystem::path writeFile(const test_support::TempDir& dir, const std::string& bytes) {
    const std::filesystem::path p = dir.path / "t.copc.laz";
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
}

}  // namespace

TEST_CASE("copc reader: info, nodes and every node's points") {
    test_support::TempDir dir("copc_reader");
    const copc_test::File f = copc_test::make();
    const io::CopcReader reader(writeFile(dir, f.bytes));
    const io::CopcInfo& info = reader.info();
    CHECK(info.center_m[0] == copc_test::kCenter[0]);
    CHECK(info.center_m[1] == copc_test::kCenter[1]);
    CHECK(info.center_m[2] == copc_test::kCenter[2]);
    CHECK(info.halfsize_m == copc_test::kHalf);
    CHECK(info.spacing_m == 1.0);
    CHECK(info.root_hier_offset == f.root_page_at);
    CHECK(info.root_hier_size == f.root_page_size);
    CHECK(info.gpstime_minimum == copc_test::kGpsMin);
    CHECK(info.gpstime_maximum == copc_test::kGpsMax);

    const std::vector<io::CopcNode>& nodes = reader.nodes();
    REQUIRE(nodes.size() == f.nodes.size());
    CHECK(std::is_sorted(nodes.begin(), nodes.end(), [](const auto& a, const auto& b) { return a.key < b.key; }));
    std::size_t total = 0;
    for (const copc_test::Node& want : f.nodes) {
        const auto it =
            std::find_if(nodes.begin(), nodes.end(), [&](const io::CopcNode& n) { return n.key == want.key; });
        REQUIRE(it != nodes.end());
        CHECK(it->offset == want.chunk_at);
        CHECK(std::size_t(it->byte_size) == want.chunk_bytes);
        REQUIRE(std::size_t(it->point_count) == want.points.size());
        const core::PointCloud cloud = reader.readNode(want.key);
        REQUIRE(cloud.points.size() == want.points.size());
        CHECK(cloud.origin == reader.origin());  // known before any node is read
        CHECK(cloud.fields.rgb);
        for (std::size_t i = 0; i < want.points.size(); ++i) {
            const copc_test::RawPoint& r = want.points[i];
            const core::CloudPoint& p = cloud.points[i];
            const std::int32_t raw[3] = {r.X, r.Y, r.Z};
            for (int k = 0; k < 3; ++k) {
                const double w = cloud.origin[k] + double(p.position[k]);
                CHECK(std::abs(w - (double(raw[k]) * copc_test::kScale + copc_test::kOffset[k])) < 1e-4);
            }
            CHECK(p.view == r.source);
            CHECK(p.intensity == r.intensity);
            CHECK(p.return_number == r.return_number);
            CHECK(p.returns == r.returns);
            const core::Role role = r.classification == 2    ? core::Role::Ground
                                    : r.classification == 64 ? core::Role::Target
                                                             : core::Role::Environment;
            CHECK(p.label == role);
            CHECK(p.rgb ==
                  core::packRgb(std::uint8_t(r.rgb[0] >> 8), std::uint8_t(r.rgb[1] >> 8), std::uint8_t(r.rgb[2] >> 8)));
        }
        total += cloud.points.size();
    }
    // One origin for every node: the file's.
    CHECK(reader.readNode({0, 0, 0, 0}).origin == reader.readNode({2, 3, 3, 3}).origin);

    // The same file read whole as LAZ: LASzip follows the variable chunk table.
    const core::PointCloud whole = io::readCloud(dir.path / "t.copc.laz");
    CHECK(whole.points.size() == total);
}

TEST_CASE("copc reader: header bounds far from the cube give way to the cube's frame") {
    // Zeros (a writer that left them) and NaN: the frame comes from the info VLR's cube,
    // the same for the reader and every node, and the points keep their millimetres.
    for (const double bad : {0.0, std::nan("")}) {
        CAPTURE(bad);
        test_support::TempDir dir("copc_reader_bounds");
        copc_test::File f = copc_test::make();
        const io::CopcReader good(writeFile(dir, f.bytes));
        const glm::dvec3 framed = good.origin();
        for (std::size_t at = 179; at < 227; at += 8) std::memcpy(f.bytes.data() + at, &bad, sizeof bad);
        const io::CopcReader reader(writeFile(dir, f.bytes));
        CHECK(reader.origin() == glm::dvec3(copc_test::kCenter[0], copc_test::kCenter[1], 0.0));
        CHECK(std::abs(reader.origin().x - framed.x) < 2.0 * copc_test::kHalf);
        for (const copc_test::Node& want : f.nodes) {
            const core::PointCloud cloud = reader.readNode(want.key);
            REQUIRE(cloud.points.size() == want.points.size());
            CHECK(cloud.origin == reader.origin());
            for (std::size_t i = 0; i < want.points.size(); ++i) {
                const std::int32_t raw[3] = {want.points[i].X, want.points[i].Y, want.points[i].Z};
                for (int k = 0; k < 3; ++k)
                    CHECK(std::abs(cloud.origin[k] + double(cloud.points[i].position[k]) -
                                   (double(raw[k]) * copc_test::kScale + copc_test::kOffset[k])) < 1e-4);
            }
        }
    }
}

TEST_CASE("copc reader: 73 nodes in one page, read alone and whole") {
    test_support::TempDir dir("copc_reader_many");
    const copc_test::File f = copc_test::make({}, true);
    const io::CopcReader reader(writeFile(dir, f.bytes));
    REQUIRE(reader.nodes().size() == 73);
    std::size_t total = 0;
    for (const copc_test::Node& want : f.nodes) {
        const core::PointCloud cloud = reader.readNode(want.key);
        REQUIRE(cloud.points.size() == want.points.size());
        const copc_test::RawPoint& r = want.points.back();
        CHECK(std::abs(cloud.origin.x + double(cloud.points.back().position.x) -
                       (double(r.X) * copc_test::kScale + copc_test::kOffset[0])) < 1e-4);
        total += cloud.points.size();
    }
    // LASzip reads the whole file through the 73 chunks of the variable chunk table.
    CHECK(io::readCloud(dir.path / "t.copc.laz").points.size() == total);
}

TEST_CASE("copc reader: keys without points and broken files give one line") {
    test_support::TempDir dir("copc_reader_errors");
    const copc_test::File f = copc_test::make();
    const std::filesystem::path p = writeFile(dir, f.bytes);
    const io::CopcReader reader(p);
    CHECK(test_support::errorOf([&] { reader.readNode({1, 1, 1, 1}); }) ==
          "copc: " + p.string() + " node 1-1-1-1: the file has no node with points of that key");
    CHECK(test_support::errorOf([&] { reader.readNode({5, 0, 0, 0}); }).find("no node with points") !=
          std::string::npos);

    std::string b = f.bytes;
    std::memcpy(b.data() + f.info_at - 54 + 2, "copx", 4);
    const std::filesystem::path q = dir.path / "noinfo.copc.laz";
    std::ofstream(q, std::ios::binary) << b;
    CHECK(test_support::errorOf([&] { io::CopcReader r(q); }) ==
          "copc: " + q.string() + ": copc-info: no info VLR (user \"copc\", record 1); a COPC file needs one");

    b = f.bytes;
    copc_test::put<std::int32_t>(b, f.nodes[2].entry_at + 24, std::int32_t(f.nodes[2].chunk_bytes) + 3);
    std::ofstream(q, std::ios::binary | std::ios::trunc) << b;
    const std::string e = test_support::errorOf([&] { io::CopcReader r(q); });
    CHECK(e.find("node-chunk: node 1-1-0-0 declares") != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
    // What leaves every node readable is accepted: a node taken out of the hierarchy (its
    // chunk unreferenced, the header's count then too high) and bytes in no page.
    b = f.bytes;
    const copc_test::Node& leaf = f.nodes[3];
    REQUIRE(leaf.key == io::CopcKey{2, 3, 3, 3});
    copc_test::put<std::uint64_t>(b, leaf.entry_at + 16, 0u);
    copc_test::put<std::int32_t>(b, leaf.entry_at + 24, 0);
    copc_test::put<std::int32_t>(b, leaf.entry_at + 28, 0);
    copc_test::put<std::uint64_t>(b, f.evlr_at + 20, copc_test::get<std::uint64_t>(b, f.evlr_at + 20) + 32);
    b.append(32, '\0');
    std::ofstream(q, std::ios::binary | std::ios::trunc) << b;
    const io::CopcReader lenient(q);
    CHECK(lenient.nodes().size() == f.nodes.size() - 1);
    CHECK(lenient.readNode({2, 0, 2, 0}).points.size() == f.nodes[5].points.size());

    CHECK(test_support::errorOf([&] { io::CopcReader r(dir.path / "none.copc.laz"); }) ==
          "copc: " + (dir.path / "none.copc.laz").string() + ": file does not exist");
}

TEST_CASE("copc reader: by page, the root page at open and each child page when asked") {
    test_support::TempDir dir("copc_reader_paged");
    const copc_test::File f = copc_test::make();
    const std::filesystem::path p = writeFile(dir, f.bytes);
    const io::CopcReader whole(p);
    const io::CopcReader paged(p, io::CopcHierarchy::by_page);
    CHECK(paged.info().root_hier_offset == whole.info().root_hier_offset);
    CHECK(paged.pointCount() == whole.pointCount());
    CHECK(paged.origin() == whole.origin());
    // The root page: its 4 nodes with points, the empty 1-1-1-1 and the page of 1-0-1-0.
    REQUIRE(paged.nodes().size() == 4);
    CHECK(paged.emptyNodes() == std::vector<io::CopcKey>{{1, 1, 1, 1}});
    REQUIRE(paged.pages().size() == 1);
    const io::CopcPage page = paged.pages()[0];
    CHECK(page.key == io::CopcKey{1, 0, 1, 0});
    CHECK(page.offset == f.child_page_at);
    CHECK(page.bytes == f.child_page_size);
    CHECK(whole.pages().empty());
    // The child page: the rest of the nodes, as the whole read gives them.
    const io::CopcPageEntries child = paged.readPage(page);
    CHECK(child.pages.empty());
    std::vector<io::CopcNode> all = paged.nodes();
    all.insert(all.end(), child.nodes.begin(), child.nodes.end());
    std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
    REQUIRE(all.size() == whole.nodes().size());
    for (std::size_t i = 0; i < all.size(); ++i) {
        CHECK(all[i].key == whole.nodes()[i].key);
        CHECK(all[i].offset == whole.nodes()[i].offset);
        CHECK(all[i].point_count == whole.nodes()[i].point_count);
    }
    // A node of the child page reads through its entry, as the whole reader reads it.
    const io::CopcNode& deep = child.nodes.back();
    CHECK(deep.key.level == 2);
    const core::PointCloud a = paged.readNodeEntry(deep), b = whole.readNode(deep.key);
    REQUIRE(a.points.size() == b.points.size());
    CHECK(a.points.back().position == b.points.back().position);
    // An entry outside the point data is refused before any byte is read.
    io::CopcNode bad = deep;
    bad.offset = f.bytes.size() - 4;
    CHECK(test_support::errorOf([&] { paged.readNodeEntry(bad); }).find("is not inside the point data") !=
          std::string::npos);
}

TEST_CASE("copc reader: by page, a broken child page gives one line when it is read, not at open") {
    test_support::TempDir dir("copc_reader_paged_bad");
    const copc_test::File f = copc_test::make();
    const std::filesystem::path q = dir.path / "bad.copc.laz";
    // A key of the child page moved outside the subtree of 1-0-1-0.
    std::string b = f.bytes;
    const copc_test::Node& child_node = *std::find_if(
        f.nodes.begin(), f.nodes.end(), [](const copc_test::Node& n) { return n.key == io::CopcKey{2, 0, 2, 0}; });
    copc_test::put<std::int32_t>(b, child_node.entry_at + 4, 3);
    std::ofstream(q, std::ios::binary) << b;
    CHECK_THROWS(io::CopcReader(q));  // read whole, the page is checked at open
    const io::CopcReader paged(q, io::CopcHierarchy::by_page);
    REQUIRE(paged.pages().size() == 1);
    const std::string e = test_support::errorOf([&] { paged.readPage(paged.pages()[0]); });
    CHECK(e.find("copc: " + q.string() + " page of 1-0-1-0: node-key: node 2-3-2-0 is in the page of 1-0-1-0") == 0);
    CHECK(e.find('\n') == std::string::npos);
    // A child page whose bytes run past the hierarchy record.
    io::CopcPage outside = paged.pages()[0];
    outside.bytes += 64;
    CHECK(test_support::errorOf([&] { paged.readPage(outside); }).find("hierarchy-page: the page of 1-0-1-0") !=
          std::string::npos);
    // A child page that names itself as its own child page: refused, not read again and again.
    b = f.bytes;
    copc_test::put<std::int32_t>(b, child_node.entry_at + 0, 1);
    copc_test::put<std::int32_t>(b, child_node.entry_at + 4, 0);
    copc_test::put<std::int32_t>(b, child_node.entry_at + 8, 1);
    copc_test::put<std::int32_t>(b, child_node.entry_at + 12, 0);
    copc_test::put<std::uint64_t>(b, child_node.entry_at + 16, f.child_page_at);
    copc_test::put<std::int32_t>(b, child_node.entry_at + 24, std::int32_t(f.child_page_size));
    copc_test::put<std::int32_t>(b, child_node.entry_at + 28, -1);
    std::ofstream(q, std::ios::binary | std::ios::trunc) << b;
    const io::CopcReader self(q, io::CopcHierarchy::by_page);
    CHECK(test_support::errorOf([&] {
              self.readPage(self.pages()[0]);
          }).find("points to a child page for its own key") != std::string::npos);
}

TEST_CASE("copc reader: by page, a page of more entries than its bound is refused, naming both") {
    test_support::TempDir dir("copc_reader_page_bound");
    const copc_test::File f = copc_test::make();  // a root page of 6 entries, a child page of 3
    const std::filesystem::path p = writeFile(dir, f.bytes);
    const std::string m = test_support::errorOf([&] { io::CopcReader(p, io::CopcHierarchy::by_page, 5); });
    CHECK(m == "copc: " + p.string() +
                   ": hierarchy-page: the root hierarchy page has 6 entries; allowed at most 5 in one page (this "
                   "reader's memory bound)");
    // A child page is held to the same bound when it is read: the child page (last in the
    // file) grown to 7 entries by empty nodes of its subtree.
    std::string b = f.bytes;
    for (const io::CopcKey& k : {io::CopcKey{2, 0, 2, 1}, {2, 1, 2, 0}, {2, 1, 2, 1}, {2, 0, 3, 0}})
        b += copc_test::entry(k, 0, 0, 0);
    copc_test::put<std::int32_t>(b, f.pointer_entry_at + 24, std::int32_t(f.child_page_size + 4 * 32));
    copc_test::put<std::uint64_t>(b, f.evlr_at + 20, copc_test::get<std::uint64_t>(b, f.evlr_at + 20) + 4 * 32);
    const std::filesystem::path q = dir.path / "grown.copc.laz";
    std::ofstream(q, std::ios::binary) << b;
    // The caller names what sets the bound (the viewer: its option), here and by readPage.
    const io::CopcReader paged(q, io::CopcHierarchy::by_page, 6, "the test's 1 MiB, --memory-mb");
    CHECK(test_support::errorOf([&] { paged.readPage(paged.pages()[0]); })
              .find("page of 1-0-1-0: hierarchy-page: the page of 1-0-1-0 has 7 entries; allowed at most 6 in one page "
                    "(the test's 1 MiB, --memory-mb)") != std::string::npos);
    CHECK(io::CopcReader(q, io::CopcHierarchy::by_page, 7).readPage(paged.pages()[0]).empty_nodes.size() == 4);
    // Within the bound, and read whole (no bound), the file opens.
    CHECK(io::CopcReader(p, io::CopcHierarchy::by_page, 6).nodes().size() == 4);
    CHECK(io::CopcReader(p, io::CopcHierarchy::whole, 1).nodes().size() == 7);
}

TEST_CASE("copc reader: the header's scale, the coordinates' step") {
    test_support::TempDir dir("copc_reader_scale");
    const io::CopcReader reader(writeFile(dir, copc_test::make().bytes), io::CopcHierarchy::by_page);
    CHECK(reader.scale() == glm::dvec3(copc_test::kScale));
}

TEST_CASE("copc reader: isCopcFile tells a COPC file from other files by its first VLR") {
    test_support::TempDir dir("copc_is");
    const copc_test::File f = copc_test::make();
    const std::filesystem::path copc = writeFile(dir, f.bytes);
    CHECK(io::isCopcFile(copc));
    // The same bytes with the info record's number changed, its user changed, or cut short.
    std::string other = f.bytes;
    other[375 + 2 + 16] = 2;
    std::ofstream(dir.path / "record.laz", std::ios::binary) << other;
    CHECK_FALSE(io::isCopcFile(dir.path / "record.laz"));
    other = f.bytes;
    other[375 + 2] = 'C';
    std::ofstream(dir.path / "user.laz", std::ios::binary) << other;
    CHECK_FALSE(io::isCopcFile(dir.path / "user.laz"));
    std::ofstream(dir.path / "short.laz", std::ios::binary) << f.bytes.substr(0, 394);
    CHECK_FALSE(io::isCopcFile(dir.path / "short.laz"));
    other = f.bytes;
    other[0] = 'X';
    std::ofstream(dir.path / "signature.laz", std::ios::binary) << other;
    CHECK_FALSE(io::isCopcFile(dir.path / "signature.laz"));
    CHECK_FALSE(io::isCopcFile(dir.path / "missing.laz"));
    CHECK_FALSE(io::isCopcFile(dir.path));  // a folder
}
