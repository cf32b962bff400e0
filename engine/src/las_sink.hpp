// engine/src/las_sink.hpp (internal): the LAS/LAZ side of engine::CloudWriter
// (las_writer.cpp: LAS; laz_writer.cpp: LAZ, chunks compressed in parallel).
#pragma once
#include <engine/cloud_io.hpp>

#include <memory>
#include <span>

namespace engine::detail {

/// Streams points into a LAS 1.4 (or LAZ) file on a TempFile's stream.
class LasSink {
public:
    virtual ~LasSink() = default;
    /// Throws Error("output: <path>: ...") (a point beyond the 1 mm grid's reach, a
    /// LASzip failure).
    virtual void append(std::span<const CloudPoint> points) = 0;
    /// Writes the header's counts and bounds (and LAZ's chunk table) and flushes; the
    /// caller then commits the TempFile.
    virtual void finish() = 0;
};

/// Opens the writer: point format 7 (6 without fields.rgb), scale 0.001 m, the offsets
/// `origin` (so a point's integer coordinates are its local position in millimetres).
/// Throws Error("output: <path>: ...").
std::unique_ptr<LasSink> openLasSink(TempFile& file, bool compress, const glm::dvec3& origin,
                                     const CloudFields& fields, const LasOptions& options);

class LasRecord;
/// The LAZ writer (laz_writer.cpp): LASzip compresses chunks of lazChunkPoints() points
/// on options.threads threads, the chunks are joined in order with their table.
std::unique_ptr<LasSink> openLazSink(TempFile& file, LasRecord record, const LasOptions& options);

}  // namespace engine::detail
