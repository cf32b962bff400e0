// io/copc_writer.hpp: writing clouds as COPC 1.0 files (io/copc.hpp describes the format).
//
// The writer holds the cloud in memory (or spills it to scratch files past a bound), builds the octree (io/src/copc/copc_octree.hpp:
// a cube around the points, grid-sampled nodes of at most CopcOptions::max_node_points),
// has LASzip compress each node as one variable-size LAZ chunk on LasOptions::threads
// threads, and writes the file through the same temporary-and-rename path as every cloud
// writer (CloudWriter with CloudFormat::Copc). The points' records are the LAS writer's
// (point format 7, or 6 without colour; our extra bytes; scale 1 mm, offsets = origin).
// The file is the same for any thread count.
#pragma once
#include <core/point_cloud.hpp>
#include <io/cloud_io.hpp>

#include <io/copc.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>

namespace io {

/// The node cap CopcOptions starts with. Large nodes keep long runs of each scan line
/// together, which LAZ compresses well, and leave fewer sampled levels above the leaves;
/// small ones let a viewer load the cloud in finer steps.
inline constexpr std::uint32_t kDefaultMaxNodePoints = 400000;
/// The node caps the commands accept (--node-points): below, a node's chunk and hierarchy
/// entry cost more than its points; above, a reader decodes tens of megabytes for one node.
inline constexpr std::uint32_t kLeastNodeCap = 100;
inline constexpr std::uint32_t kMostNodeCap = 4000000;

struct CopcOptions {
    /// The most points a node holds (a node whose cube is 1 mm wide holds all its points).
    std::uint32_t max_node_points = kDefaultMaxNodePoints;
    /// The most the writer holds (0: no bound, every point in memory). Past it the points
    /// go to anonymous scratch files in the output's folder and the octree is built a part
    /// at a time (io/src/copc/copc_writer.cpp); the file is the same either way. Throws
    /// at finish when the bound is below what one node needs (copcMinimumBytes).
    std::uint64_t memory_bytes = 0;
};

/// Bytes the COPC writer holds per point while it builds and writes a file (the points,
/// their integer coordinates, the octree's indices), for callers that plan memory.
std::uint64_t copcBytesPerPoint();
/// Bytes the COPC writer holds besides its points (the nodes being compressed, the
/// sampling grids of its threads), with `threads` worker threads and nodes of at most
/// `max_node_points`.
std::uint64_t copcFixedBytes(int threads, std::uint32_t max_node_points = kDefaultMaxNodePoints);

/// The least CopcOptions::memory_bytes that a cloud of any size can be written in, with
/// `threads` worker threads and nodes of at most `max_node_points`.
std::uint64_t copcMinimumBytes(int threads, std::uint32_t max_node_points = kDefaultMaxNodePoints);

/// Writes `cloud` as a COPC file at `path`, atomically (as writeCloud does), with its
/// foreign side records where it has them. Throws Error("output: <path>: ...").
void writeCopc(const std::filesystem::path& path, const core::PointCloud& cloud, const LasOptions& las = {},
               const CopcOptions& copc = {});

/// Writes a COPC file from nodes the caller has made already: for data that is an octree
/// before it is a file (a synthetic survey too large to hold or spill, a tiled source).
/// The cube is centred on `origin`, with an edge of 2^bits mm; each node's points must
/// lie in its key's cube, and a key comes once. Ancestors that were never added become
/// empty nodes of the hierarchy. The records, the layout and the atomic output are those
/// of writeCopc. Nothing checks that a node's points are a sample of its children's:
/// that is the caller's promise. Throws Error("output: <path>: ...").
class CopcNodeWriter {
  public:
    struct Node {
        CopcKey key;
        std::span<const core::CloudPoint> points;
    };

    /// `bits` in [1, 31]; LasOptions::threads compress the nodes of each add().
    CopcNodeWriter(const std::filesystem::path& path, const glm::dvec3& origin, const core::CloudFields& fields,
                   int bits, const LasOptions& las = {});
    ~CopcNodeWriter();
    CopcNodeWriter(const CopcNodeWriter&) = delete;
    CopcNodeWriter& operator=(const CopcNodeWriter&) = delete;

    /// Compresses `nodes` on the threads and writes them, in this order.
    void add(std::span<const Node> nodes);
    /// Writes the chunk table and the hierarchy, then renames the file into place.
    void commit();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace io
