// The COPC writer's part tree (io/src/copc/writer/part_tree.hpp): from a histogram of the
// spilled points, the top of the octree whose buckets part every point, and the memory
// bound that leaves no room for a bucket refused with the least it needs.
#include <test_files.hpp>
#include <core/error.hpp>
#include <io/copc_writer.hpp>
#include <io/point_packing.hpp>

#include "../../../../io/src/copc/writer/part_tree.hpp"
#include "../../../../io/src/las/las_record.hpp"

#include <doctest/doctest.h>

#include <random>
#include <string>
#include <vector>

namespace {

using namespace io::detail::copc_writer;
using test_support::errorOf;
using test_support::TempDir;

struct Fixture {
    TempDir dir{"copc_part_tree"};
    core::CloudFields fields;
    io::detail::LasRecord record{"output: out.copc.laz", glm::dvec3(0.0), fields, io::LasOptions{}};
    io::PointPacking packing{fields, io::PointPacking::Position::Quantized};
    WriterSetup setup{record, packing, 0, 100, dir.path, "out.copc.laz"};
};

}  // namespace

TEST_CASE("copc part tree: every point falls in one bucket, inside its root's cube, as the histogram counted") {
    Fixture f;
    // 20000 points through a 100 m cube, one in 40 in a dense 2 m corner.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> in(0.0f, 100.0f), corner(0.0f, 2.0f);
    std::vector<std::array<std::int32_t, 3>> xyz(20000);
    std::array<std::int32_t, 3> lo{}, hi{};
    Spill spill(f.dir.path, "out.copc.laz", 0);
    std::vector<unsigned char> packed(f.packing.size());
    for (std::size_t i = 0; i < xyz.size(); ++i) {
        core::CloudPoint p;
        p.position =
            i % 40 == 0 ? glm::vec3(corner(rng), corner(rng), corner(rng)) : glm::vec3(in(rng), in(rng), in(rng));
        xyz[i] = f.record.quantize(p, i);
        for (std::size_t k = 0; k < 3; ++k) {
            lo[k] = i ? std::min(lo[k], xyz[i][k]) : xyz[i][k];
            hi[k] = i ? std::max(hi[k], xyz[i][k]) : xyz[i][k];
        }
        f.packing.packQuantized(p, xyz[i], packed.data());
        spill.write(packed.data(), packed.size());
    }
    const io::detail::OctreeCube cube = io::detail::enclosingCube(lo, hi);
    // Room for buckets of about a thousand points beside the writer's fixed bytes.
    const std::uint64_t memory = io::copcFixedBytes(0, f.setup.cap) + 240000;
    PartTree tree;
    tree.plan(f.setup, cube, memory);
    tree.countSpill(f.setup, spill, xyz.size(), cube);
    tree.build(f.setup, cube);
    REQUIRE(tree.buckets.size() > 8);
    std::vector<std::uint64_t> counted(tree.buckets.size(), 0);
    for (const auto& p : xyz) {
        const int b = tree.bucketOf(cube, p);
        REQUIRE(b >= 0);
        REQUIRE(std::size_t(b) < tree.buckets.size());
        ++counted[std::size_t(b)];
        const io::CopcKey key = tree.tops[std::size_t(tree.buckets[std::size_t(b)].top)].key;
        const int shift = cube.bits - key.level;
        CHECK(((std::int64_t(p[0]) - cube.corner[0]) >> shift) == key.x);
        CHECK(((std::int64_t(p[1]) - cube.corner[1]) >> shift) == key.y);
        CHECK(((std::int64_t(p[2]) - cube.corner[2]) >> shift) == key.z);
    }
    for (std::size_t b = 0; b < tree.buckets.size(); ++b) {
        CAPTURE(b);
        CHECK(counted[b] == tree.buckets[b].count);
        CHECK(counted[b] > 0);
        CHECK(counted[b] < 2500);  // parted: no bucket holds a large share
    }
    // The root splits; each top node is its children's sum.
    CHECK(tree.tops[0].count == xyz.size());
    for (const Top& t : tree.tops) {
        if (t.bucket >= 0) continue;
        std::uint64_t sum = 0;
        for (int c : t.child)
            if (c >= 0) sum += tree.tops[std::size_t(c)].count;
        CHECK(sum == t.count);
    }
}

TEST_CASE("copc part tree: a bound with no room for a bucket of one node is refused, naming the least") {
    Fixture f;
    io::detail::OctreeCube cube;
    cube.bits = 20;
    PartTree tree;
    const std::uint64_t memory = io::copcFixedBytes(0, f.setup.cap) + 1000;
    CHECK(errorOf([&] { tree.plan(f.setup, cube, memory); }) ==
          "output: out.copc.laz: a memory bound of " + std::to_string(memory >> 20) +
              " MiB leaves no room for a node of 100 points; allowed at least " +
              std::to_string(io::copcMinimumBytes(0, 100) >> 20) + " MiB");
}
