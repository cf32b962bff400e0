// fuzz/fuzz_copc_reader.cpp: libFuzzer target for COPC reading (io/src/copc/: the layout
// parse, the validator behind `index --check` and io::CopcReader's node-by-node reads, with
// LASzip decoding each node's chunk). Every input is made to start with "LASF" so each
// mutation reaches the COPC code, and is written to a scratch file because both entry
// points take a path. Each input is read the three ways the program reads COPC: the whole
// hierarchy at once with every node decoded (`index --check`, the reader's default); the
// hierarchy by page under an entry bound, child pages read one by one, with a foreign
// file's side records kept (the viewer); and positions only (the ground fit). The contract:
// - checkCopc never throws and every finding is one printable ASCII line;
// - CopcReader opens the file or throws core::Error of one printable line, and so does
//   each readPage, readNode and readNodeEntry;
// - a file with no finding opens both ways, its pages read, the pages reach exactly the
//   nodes the whole hierarchy holds, and each node it decodes gives exactly its point
//   count, every point finite and inside its node's cube (to a scale unit), with one side
//   record per point where they are kept.
// Seeds: fuzz/seeds/copc (files written by `ladarvr index`, and two of tests/io/copc_tool
// with a child page).
#include "check_message.hpp"

#include <core/error.hpp>
#include <io/copc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

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

// Aborts unless a node of a valid file decoded to exactly its points, each finite and
// inside the node's cube, with one side record per point where the reader kept them.
void checkNodePoints(const io::CopcInfo& info, const io::CopcNode& node, const core::PointCloud& pts) {
    if (pts.points.size() != std::size_t(node.point_count)) std::abort();
    if (pts.foreign && pts.foreign->records.size() != pts.points.size() * pts.foreign->header.stride()) {
        std::fprintf(stderr, "valid file, %zu side record bytes for %zu points\n", pts.foreign->records.size(),
                     pts.points.size());
        std::abort();
    }
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

// The viewer's and the ground fit's reads: the hierarchy by page under an entry bound
// (an input of at most 64 KiB holds fewer entries, so a valid file is never refused by
// it), child pages read as a client reaches them, and a few nodes decoded with the side
// records kept or positions only. `whole_nodes` is what the whole hierarchy held (empty
// when it was refused).
void readByPage(const std::filesystem::path& file, bool valid, const std::vector<io::CopcNode>& whole_nodes) {
    constexpr std::uint64_t kPageEntriesMax = 4096;
    constexpr std::size_t kPagesMax = 64;  // pages read per input
    constexpr std::size_t kNodesMax = 4;   // nodes decoded per input, each way
    try {
        io::CopcReader reader(file, io::CopcHierarchy::by_page, kPageEntriesMax, "the fuzz target's bound");
        const io::CopcInfo& info = reader.info();
        std::vector<io::CopcNode> nodes = reader.nodes();
        std::vector<io::CopcPage> pages = reader.pages();
        std::size_t pages_read = 0;
        while (!pages.empty() && pages_read < kPagesMax) {
            const io::CopcPage page = pages.back();
            pages.pop_back();
            ++pages_read;
            try {
                io::CopcPageEntries entries = reader.readPage(page);
                nodes.insert(nodes.end(), entries.nodes.begin(), entries.nodes.end());
                pages.insert(pages.end(), entries.pages.begin(), entries.pages.end());
            } catch (const core::Error& e) {
                fuzz::checkMessage(e.what(), true);
                if (valid) {
                    std::fprintf(stderr, "valid file, page refused: %s\n", e.what());
                    std::abort();
                }
            }
        }
        if (valid && pages.empty()) {
            std::vector<io::CopcKey> by_page, whole;
            for (const io::CopcNode& n : nodes) by_page.push_back(n.key);
            for (const io::CopcNode& n : whole_nodes) whole.push_back(n.key);
            std::sort(by_page.begin(), by_page.end());
            std::sort(whole.begin(), whole.end());
            if (by_page != whole) {
                std::fprintf(stderr, "valid file, %zu nodes by page against %zu in the whole hierarchy\n",
                             by_page.size(), whole.size());
                std::abort();
            }
        }
        for (std::size_t i = 0; i < nodes.size() && i < 2 * kNodesMax; ++i) {
            core::PointCloud pts;
            try {
                pts = i % 2 == 0 ? reader.readNodeEntry(nodes[i], io::SideRecords::Keep)
                                 : reader.readNodeEntry(nodes[i], io::SideRecords::Drop, io::PointFields::Positions);
            } catch (const core::Error& e) {
                fuzz::checkMessage(e.what(), true);
                continue;
            }
            if (valid) checkNodePoints(info, nodes[i], pts);
        }
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what(), true);
        if (valid) {
            std::fprintf(stderr, "valid file, reader by page refused: %s\n", e.what());
            std::abort();
        }
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

    std::vector<io::CopcNode> whole_nodes;
    try {
        io::CopcReader reader(file);
        const io::CopcInfo& info = reader.info();
        whole_nodes = reader.nodes();
        for (const io::CopcNode& node : whole_nodes) {
            core::PointCloud pts;
            try {
                pts = reader.readNode(node.key);
            } catch (const core::Error& e) {
                // The LAS reader's own rules (our label field among them) may refuse a node
                // that the COPC rules accept; the refusal must still be one line.
                fuzz::checkMessage(e.what(), true);
                continue;
            }
            if (valid) checkNodePoints(info, node, pts);
        }
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what(), true);
        if (valid) {
            std::fprintf(stderr, "valid file, reader refused: %s\n", e.what());
            std::abort();
        }
    }
    readByPage(file, valid, whole_nodes);
    return 0;
}
