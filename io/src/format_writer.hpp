// io/src/format_writer.hpp (internal): one cloud format's writer behind io::CloudWriter,
// as io/src/cloud_decode.hpp's FormatReader is one format's reader behind CloudReader.
// Each writes into a TempFile that CloudWriter opened and commits after finish().
#pragma once
#include <io/cloud_io.hpp>
#include <io/copc_writer.hpp>

#include <memory>
#include <span>
#include <stdexcept>

namespace io::detail {

class FormatWriter {
  public:
    virtual ~FormatWriter() = default;
    /// Appends points. Throws Error("output: <path>: ...") (a failed write, a point a
    /// format cannot hold).
    virtual void append(std::span<const core::CloudPoint> points) = 0;
    /// Appends points with their side records (LasOptions::foreign's stride() bytes each):
    /// the LAS, LAZ and COPC writers write them back; the others drop them.
    virtual void appendForeign(std::span<const core::CloudPoint> points, const unsigned char* /*records*/) {
        append(points);
    }
    /// CloudWriter::prescanPasses and prescan: none, unless the format says otherwise.
    virtual int prescanPasses(std::uint64_t /*points*/, const core::Bounds* /*positions*/) { return 0; }
    virtual void prescan(int /*pass*/, std::span<const core::CloudPoint> /*points*/) {}
    /// CloudWriter::rewritable, readBack and rewrite: none, unless the format says otherwise.
    virtual bool rewritable() const { return false; }
    virtual std::size_t recordBytes() const { return 0; }
    virtual std::size_t readBack(std::uint64_t /*first*/, std::span<core::CloudPoint> /*out*/) {
        throw std::logic_error("io: this format's points cannot be read back");
    }
    virtual void rewrite(std::uint64_t /*first*/, std::span<const core::CloudPoint> /*points*/) {
        throw std::logic_error("io: this format's points cannot be rewritten");
    }
    /// CloudWriter::packRecords and appendRecords (`count` records): rewritable formats only.
    virtual void packRecords(std::span<const core::CloudPoint> /*points*/, char* /*out*/) const {
        throw std::logic_error("io: this format's records cannot be packed apart");
    }
    virtual void appendRecords(const char* /*records*/, std::size_t /*count*/) {
        throw std::logic_error("io: this format's records cannot be appended packed");
    }
    /// Completes the file (the header's counts, LAS bounds, LAZ's chunk table) and
    /// flushes; the caller then commits the TempFile. Throws Error("output: <path>: ...").
    virtual void finish() = 0;
};

/// PCD v0.7, binary or ascii (pcd/pcd_writer.cpp).
std::unique_ptr<FormatWriter> openPcdWriter(platform::TempFile& file, bool ascii, const glm::dvec3& origin,
                                            const core::CloudFields& fields);
/// PLY 1.0, binary little endian or ascii (ply/ply_writer.cpp).
std::unique_ptr<FormatWriter> openPlyWriter(platform::TempFile& file, bool ascii, const glm::dvec3& origin,
                                            const core::CloudFields& fields);
/// LAS 1.4 (las/las_writer.cpp): point format 7 (6 without fields.rgb), scale 0.001 m, the
/// offsets `origin` (so a point's integer coordinates are its local position in millimetres).
std::unique_ptr<FormatWriter> openLasWriter(platform::TempFile& file, const glm::dvec3& origin,
                                            const core::CloudFields& fields, const LasOptions& options);
/// LAZ (las/laz_writer.cpp): the same records, LASzip compressing chunks of
/// lazChunkPoints() points on options.threads threads, joined in order with their table.
std::unique_ptr<FormatWriter> openLazWriter(platform::TempFile& file, const glm::dvec3& origin,
                                            const core::CloudFields& fields, const LasOptions& options);

/// COPC (copc/copc_writer.cpp over the stages in copc/writer/): the LAZ writer's records in
/// an octree of variable-size chunks, built once every point has arrived (held in memory
/// up to the writer's bound, spilled to scratch files past it).
std::unique_ptr<FormatWriter> openCopcWriter(platform::TempFile& file, const glm::dvec3& origin,
                                             const core::CloudFields& fields, const LasOptions& las,
                                             const CopcOptions& copc);

}  // namespace io::detail
