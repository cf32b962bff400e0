// io/src/copc/copc_node_writer.cpp: a COPC file from nodes the caller made
// (io::CopcNodeWriter in io/copc_writer.hpp): each add() checks its nodes, compresses them
// on the threads and hands them in order to the assembler the writer's front also uses
// (writer/assembler.hpp); commit() adds the missing ancestors as empty nodes.
#include "copc_octree.hpp"
#include "writer/assembler.hpp"
#include "writer/setup.hpp"

#include <core/error.hpp>
#include <io/copc_writer.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace io {

namespace {

// Nodes compressed at once per thread before they are written in order.
constexpr std::size_t kNodesPerThread = 4;

}  // namespace

struct CopcNodeWriter::Impl {
    platform::TempFile temp;
    detail::LasRecord record;
    detail::OctreeCube cube;
    int threads = 0;
    std::set<CopcKey> added;
    std::unique_ptr<detail::copc_writer::Assembler> out;
    bool committed = false;

    Impl(const std::filesystem::path& path, const glm::dvec3& origin, const core::CloudFields& fields, int bits,
         const LasOptions& las)
        : temp(path),
          record("output: " + path.string(), origin, fields, las, detail::LasRecord::Scales::One),
          threads(std::max(las.threads, 0)) {
        if (bits < 1 || bits > 31)
            throw core::Error("output: " + path.string() + ": a COPC cube of 2^" + std::to_string(bits) +
                              " mm; allowed bits 1 to 31");
        cube.bits = bits;
        cube.corner.fill(-(std::int64_t(1) << (bits - 1)));
        out = std::make_unique<detail::copc_writer::Assembler>(record, temp.file());
    }

    // One line naming the node and what is allowed.
    std::string nodeName(const CopcKey& k) const {
        return "node " + std::to_string(k.level) + "-" + std::to_string(k.x) + "-" + std::to_string(k.y) + "-" +
               std::to_string(k.z);
    }

    void checkNode(const Node& node) {
        const CopcKey& k = node.key;
        const std::int64_t side = k.level >= 0 && k.level <= cube.bits ? std::int64_t(1) << k.level : 0;
        if (side == 0 || k.x < 0 || k.y < 0 || k.z < 0 || k.x >= side || k.y >= side || k.z >= side)
            throw core::Error(record.where() + ": " + nodeName(k) + " is outside the octree; allowed levels 0 to " +
                              std::to_string(cube.bits) + " and x, y, z in [0, 2^level)");
        if (!added.insert(k).second) throw core::Error(record.where() + ": " + nodeName(k) + " was added before");
        const int shift = cube.bits - k.level;
        const std::int64_t key[3] = {k.x, k.y, k.z};
        for (std::size_t i = 0; i < node.points.size(); ++i) {
            const std::array<std::int32_t, 3> xyz = record.quantize(node.points[i], i);
            for (std::size_t a = 0; a < 3; ++a)
                if (((std::int64_t(xyz[a]) - cube.corner[a]) >> shift) != key[a])
                    throw core::Error(record.where() + ": point " + std::to_string(i) + " of " + nodeName(k) +
                                      " lies outside its cube");
        }
    }
};

CopcNodeWriter::CopcNodeWriter(const std::filesystem::path& path, const glm::dvec3& origin,
                               const core::CloudFields& fields, int bits, const LasOptions& las) {
    platform::checkWritableDestination(path);
    impl_ = std::make_unique<Impl>(path, origin, fields, bits, las);
}

CopcNodeWriter::~CopcNodeWriter() {
    if (impl_ && !impl_->committed) impl_->temp.discard();
}

void CopcNodeWriter::add(std::span<const Node> nodes) {
    Impl& m = *impl_;
    for (const Node& n : nodes) m.checkNode(n);
    std::vector<detail::LaszipFile> files(nodes.size());
    std::vector<detail::LasInventory> counted(nodes.size());
    detail::orderedParallel(
        nodes.size(), m.threads, kNodesPerThread * std::size_t(m.threads + 1),
        [&](std::size_t i) {
            if (!nodes[i].points.empty())
                files[i] = detail::compressWithLaszip(m.record, nodes[i].points, 0, counted[i],
                                                      detail::copc_writer::kVariableChunks);
        },
        [&](std::size_t i) {
            if (nodes[i].points.empty())
                m.out->addEmpty(nodes[i].key);
            else
                m.out->add(nodes[i].key, files[i], nodes[i].points.size(), counted[i]);
            files[i] = detail::LaszipFile{};
        });
}

void CopcNodeWriter::commit() {
    Impl& m = *impl_;
    // Every ancestor of a node is in the hierarchy, empty where it was never added.
    std::set<CopcKey> missing;
    for (const CopcKey& k : m.added)
        for (CopcKey a = k; a.level > 0;) {
            a = {a.level - 1, a.x >> 1, a.y >> 1, a.z >> 1};
            if (m.added.count(a) || !missing.insert(a).second) break;
        }
    if (m.added.empty()) missing.insert(CopcKey{});
    for (const CopcKey& a : missing) m.out->addEmpty(a);
    m.out->finish(m.cube);
    m.temp.commit();
    m.committed = true;
}

}  // namespace io
