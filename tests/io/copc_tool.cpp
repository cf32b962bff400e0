// copc_tool: the COPC side of the tests in other languages.
//   copc_tool make <out>   writes the hand-made valid COPC file (copc_test_file.hpp)
//   copc_tool many <out>   the same with 73 nodes in one page
//   copc_tool bad <out>    `many` with the chunk of node 1-1-1-1 overwritten by bytes
//                          that do not decode (a corrupt node in an otherwise valid file)
//   copc_tool nodes <out>  a file io::CopcNodeWriter writes from nodes made here: a
//                          chain of nodes from the root to level 5 (so a child page) and
//                          their siblings, a few dozen points each
//   copc_tool dump <in>    what io::CopcReader reads, as one JSON object: the info, the
//                          nodes and their point counts, and over all points the count,
//                          the bounds and sums of the coordinates in whole millimetres and
//                          the count of each role (what tests/io/copcjs_read.mjs prints;
//                          the sums as decimal strings, exact beyond 2^53)
#include <core/error.hpp>
#include <io/copc.hpp>
#include <io/copc_writer.hpp>

#include "copc_test_file.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
    try {
        const std::string what = argc == 3 ? argv[1] : "";
        if (what == "make" || what == "many") {
            std::ofstream(argv[2], std::ios::binary) << copc_test::make({}, what == "many").bytes;
            return 0;
        }
        if (what == "nodes") {
            // A 4.096 m cube around a georeferenced origin; node (level, 0, 0, 0) and its
            // sibling (level, 1, 1, 1) of every level hold points spread over their cubes.
            const glm::dvec3 origin(631000.0, 5402000.0, 220.0);
            constexpr int bits = 12;
            std::vector<std::vector<core::CloudPoint>> held;
            std::vector<io::CopcNodeWriter::Node> nodes;
            for (int level = 0; level <= 5; ++level)
                for (const int o : {0, 1}) {
                    if (level == 0 && o == 1) continue;
                    const double side_m = 4.096 / double(1 << level), low_m = -2.048 + o * side_m;
                    std::vector<core::CloudPoint> pts;
                    for (int i = 0; i < 20 + 7 * level; ++i) {
                        core::CloudPoint p;
                        const double t = (i + 0.5) / double(20 + 7 * level);
                        p.position = glm::vec3(float(low_m + side_m * t), float(low_m + side_m * (1.0 - t)),
                                               float(low_m + side_m * 0.5));
                        p.rgb = core::packRgb(std::uint8_t(40 * level), std::uint8_t(i), 200);
                        p.label = core::Role(i % 3);
                        p.view = std::uint16_t(level);
                        pts.push_back(p);
                    }
                    held.push_back(std::move(pts));
                    nodes.push_back({io::CopcKey{level, o, o, o}, held.back()});
                }
            io::LasOptions las;
            las.threads = 2;
            io::CopcNodeWriter w(argv[2], origin, core::CloudFields{}, bits, las);
            w.add(nodes);
            w.commit();
            return 0;
        }
        if (what == "bad") {
            copc_test::File f = copc_test::make({}, true);
            for (const copc_test::Node& n : f.nodes)
                if (n.key == io::CopcKey{1, 1, 1, 1})
                    for (std::size_t i = 0; i < n.chunk_bytes; ++i) f.bytes[n.chunk_at + i] = char(0xA5 ^ (i * 7));
            std::ofstream(argv[2], std::ios::binary) << f.bytes;
            return 0;
        }
        if (what != "dump") {
            std::fprintf(stderr, "usage: copc_tool make OUT | many OUT | bad OUT | nodes OUT | dump IN\n");
            return 2;
        }
        const io::CopcReader reader(argv[2]);
        const io::CopcInfo& i = reader.info();
        std::printf(
            "{\"info\": {\"center\": [%.17g, %.17g, %.17g], \"halfsize\": %.17g, \"spacing\": %.17g, "
            "\"root_hier_offset\": %" PRIu64 ", \"root_hier_size\": %" PRIu64 ", \"gpstime\": [%.17g, %.17g]},\n",
            i.center_m[0], i.center_m[1], i.center_m[2], i.halfsize_m, i.spacing_m, i.root_hier_offset,
            i.root_hier_size, i.gpstime_minimum, i.gpstime_maximum);
        std::printf(" \"node_count\": %zu,\n \"nodes\": {", reader.nodes().size());
        std::int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
        std::int64_t sum[3] = {0, 0, 0};
        std::uint64_t roles[3] = {0, 0, 0}, points = 0;
        bool first = true;
        for (const io::CopcNode& n : reader.nodes()) {
            std::printf("%s\"%d-%d-%d-%d\": %d", first ? "" : ", ", n.key.level, n.key.x, n.key.y, n.key.z,
                        n.point_count);
            first = false;
            const core::PointCloud c = reader.readNode(n.key);
            for (const core::CloudPoint& p : c.points) {
                for (int k = 0; k < 3; ++k) {
                    const auto mm = std::int64_t(std::llround((c.origin[k] + double(p.position[k])) * 1000.0));
                    lo[k] = std::min(lo[k], mm);
                    hi[k] = std::max(hi[k], mm);
                    sum[k] += mm;
                }
                ++roles[std::size_t(p.label)];
                ++points;
            }
        }
        std::printf("},\n \"points\": %" PRIu64 ", \"min_mm\": [%" PRId64 ", %" PRId64 ", %" PRId64
                    "], \"max_mm\": [%" PRId64 ", %" PRId64 ", %" PRId64 "],\n \"sum_mm\": [\"%" PRId64 "\", \"%" PRId64
                    "\", \"%" PRId64 "\"], \"roles\": [%" PRIu64 ", %" PRIu64 ", %" PRIu64 "]}\n",
                    points, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], sum[0], sum[1], sum[2], roles[0], roles[1],
                    roles[2]);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "copc_tool: %s\n", e.what());
        return 1;
    }
}
