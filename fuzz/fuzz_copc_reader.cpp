// fuzz/fuzz_copc_reader.cpp: libFuzzer target for COPC reading (io/src/copc/: the layout
// parse, the validator behind `index --check` and io::CopcReader's node-by-node reads, with
// LASzip decoding each node's chunk). Every input is made to start with "LASF" so each
// mutation reaches the COPC code, and is written to a scratch file because both entry
// points take a path. The contract:
// - checkCopc never throws and every finding is one printable ASCII line;
// - CopcReader opens the file or throws core::Error of one printable line, and so does
//   each readNode;
// - a file with no finding opens, and each node it decodes gives exactly its point count,
//   every point finite and inside its node's cube (to a scale unit).
// Seeds: fuzz/seeds/copc (files written by `ladarvr index`).
#include "check_message.hpp"

#include <core/error.hpp>
#include <io/copc.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace {

std::filesystem::path scratchFile() {
    const char* tmp = std::getenv("TMPDIR");
    return std::filesystem::path(tmp && *tmp ? tmp : "/tmp") /
           ("fuzz_copc_" + std::to_string(::getpid()) + ".copc.laz");
}

void cubeOf(const io::CopcInfo& info, const io::CopcKey& key, double lo[3], double hi[3]) {
    const double side = 2.0 * info.halfsize_m / double(std::int64_t(1) << key.level);
    const int cell[3] = {key.x, key.y, key.z};
    for (int k = 0; k < 3; ++k) {
        lo[k] = info.center_m[std::size_t(k)] - info.halfsize_m + side * cell[k];
        hi[k] = lo[k] + side;
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    bytes.replace(0, std::min<std::size_t>(4, bytes.size()), "LASF");
    static const std::filesystem::path file = scratchFile();
    {
        std::FILE* f = std::fopen(file.c_str(), "wb");
        if (!f) std::abort();
        if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) std::abort();
        std::fclose(f);
    }

    const std::vector<io::CopcFinding> findings = io::checkCopc(file);
    for (const io::CopcFinding& fi : findings) {
        fuzz::checkMessage(fi.rule.c_str(), true);
        fuzz::checkMessage(fi.message.c_str(), true);
    }
    const bool valid = findings.empty();

    try {
        io::CopcReader reader(file);
        const io::CopcInfo& info = reader.info();
        for (const io::CopcNode& node : reader.nodes()) {
            core::PointCloud pts;
            try {
                pts = reader.readNode(node.key);
            } catch (const core::Error& e) {
                // The LAS reader's own rules (our label field among them) may refuse a node
                // that the COPC rules accept; the refusal must still be one line.
                fuzz::checkMessage(e.what(), true);
                continue;
            }
            if (!valid) continue;
            if (pts.points.size() != std::size_t(node.point_count)) std::abort();
            double lo[3], hi[3];
            cubeOf(info, node.key, lo, hi);
            for (const core::CloudPoint& p : pts.points) {
                const double local[3] = {p.position.x, p.position.y, p.position.z};
                const double w[3] = {pts.origin.x + local[0], pts.origin.y + local[1], pts.origin.z + local[2]};
                for (int k = 0; k < 3; ++k) {
                    if (!std::isfinite(w[k])) std::abort();
                    // A scale unit, and the float rounding of the local coordinate.
                    const double slack = 0.002 + 1e-6 * std::abs(local[k]);
                    if (w[k] < lo[k] - slack || w[k] > hi[k] + slack) {
                        std::fprintf(stderr, "valid file, point outside its node's cube on axis %d\n", k);
                        std::abort();
                    }
                }
            }
        }
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what(), true);
        if (valid) {
            std::fprintf(stderr, "valid file, reader refused: %s\n", e.what());
            std::abort();
        }
    }
    return 0;
}
