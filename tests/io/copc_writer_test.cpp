// The COPC writer: the variable LAZ chunk table against LASzip's own, and files whose
// structure a small parser here checks against the COPC rules (the info VLR first at 375,
// the hierarchy pages, every node's chunk where its entry says, decoded by LASzip through
// the chunk table with every point inside its node's cube), whose points read back whole
// through our LAZ reader, whose coarse levels cover the area, and that are the same bytes
// for any thread count.
#include <test_files.hpp>
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/copc_writer.hpp>

#include "../../io/src/las/las_record.hpp"
#include "../../io/src/las/laz_chunk_table.hpp"
#include "../../io/src/las/laz_compress.hpp"

#include <doctest/doctest.h>

#include <laszip/laszip_api.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <span>
#include <string>
#include <tuple>

namespace fs = std::filesystem;

namespace {

using test_support::slurp;
using test_support::TempDir;

template <typename T>
T at(const std::string& s, std::size_t offset) {
    REQUIRE(offset + sizeof(T) <= s.size());
    T v;
    std::memcpy(&v, s.data() + offset, sizeof v);
    return v;
}

core::CloudFields ladarFields(bool rgb) {
    core::CloudFields f;
    f.rgb = rgb;
    f.intensity = f.returns = f.incidence = f.scan_angle = f.height_above_ground = true;
    return f;
}

// A terrain with a few towers and a dense cluster (so that some branches go deep), every
// field set from the index.
core::PointCloud terrain(std::size_t n, std::uint32_t seed, const glm::dvec3& origin, bool rgb = true) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    core::PointCloud c;
    c.origin = origin;
    c.fields = ladarFields(rgb);
    c.points.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        core::CloudPoint& p = c.points[i];
        const float x = u(rng) * 200.0f - 100.0f, y = u(rng) * 150.0f - 75.0f;
        if (i % 10 == 0) {  // a dense cluster of 1 m
            p.position = {30.0f + u(rng), -20.0f + u(rng), 5.0f + u(rng)};
        } else if (i % 10 == 1) {  // a tower
            p.position = {-40.0f + u(rng) * 2.0f, 10.0f + u(rng) * 2.0f, u(rng) * 60.0f};
        } else {
            p.position = {x, y, 0.1f * std::sin(x * 0.05f) * 20.0f + u(rng) * 0.05f};
        }
        p.rgb = core::packRgb(std::uint8_t(i), std::uint8_t(i >> 8), std::uint8_t(i * 13));
        p.range_m = 300.0f + float(i % 1000);
        p.incidence_deg = float(i % 90);
        p.scan_angle_deg = float(i % 50) * 0.06f - 1.5f;
        p.height_above_ground_m = p.position.z;
        p.intensity = std::uint16_t(i * 37);
        p.view = std::uint16_t(i % 700);
        p.label = core::Role(i % 3);
        p.return_number = std::uint8_t(1 + i % 2);
        p.returns = 2;
    }
    return c;
}

// What a file holds, parsed here from the bytes as the COPC specification lays it out.
struct Parsed {
    std::uint32_t point_data_at = 0, vlrs = 0;
    std::uint64_t points = 0, evlr_at = 0;
    std::uint32_t evlrs = 0;
    double scale[3]{}, offset[3]{}, max[3]{}, min[3]{};
    double center[3]{}, halfsize = 0, spacing = 0, gps_min = 0, gps_max = 0;
    std::uint64_t root_offset = 0, root_size = 0, hierarchy_at = 0, hierarchy_size = 0;
    std::uint32_t laszip_chunk_size = 0;
    struct Entry {
        std::int32_t level, x, y, z;
        std::uint64_t offset;
        std::int32_t bytes, count;
    };
    std::vector<Entry> nodes;  // entries with point_count >= 0, from every page reached
    std::size_t pages = 0;
    std::uint64_t page_bytes = 0;  // of the pages reached
    std::int64_t table_at = 0;
};

void readPage(const std::string& f, Parsed& p, std::uint64_t offset, std::uint64_t size) {
    REQUIRE(size % 32 == 0);
    REQUIRE(offset >= p.hierarchy_at);
    REQUIRE(offset + size <= p.hierarchy_at + p.hierarchy_size);
    ++p.pages;
    p.page_bytes += size;
    for (std::uint64_t e = offset; e < offset + size; e += 32) {
        Parsed::Entry n{at<std::int32_t>(f, e),      at<std::int32_t>(f, e + 4),   at<std::int32_t>(f, e + 8),
                        at<std::int32_t>(f, e + 12), at<std::uint64_t>(f, e + 16), at<std::int32_t>(f, e + 24),
                        at<std::int32_t>(f, e + 28)};
        if (n.count == -1)
            readPage(f, p, n.offset, std::uint64_t(n.bytes));
        else
            p.nodes.push_back(n);
    }
}

Parsed parse(const std::string& f) {
    Parsed p;
    REQUIRE(f.size() > 375);
    CHECK(f.compare(0, 4, "LASF") == 0);
    CHECK(at<std::uint8_t>(f, 24) == 1);
    CHECK(at<std::uint8_t>(f, 25) == 4);
    CHECK(at<std::uint16_t>(f, 94) == 375);
    p.point_data_at = at<std::uint32_t>(f, 96);
    p.vlrs = at<std::uint32_t>(f, 100);
    const int format = at<std::uint8_t>(f, 104) & 0x3F;
    CHECK((format == 6 || format == 7));
    for (int k = 0; k < 3; ++k) {
        p.scale[k] = at<double>(f, 131 + 8 * std::size_t(k));
        p.offset[k] = at<double>(f, 155 + 8 * std::size_t(k));
        p.max[k] = at<double>(f, 179 + 16 * std::size_t(k));
        p.min[k] = at<double>(f, 187 + 16 * std::size_t(k));
    }
    p.evlr_at = at<std::uint64_t>(f, 235);
    p.evlrs = at<std::uint32_t>(f, 243);
    p.points = at<std::uint64_t>(f, 247);
    // The info VLR first, at 375.
    CHECK(std::string(f.data() + 377) == "copc");
    CHECK(at<std::uint16_t>(f, 393) == 1);
    CHECK(at<std::uint16_t>(f, 395) == 160);
    const std::size_t info = 375 + 54;
    for (std::size_t k = 0; k < 3; ++k) p.center[k] = at<double>(f, info + 8 * k);
    p.halfsize = at<double>(f, info + 24);
    p.spacing = at<double>(f, info + 32);
    p.root_offset = at<std::uint64_t>(f, info + 40);
    p.root_size = at<std::uint64_t>(f, info + 48);
    p.gps_min = at<double>(f, info + 56);
    p.gps_max = at<double>(f, info + 64);
    for (std::size_t b = info + 72; b < info + 160; ++b) CHECK(f[b] == 0);
    // The other VLRs: the LASzip VLR's chunk size.
    std::size_t v = 375;
    for (std::uint32_t i = 0; i < p.vlrs; ++i) {
        const std::string user(f.data() + v + 2);
        const auto id = at<std::uint16_t>(f, v + 18);
        const auto len = at<std::uint16_t>(f, v + 20);
        if (user == "laszip encoded" && id == 22204) p.laszip_chunk_size = at<std::uint32_t>(f, v + 54 + 12);
        v += 54 + len;
    }
    CHECK(v == p.point_data_at);
    p.table_at = at<std::int64_t>(f, p.point_data_at);
    // The hierarchy EVLR, its pages from the root page.
    REQUIRE(p.evlrs == 1);
    CHECK(std::string(f.data() + p.evlr_at + 2) == "copc");
    CHECK(at<std::uint16_t>(f, p.evlr_at + 18) == 1000);
    p.hierarchy_size = at<std::uint64_t>(f, p.evlr_at + 20);
    p.hierarchy_at = p.evlr_at + 60;
    CHECK(p.hierarchy_at + p.hierarchy_size == f.size());
    CHECK(p.root_offset == p.hierarchy_at);
    readPage(f, p, p.root_offset, p.root_size);
    return p;
}

// Decodes every node through LASzip, seeking to each chunk's first point by the table, and
// checks that its points lie inside the node's cube and within the GPS range. Returns the
// world positions per node key.
std::map<std::tuple<int, int, int, int>, std::vector<glm::dvec3>> decodeNodes(const fs::path& path, const Parsed& p) {
    std::vector<Parsed::Entry> chunks;
    for (const auto& n : p.nodes)
        if (n.count > 0) chunks.push_back(n);
    std::sort(chunks.begin(), chunks.end(), [](const auto& a, const auto& b) { return a.offset < b.offset; });
    // The chunks follow one another from the point data to the table.
    std::uint64_t expect = p.point_data_at + 8;
    std::uint64_t first = 0;
    std::vector<std::uint64_t> first_point;
    for (const auto& c : chunks) {
        CHECK(c.offset == expect);
        expect += std::uint64_t(c.bytes);
        first_point.push_back(first);
        first += std::uint64_t(c.count);
    }
    CHECK(std::int64_t(expect) == p.table_at);
    CHECK(first == p.points);
    laszip_POINTER zip = nullptr;
    REQUIRE(laszip_create(&zip) == 0);
    laszip_BOOL compressed = 0;
    REQUIRE(laszip_open_reader(zip, path.c_str(), &compressed) == 0);
    laszip_point_struct* q = nullptr;
    REQUIRE(laszip_get_point_pointer(zip, &q) == 0);
    std::map<std::tuple<int, int, int, int>, std::vector<glm::dvec3>> out;
    // Backwards, so that every chunk is reached by a seek.
    for (std::size_t c = chunks.size(); c-- > 0;) {
        const auto& n = chunks[c];
        const double half = p.halfsize / std::ldexp(1.0, n.level);
        const int key[3] = {n.x, n.y, n.z};
        REQUIRE(laszip_seek_point(zip, laszip_I64(first_point[c])) == 0);
        auto& pts = out[{n.level, n.x, n.y, n.z}];
        for (std::int32_t i = 0; i < n.count; ++i) {
            REQUIRE(laszip_read_point(zip) == 0);
            const laszip_I32 xyz[3] = {q->X, q->Y, q->Z};
            glm::dvec3 w;
            for (int k = 0; k < 3; ++k) {
                const double lo = p.center[k] - p.halfsize + 2.0 * half * key[k];
                w[k] = double(xyz[k]) * p.scale[k] + p.offset[k];
                CHECK(w[k] >= lo);
                CHECK(w[k] <= lo + 2.0 * half);
            }
            CHECK(q->gps_time >= p.gps_min);
            CHECK(q->gps_time <= p.gps_max);
            pts.push_back(w);
        }
    }
    laszip_close_reader(zip);
    laszip_destroy(zip);
    return out;
}

// Every field a point carries, as written: integer millimetres for the position.
using PointKey = std::tuple<std::int64_t, std::int64_t, std::int64_t, std::uint32_t, float, float, float, float,
                            std::uint16_t, std::uint16_t, int, int, int>;
PointKey keyOf(const core::CloudPoint& p, const glm::dvec3& origin) {
    // As the writer quantizes: the local position to the millimetre, then the origin's.
    const auto mm = [](double local, double o) { return std::llround(local / 0.001) + std::llround(o * 1000.0); };
    return {mm(p.position.x, origin.x),
            mm(p.position.y, origin.y),
            mm(p.position.z, origin.z),
            p.rgb,
            p.range_m,
            p.incidence_deg,
            p.scan_angle_deg,
            p.height_above_ground_m,
            p.intensity,
            p.view,
            int(p.label),
            p.return_number,
            p.returns};
}

std::string written(const fs::path& path, const core::PointCloud& c, int threads, std::uint32_t cap = 100000) {
    io::LasOptions las;
    las.threads = threads;
    las.gps_start_s = 1000.0;
    las.view_interval_s = 0.25;
    io::CopcOptions copc;
    copc.max_node_points = cap;
    io::writeCopc(path, c, las, copc);
    return slurp(path);
}

}  // namespace

TEST_CASE("copc_writer: the variable chunk table of one chunk is LASzip's own") {
    const core::PointCloud c = terrain(3000, 5, glm::dvec3(0.0));
    io::detail::LasRecord record("test", c.origin, c.fields, io::LasOptions{});
    io::detail::LasInventory inv;
    const io::detail::LaszipFile f = io::detail::compressWithLaszip(record, c.points, 0, inv, 0xFFFFFFFFu);
    const std::uint32_t points[] = {3000};
    const std::uint32_t bytes[] = {std::uint32_t(f.table_at - f.point_data_at - 8)};
    const std::string table = io::detail::lazVariableChunkTable(points, bytes);
    CHECK(f.bytes.substr(f.table_at) == table);
    // And it differs from the fixed table, which codes no point counts.
    CHECK(io::detail::lazChunkTable(bytes) != table);
    CHECK_THROWS_AS(io::detail::lazVariableChunkTable(points, {}), core::Error);
}

TEST_CASE("copc_writer: the file's structure, every node's points inside its cube, LASzip seeking each chunk") {
    TempDir dir("copc_structure");
    const glm::dvec3 origin(1.0e7, 2.0e7 + 0.123, 150.0);
    const core::PointCloud c = terrain(30000, 11, origin);
    const fs::path path = dir.path / "s.copc.laz";
    const std::string f = written(path, c, 2, 200);
    const Parsed p = parse(f);
    CHECK(p.points == c.points.size());
    CHECK(p.laszip_chunk_size == 0xFFFFFFFFu);
    // Deep enough for child pages; every page reached, no bytes of the EVLR left over.
    CHECK(p.pages > 1);
    CHECK(p.page_bytes == p.hierarchy_size);
    // The cube encloses the header's bounds; spacing as the specification has it.
    for (int k = 0; k < 3; ++k) {
        CHECK(p.center[k] - p.halfsize <= p.min[k]);
        CHECK(p.center[k] + p.halfsize >= p.max[k]);
    }
    CHECK(p.spacing == doctest::Approx(2.0 * p.halfsize / 128.0));
    CHECK(p.gps_min == doctest::Approx(1000.0));
    CHECK(p.gps_max == doctest::Approx(1000.0 + 699 * 0.25));
    // Keys unique, ancestors present, levels within reach; the cap holds.
    std::set<std::tuple<int, int, int, int>> keys;
    std::int64_t total = 0;
    for (const auto& n : p.nodes) {
        CHECK(keys.insert({n.level, n.x, n.y, n.z}).second);
        CHECK(n.count <= 200);
        CHECK(n.count >= 0);
        if (n.count == 0) CHECK(n.offset == 0);
        total += n.count;
    }
    for (const auto& n : p.nodes)
        if (n.level > 0) CHECK(keys.count({n.level - 1, n.x >> 1, n.y >> 1, n.z >> 1}) == 1);
    CHECK(total == std::int64_t(c.points.size()));
    const auto decoded = decodeNodes(path, p);
    // Every point in exactly one node: the nodes' points are the cloud's, as a multiset.
    std::multiset<std::tuple<std::int64_t, std::int64_t, std::int64_t>> in, out;
    for (const auto& q : c.points) {
        const PointKey k = keyOf(q, origin);
        in.insert({std::get<0>(k), std::get<1>(k), std::get<2>(k)});
    }
    for (const auto& [key, pts] : decoded)
        for (const glm::dvec3& w : pts)
            out.insert({std::llround(w.x * 1000.0), std::llround(w.y * 1000.0), std::llround(w.z * 1000.0)});
    CHECK(in == out);
}

TEST_CASE("copc_writer: every field of every point reads back as from a plain LAZ, origin at 1e7 m") {
    TempDir dir("copc_roundtrip");
    const glm::dvec3 origin(1.0e7 + 0.5, -1.0e7, 12.25);
    for (const bool rgb : {true, false}) {
        CAPTURE(rgb);
        const core::PointCloud c = terrain(60000, 3, origin, rgb);
        const fs::path path = dir.path / "r.copc.laz";
        written(path, c, 1, 5000);
        const core::PointCloud back = io::readCloud(path);
        // The same points written as a plain LAZ file read back: the same fields, in another order.
        io::LasOptions las;
        las.gps_start_s = 1000.0;
        las.view_interval_s = 0.25;
        io::writeCloud(dir.path / "r.laz", c, io::CloudFormat::Laz, las);
        const core::PointCloud plain = io::readCloud(dir.path / "r.laz");
        REQUIRE(back.points.size() == c.points.size());
        REQUIRE(plain.points.size() == c.points.size());
        CHECK(back.fields.rgb == rgb);
        CHECK(back.fields.range);
        CHECK(back.fields.incidence);
        CHECK(back.fields.height_above_ground);
        CHECK(back.fields.scan_angle);
        CHECK(back.fields.intensity);
        CHECK(back.fields.returns);
        CHECK(back.origin == plain.origin);
        std::vector<PointKey> a, b, w;
        for (const auto& q : plain.points) a.push_back(keyOf(q, plain.origin));
        for (const auto& q : back.points) b.push_back(keyOf(q, back.origin));
        for (const auto& q : c.points) w.push_back(keyOf(q, origin));
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        std::sort(w.begin(), w.end());
        std::size_t same = 0;
        for (std::size_t i = 0; i < a.size(); ++i) same += a[i] == b[i];
        // Against what was written: the world position to the millimetre, range, incidence,
        // height, intensity and view exactly (colours are 8-bit, the scan angle in 0.006 deg).
        const auto kept = [](const PointKey& k) {
            return std::tuple(std::get<0>(k), std::get<1>(k), std::get<2>(k), std::get<4>(k), std::get<5>(k),
                              std::get<7>(k), std::get<8>(k), std::get<9>(k), std::get<10>(k));
        };
        std::vector<decltype(kept(a[0]))> kw, kb;
        for (const auto& k : w) kw.push_back(kept(k));
        for (const auto& k : b) kb.push_back(kept(k));
        std::sort(kw.begin(), kw.end());
        std::sort(kb.begin(), kb.end());
        CHECK(kw == kb);
        CHECK(same == a.size());
        std::array<std::size_t, 3> classes_in{}, classes_out{};
        for (const auto& q : c.points) ++classes_in[std::size_t(q.label)];
        for (const auto& q : back.points) ++classes_out[std::size_t(q.label)];
        CHECK(classes_in == classes_out);
    }
}

TEST_CASE("copc_writer: a coarse level covers the area the cloud covers") {
    TempDir dir("copc_cover");
    const glm::dvec3 origin(500000.0, 4000000.0, 0.0);
    const core::PointCloud c = terrain(200000, 21, origin);
    const fs::path path = dir.path / "c.copc.laz";
    const Parsed p = parse(written(path, c, 2, 20000));
    const auto decoded = decodeNodes(path, p);
    // The grid of level 1's spacing (256 cells per axis over the cube): every cell the cloud
    // occupies holds a point of level 0 or 1.
    const double cell = p.halfsize / 128.0;
    const auto cellOf = [&](const glm::dvec3& w) {
        return std::tuple<long, long, long>(std::lround(std::floor((w.x - p.center[0] + p.halfsize) / cell)),
                                            std::lround(std::floor((w.y - p.center[1] + p.halfsize) / cell)),
                                            std::lround(std::floor((w.z - p.center[2] + p.halfsize) / cell)));
    };
    std::set<std::tuple<long, long, long>> all, coarse;
    std::size_t coarse_points = 0;
    for (const auto& [key, pts] : decoded)
        for (const glm::dvec3& w : pts) {
            all.insert(cellOf(w));
            if (std::get<0>(key) <= 1) {
                coarse.insert(cellOf(w));
                ++coarse_points;
            }
        }
    CHECK(coarse_points < c.points.size() / 2);  // a sample, not the cloud
    CHECK(all.size() > 1000);
    CHECK(coarse == all);
}

TEST_CASE("copc_writer: the same bytes for any thread count") {
    TempDir dir("copc_threads");
    const core::PointCloud c = terrain(40000, 8, glm::dvec3(1.0e7, 1.0e7, 0.0));
    const std::string one = written(dir.path / "a.copc.laz", c, 0, 1000);
    CHECK(one == written(dir.path / "b.copc.laz", c, 1, 1000));
    CHECK(one == written(dir.path / "c.copc.laz", c, 3, 1000));
    CHECK(one == written(dir.path / "d.copc.laz", c, 7, 1000));
}

TEST_CASE("copc_writer: a .copc.laz name is COPC, never a plain LAZ") {
    CHECK(io::formatForPath("a/b.copc.laz") == io::CloudFormat::Copc);
    CHECK(io::formatForPath("a/b.COPC.Laz") == io::CloudFormat::Copc);
    CHECK(io::formatForPath("a/b.laz") == io::CloudFormat::Laz);
    CHECK(io::formatForPath("a/.copc.laz") == io::CloudFormat::Laz);  // a hidden file named ".copc"
    CHECK(io::parseCloudFormat("copc", "--format") == io::CloudFormat::Copc);
    TempDir dir("copc_name");
    const core::PointCloud c = terrain(500, 1, glm::dvec3(0.0));
    const fs::path path = dir.path / "w.copc.laz";
    io::writeCloud(path, c, io::formatForPath(path));
    const Parsed p = parse(slurp(path));
    CHECK(p.points == 500);
    CHECK(p.laszip_chunk_size == 0xFFFFFFFFu);
}

TEST_CASE("copc_writer: an empty cloud and a single point make valid files") {
    TempDir dir("copc_small");
    for (const std::size_t n : {std::size_t(0), std::size_t(1)}) {
        CAPTURE(n);
        const core::PointCloud c = terrain(n, 2, glm::dvec3(10.0, 20.0, 30.0));
        const fs::path path = dir.path / "e.copc.laz";
        const Parsed p = parse(written(path, c, 1));
        CHECK(p.points == n);
        REQUIRE(p.nodes.size() == 1);
        CHECK(p.nodes[0].count == std::int32_t(n));
        CHECK(io::readCloud(path).points.size() == n);
    }
}

TEST_CASE("copc_writer: a point out of LAS's reach is one error, and no file is left") {
    TempDir dir("copc_error");
    core::PointCloud c = terrain(1000, 4, glm::dvec3(0.0));
    c.points[700].position.x = 3.0e6f;
    const fs::path path = dir.path / "bad.copc.laz";
    CHECK(test_support::errorOf([&] { io::writeCopc(path, c); }) ==
          "output: " + path.string() +
              ": point 700 lies beyond 2,147 km of the cloud origin, out of LAS's reach at 1 mm");
    CHECK(dir.entries() == 0);
}

TEST_CASE("copc_writer: past its memory bound it spills and builds a part at a time, and writes the same file") {
    TempDir dir("copc_spill");
    const core::PointCloud c = terrain(60000, 13, glm::dvec3(1.0e7, 1.0e7, 0.0));
    for (const int threads : {0, 2}) {
        CAPTURE(threads);
        io::LasOptions las;
        las.threads = threads;
        io::CopcOptions copc;
        copc.max_node_points = 200;
        io::writeCopc(dir.path / "memory.copc.laz", c, las, copc);
        // Less than the points need in memory (64 bytes each: 3.8 MB), room for buckets of
        // about 8000 points: many buckets, levels above them.
        copc.memory_bytes = io::copcFixedBytes(threads, copc.max_node_points) + 1800000;
        io::writeCopc(dir.path / "spilled.copc.laz", c, las, copc);
        const std::string a = slurp(dir.path / "memory.copc.laz"), b = slurp(dir.path / "spilled.copc.laz");
        CHECK(a.size() == b.size());
        CHECK(a == b);
        CHECK(dir.entries() == 2);  // the scratch files are gone
    }
    // A bound below one node's room is one error naming the least allowed (the bound is
    // below what the points need beside the writer's fixed bytes, so they spill).
    io::CopcOptions tight;
    tight.memory_bytes = io::copcFixedBytes(0) + 1000;
    REQUIRE(tight.memory_bytes < io::copcMinimumBytes(0));
    const std::string e = test_support::errorOf([&] { io::writeCopc(dir.path / "tight.copc.laz", c, {}, tight); });
    CHECK(e.find("leaves no room for a node of " + std::to_string(io::kDefaultMaxNodePoints) +
                 " points; allowed at least " + std::to_string(io::copcMinimumBytes(0) >> 20) + " MiB") !=
          std::string::npos);
    CHECK_FALSE(fs::exists(dir.path / "tight.copc.laz"));
}

// Writes `c` through a CloudWriter, giving it the points first as often as it asks, in
// chunks of `chunk`, each pass's points from `pass_points` (the cloud's own by default);
// returns the passes asked for.
int writePrescanned(const fs::path& path, const core::PointCloud& c, const io::LasOptions& las,
                    const io::CopcOptions& copc, const std::vector<core::CloudPoint>* appended = nullptr,
                    std::size_t last_pass_points = std::numeric_limits<std::size_t>::max(),
                    const core::Bounds* positions = nullptr) {
    constexpr std::size_t kChunk = 7001;
    io::CloudWriter w(path, io::CloudFormat::Copc, c.origin, c.fields, las, &copc);
    const int passes = w.prescanPasses(c.points.size(), positions);
    for (int pass = 0; pass < passes; ++pass) {
        const std::size_t n = pass == passes - 1 ? std::min(last_pass_points, c.points.size()) : c.points.size();
        for (std::size_t i = 0; i < n; i += kChunk)
            w.prescan(pass, std::span(c.points).subspan(i, std::min(kChunk, n - i)));
    }
    const std::vector<core::CloudPoint>& points = appended ? *appended : c.points;
    for (std::size_t i = 0; i < points.size(); i += kChunk)
        w.append(std::span(points).subspan(i, std::min(kChunk, points.size() - i)));
    w.commit();
    return passes;
}

TEST_CASE(
    "copc_writer: past its bound, given the points first, it sorts them into its parts as they come: the "
    "same file") {
    TempDir dir("copc_prescan");
    const core::PointCloud c = terrain(60000, 17, glm::dvec3(1.0e7, 1.0e7, 0.0));
    for (const int threads : {0, 2}) {
        CAPTURE(threads);
        io::LasOptions las;
        las.threads = threads;
        io::CopcOptions copc;
        copc.max_node_points = 200;
        io::writeCopc(dir.path / "memory.copc.laz", c, las, copc);
        // Within the bound the writer holds the points and asks for nothing.
        CHECK(writePrescanned(dir.path / "held.copc.laz", c, las, copc) == 0);
        CHECK(slurp(dir.path / "held.copc.laz") == slurp(dir.path / "memory.copc.laz"));
        // Buckets of about 8000 points: a few, sorted as they come.
        copc.memory_bytes = io::copcFixedBytes(threads, copc.max_node_points) + 1800000;
        CHECK(writePrescanned(dir.path / "prescanned.copc.laz", c, las, copc) == 2);
        CHECK(slurp(dir.path / "prescanned.copc.laz") == slurp(dir.path / "memory.copc.laz"));
        CHECK(dir.entries() == 3);  // no scratch file left
        // Given the positions' bounds, it asks for one pass, their histogram.
        core::Bounds positions;
        for (const core::CloudPoint& p : c.points) positions.extend(glm::dvec3(p.position));
        CHECK(writePrescanned(dir.path / "prescanned.copc.laz", c, las, copc, nullptr, SIZE_MAX, &positions) == 1);
        CHECK(slurp(dir.path / "prescanned.copc.laz") == slurp(dir.path / "memory.copc.laz"));
        CHECK(dir.entries() == 3);
        // Points all through a cube, buckets of a few hundred: more than the writer keeps
        // open at once, so it holds and spills them as it does unasked.
        core::PointCloud cube = terrain(120000, 19, glm::dvec3(0.0));
        std::mt19937 rng(23);
        std::uniform_real_distribution<float> in(0.0f, 100.0f);
        for (core::CloudPoint& p : cube.points) p.position = glm::vec3(in(rng), in(rng), in(rng));
        copc.memory_bytes = 0;
        io::writeCopc(dir.path / "memory.copc.laz", cube, las, copc);
        copc.memory_bytes = io::copcFixedBytes(threads, copc.max_node_points) + 140000;
        CHECK(writePrescanned(dir.path / "prescanned.copc.laz", cube, las, copc) == 2);
        CHECK(slurp(dir.path / "prescanned.copc.laz") == slurp(dir.path / "memory.copc.laz"));
        CHECK(dir.entries() == 3);
    }
    // Points appended that are not those prescanned are one error each, and no file.
    io::CopcOptions copc;
    copc.max_node_points = 200;
    copc.memory_bytes = io::copcFixedBytes(0, copc.max_node_points) + 1800000;
    const fs::path out = dir.path / "bad.copc.laz";
    const auto errorWith = [&](const std::vector<core::CloudPoint>* appended, std::size_t second = SIZE_MAX) {
        const std::string e = test_support::errorOf([&] { writePrescanned(out, c, {}, copc, appended, second); });
        CHECK_FALSE(fs::exists(out));
        return e;
    };
    std::vector<core::CloudPoint> moved = c.points;
    moved[100].position.x += 1.0e4f;
    CHECK(errorWith(&moved) ==
          "output: " + out.string() + ": point 100 lies outside the bounds of the points prescanned");
    // Within the bounds, the first point moved onto the one farthest from it: the parts
    // would no longer hold what the prescan counted.
    moved = c.points;
    std::size_t far = 0;
    for (std::size_t i = 0; i < moved.size(); ++i)
        if (glm::distance(moved[i].position, moved[0].position) > glm::distance(moved[far].position, moved[0].position))
            far = i;
    moved[0].position = moved[far].position;
    CHECK(errorWith(&moved) == "output: " + out.string() + ": the points appended are not the points prescanned");
    moved = c.points;
    moved.pop_back();
    CHECK(errorWith(&moved) == "output: " + out.string() + ": 59999 points appended of the 60000 prescanned");
    // Bounds given wider than the points', or narrower.
    core::Bounds positions;
    for (const core::CloudPoint& p : c.points) positions.extend(glm::dvec3(p.position));
    core::Bounds wide = positions;
    wide.hi.z += 1.0;
    std::string e = test_support::errorOf([&] { writePrescanned(out, c, {}, copc, nullptr, SIZE_MAX, &wide); });
    CHECK(e == "output: " + out.string() + ": the bounds given for the prescan are not the points' own");
    core::Bounds narrow = positions;
    narrow.lo.x += 1.0;
    e = test_support::errorOf([&] { writePrescanned(out, c, {}, copc, nullptr, SIZE_MAX, &narrow); });
    CHECK(e.find(": lies outside the bounds of the points prescanned") == std::string::npos);
    CHECK(e.find(" lies outside the bounds of the points prescanned") != std::string::npos);
    CHECK_FALSE(fs::exists(out));
    CHECK(errorWith(nullptr, 59000) ==
          "output: " + out.string() + ": the prescan's last pass gave 59000 points of 60000");
    CHECK(dir.entries() == 3);  // the earlier files alone
}

TEST_CASE("copc_writer: nodes made by the caller become a valid COPC file that reads back node by node") {
    TempDir dir("copc_nodes");
    const fs::path path = dir.path / "nodes.copc.laz";
    const glm::dvec3 origin(5.0e5, 4.0e6, 100.0);
    constexpr int bits = 12;  // a cube of 4.096 m centred on the origin
    // A point at (x, y, z) metres from the origin; its node at `level` by its millimetres.
    const auto pointAt = [](double x, double y, double z, std::uint16_t view) {
        core::CloudPoint p;
        p.position = glm::vec3(float(x), float(y), float(z));
        p.view = view;
        p.label = core::Role::Ground;
        return p;
    };
    std::vector<core::CloudPoint> root, child, grandchild;
    for (int i = 0; i < 50; ++i) root.push_back(pointAt(-1.9 + 0.07 * i, -1.5 + 0.05 * i, 0.3, 1));
    for (int i = 0; i < 30; ++i) child.push_back(pointAt(0.1 + 0.06 * i, 0.2 + 0.01 * i, 0.5, 2));  // octant 7
    for (int i = 0; i < 20; ++i) grandchild.push_back(pointAt(-1.9 + 0.02 * i, -1.9, -1.9, 3));     // level 2, 0-0-0
    {
        io::LasOptions las;
        las.threads = 2;
        io::CopcNodeWriter w(path, origin, core::CloudFields{}, bits, las);
        const io::CopcNodeWriter::Node first[] = {{io::CopcKey{0, 0, 0, 0}, root}, {io::CopcKey{1, 1, 1, 1}, child}};
        w.add(first);
        const io::CopcNodeWriter::Node second[] = {{io::CopcKey{2, 0, 0, 0}, grandchild}};
        w.add(second);
        w.commit();
    }
    const std::vector<io::CopcFinding> findings = io::checkCopc(path);
    for (const io::CopcFinding& f : findings) CAPTURE(f.rule + ": " + f.message);
    CHECK(findings.empty());
    const io::CopcReader reader(path);
    CHECK(reader.info().halfsize_m == doctest::Approx(2.048));
    CHECK(reader.info().center_m[0] == doctest::Approx(origin.x - 0.0005));
    REQUIRE(reader.nodes().size() == 3);  // level 1, 0-0-0 is an empty ancestor: not listed
    CHECK(reader.readNode({0, 0, 0, 0}).points.size() == 50);
    CHECK(reader.readNode({1, 1, 1, 1}).points.size() == 30);
    const core::PointCloud g = reader.readNode({2, 0, 0, 0});
    REQUIRE(g.points.size() == 20);
    CHECK(g.origin.x + double(g.points[0].position.x) == doctest::Approx(origin.x - 1.9).epsilon(1e-12));
}

TEST_CASE("copc_writer: a caller's node out of its cube, out of the tree or given twice is one error, and no file") {
    TempDir dir("copc_nodes_bad");
    const fs::path path = dir.path / "bad.copc.laz";
    core::CloudPoint p;
    p.position = glm::vec3(0.5f, 0.5f, 0.5f);  // in octant 7 of a 4.096 m cube
    const std::vector<core::CloudPoint> one{p};
    const auto errorFor = [&](const std::vector<io::CopcNodeWriter::Node>& nodes) {
        return test_support::errorOf([&] {
            io::CopcNodeWriter w(path, glm::dvec3(0.0), core::CloudFields{}, 12);
            w.add(nodes);
            w.commit();
        });
    };
    const std::string where = "output: " + path.string() + ": ";
    CHECK(errorFor({{io::CopcKey{1, 0, 0, 0}, one}}) == where + "point 0 of node 1-0-0-0 lies outside its cube");
    CHECK(errorFor({{io::CopcKey{1, 2, 0, 0}, one}}) ==
          where + "node 1-2-0-0 is outside the octree; allowed levels 0 to 12 and x, y, z in [0, 2^level)");
    CHECK(errorFor({{io::CopcKey{13, 0, 0, 0}, one}}) ==
          where + "node 13-0-0-0 is outside the octree; allowed levels 0 to 12 and x, y, z in [0, 2^level)");
    CHECK(errorFor({{io::CopcKey{1, 1, 1, 1}, one}, {io::CopcKey{1, 1, 1, 1}, one}}) ==
          where + "node 1-1-1-1 was added before");
    CHECK(test_support::errorOf([&] { io::CopcNodeWriter w(path, glm::dvec3(0.0), core::CloudFields{}, 40); }) ==
          where + "a COPC cube of 2^40 mm; allowed bits 1 to 31");
    CHECK(dir.entries() == 0);
}
