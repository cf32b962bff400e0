// io/cloud_io.hpp: PCD, PLY and LAS/LAZ reading and (atomic, streaming) writing.
//
// PCD and PLY files carry the fields x y z (float, local frame), rgb (PCL's packed float;
// red green blue in PLY), label (uint8: 0 ground, 1 environment, 2 target), view, range
// (float), the optional fields CloudFields turns on, and the double-precision origin as a
// header comment ("# ladarvr origin X Y Z" in PCD, "comment ladarvr origin X Y Z" in
// PLY), so world = origin + (x, y, z). LAS/LAZ hold world coordinates at 1 mm. Readers
// of PCL, Open3D, CloudCompare, laspy and PDAL load them (docs/formats.md).
#pragma once
#include <core/frames.hpp>
#include <core/point_cloud.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace platform {
class TempFile;
}

namespace io {

class CloudReader;
struct CopcOptions;  // io/copc_writer.hpp

namespace detail {
class FormatWriter;  // one format's writer (io/src/format_writer.hpp)
}

enum class CloudFormat { PcdBinary, PcdAscii, PlyBinary, PlyAscii, Las, Laz, Copc };

/// From a name: "pcd" (binary), "pcd-ascii", "ply" (binary), "ply-ascii", "las", "laz",
/// "copc" (a COPC 1.0 LAZ file, io/copc_writer.hpp).
/// Throws Error("<parameter>: format 'x' is not one of pcd, pcd-ascii, ply, ply-ascii, las, laz, copc").
CloudFormat parseCloudFormat(std::string_view name, std::string_view parameter);
/// The format for a path's extension (any case): .pcd or none -> PcdBinary, .ply ->
/// PlyBinary, .las, .laz, and Copc for a name ending in .copc.laz. Throws
/// Error("<parameter>: <path>: extension 'x' is not one of .pcd, .ply, .las, .laz,
/// .copc.laz") for any other extension, so a cloud never lands under a misleading name.
CloudFormat formatForPath(const std::filesystem::path& path, std::string_view parameter = "output");
/// The name parseCloudFormat takes for `format` ("pcd", ..., "laz", "copc").
const char* cloudFormatName(CloudFormat format);

/// What a LAS/LAZ file needs beyond the points (docs/formats.md).
struct LasOptions {
    /// ASPRS classification written for each role (Ground, Environment, Target):
    /// 2 ground, 1 unclassified, 64 (the first user-definable class).
    std::uint8_t class_of_role[core::kRoleCount] = {2, 1, 64};
    /// GPS time of view v: gps_start_s + v * view_interval_s (the drone's time along
    /// the orbit).
    double gps_start_s = 0.0;
    double view_interval_s = 1.0;
    /// LAZ: chunks of points compressed at once, on this many threads besides the
    /// caller's (0: all on the caller's thread). The file is the same whatever the count.
    int threads = 0;
    /// LAZ: the most the writer holds in chunks being filled, waiting or being compressed
    /// (lazChunkBytes() each; two at least). 0: what `threads` can use, threads + 2 chunks.
    std::uint64_t memory_bytes = 0;
    /// Set for points read from another producer's file (CloudReader::foreignHeader()):
    /// the records then take their class, class flags, GPS time, 16-bit colour, near
    /// infrared, user data, point source ID and extra bytes from each point's side record
    /// (CloudWriter::append with records), the file gets the CRS as an OGC WKT record, and
    /// our label, view and range are not added (class_of_role and the GPS times above are
    /// unused). Of our fields only height_above_ground is added, as PDAL's
    /// `HeightAboveGround` (written in place where the source has that field already).
    std::shared_ptr<const core::ForeignHeader> foreign;
};

/// Points per LAZ chunk (LASzip's default chunk size): the unit a LAZ reader can seek
/// to, and the unit the writer compresses on one thread.
std::size_t lazChunkPoints();
/// What one LAZ chunk waiting for compression holds (its points and their compressed
/// bytes), for callers that plan memory around LasOptions::memory_bytes.
std::uint64_t lazChunkBytes();

/// Writes a cloud of unknown final size in a stream: points are appended in chunks,
/// nothing is held in memory. The data go to a platform::TempFile in the same folder
/// (platform/safe_file.hpp) and commit() renames it to `path`; destroying the writer
/// without commit() removes the temporary file, so a failed run never leaves a truncated
/// file under the final name.
class CloudWriter {
  public:
    /// Throws Error("output: <path>: ...") if the directory is missing or not writable, or
    /// `path` exists and is not a regular file, or is an input of this run.
    /// LAS/LAZ/COPC use `las`; with fields.rgb off they use point format 6, else 7. COPC
    /// holds the points in memory until commit() (io/copc_writer.hpp).
    /// COPC uses `copc` when given, else the default CopcOptions.
    CloudWriter(std::filesystem::path path, CloudFormat format, glm::dvec3 origin, core::CloudFields fields = {},
                const LasOptions& las = {}, const CopcOptions* copc = nullptr);
    ~CloudWriter();
    CloudWriter(const CloudWriter&) = delete;
    CloudWriter& operator=(const CloudWriter&) = delete;

    void append(std::span<const core::CloudPoint> points);
    /// Appends points with their side records (LasOptions::foreign's stride() bytes each,
    /// in the points' order). LAS, LAZ and COPC write them back; other formats drop them.
    void append(std::span<const core::CloudPoint> points, std::span<const unsigned char> records);
    /// How many times the writer asks to see the `points` points it is about to get before
    /// they are appended: 0 for most formats. A COPC writer that would spill them to
    /// scratch files (past CopcOptions::memory_bytes) asks for 2: it learns their bounds,
    /// then how they spread, and sorts them straight into the octree's parts as they are
    /// appended (the same file, written sooner); for 1 when `positions` gives the least
    /// box holding their positions. Ask before the first append; a caller that cannot
    /// give its points again appends them without asking.
    int prescanPasses(std::uint64_t points, const core::Bounds* positions = nullptr);
    /// Gives pass `pass` (0 up to the passes asked for) every point, in the order append()
    /// will get them; only their positions are read. Throws Error("output: <path>: ...")
    /// when the passes, the bounds given or the points appended after them differ in
    /// count or position.
    void prescan(int pass, std::span<const core::CloudPoint> points);
    /// Whether the points appended can be read back and overwritten in place before
    /// commit(): binary PCD and PLY, whose records all have one size and hold each field
    /// they carry bit for bit. A caller whose points change after they are first written
    /// (a colour known only once all have been seen) can then keep them in the output
    /// alone instead of a copy of its own.
    bool rewritable() const;
    /// Reads back the points appended [first, first + out.size()), as far as there are;
    /// returns how many. The fields the file carries come back as appended, the others as
    /// CloudPoint's defaults. Throws std::logic_error where !rewritable(), and
    /// Error("output: <path>: ...") when the read fails. Once one call to readBack or
    /// rewrite has returned, two threads may read back and rewrite disjoint ranges at once.
    std::size_t readBack(std::uint64_t first, std::span<core::CloudPoint> out);
    /// The bytes of one point's record where rewritable(), else 0.
    std::size_t recordBytes() const;
    /// Where rewritable(): packs `points` into `out` (recordBytes() each) as append()
    /// would write them, appending nothing. Const: several threads may pack at once,
    /// beside anything else the writer does. Throws std::logic_error where !rewritable().
    void packRecords(std::span<const core::CloudPoint> points, char* out) const;
    /// Appends records packRecords() made (a whole number of them), as append() would
    /// have appended their points. Throws std::logic_error where !rewritable() or the
    /// bytes are not whole records, and Error("output: <path>: ...") when the write fails.
    void appendRecords(std::span<const char> records);
    /// Overwrites the points appended [first, first + points.size()) with `points`.
    /// Throws std::logic_error where !rewritable() or past the points appended, and
    /// Error("output: <path>: ...") when the write fails.
    void rewrite(std::uint64_t first, std::span<const core::CloudPoint> points);
    /// Fixes up the point count in the header, flushes, renames into place.
    void commit();
    std::size_t count() const { return count_; }

  private:
    std::filesystem::path path_;
    std::unique_ptr<platform::TempFile> temp_;
    std::unique_ptr<detail::FormatWriter> writer_;  // null once committed
    std::size_t count_ = 0;
    std::size_t foreign_stride_ = 0;  // LasOptions::foreign's side record bytes; 0 without
};

/// Writes a whole cloud atomically (a CloudWriter in one go); a cloud with foreign side
/// records (one per point) writes them back as LasOptions::foreign says.
void writeCloud(const std::filesystem::path& path, const core::PointCloud& cloud, CloudFormat format,
                const LasOptions& las = {});

/// Reads PCD (ascii, binary, binary_compressed), PLY (ascii, binary either endian) or
/// LAS/LAZ whole, through io::CloudReader (cloud_reader.hpp). Needs x y z; rgb/rgba, label,
/// view, range are used when present (fields says which). Points with a non-finite x, y,
/// z or range are dropped, with one warning line on stderr giving the count.
/// Throws Error("pcd: <file>: ...") / ("ply: <file>: ...") naming the line or field.
core::PointCloud readCloud(const std::filesystem::path& path);
/// As readCloud, from a reader already open (its header checked): a caller can weigh
/// reader.pointsBound() against a memory budget before a point is read.
core::PointCloud readCloud(CloudReader& reader);

/// As readCloud, from the file's bytes already in memory (no warning is printed);
/// `name` is used in messages. Never reads outside `bytes` whatever they hold.
core::PointCloud readCloudData(std::string_view bytes, const std::filesystem::path& name);

}  // namespace io
