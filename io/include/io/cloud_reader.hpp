// io/cloud_reader.hpp: the one point cloud reader, chunk by chunk.
//
// Opening a file checks its whole header (every field, the counts against each other and
// the data size against the file) before the first point; nextChunk then decodes the
// points in order, a bounded number at a time, so a viewer can show the first points
// while the rest is read and the whole-cloud readCloud is the same code in one loop.
// Points with a non-finite x, y, z or range (NaN, inf, or a double beyond float range)
// are dropped and counted (docs/formats.md).
#pragma once
#include <core/point_cloud.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace io {

namespace detail {
class ByteSource;
class FormatReader;
}  // namespace detail

/// Whether a reader gives a foreign LAS/LAZ/COPC file's side records (CloudReader).
enum class SideRecords { Drop, Keep };

/// What a reader must decode of each point (CloudReader). Positions: each point's
/// position, its return number and returns, its view (LAS point source ID) and whatever
/// decides which points are left out (the range); its other fields are unspecified. The same points come in the same
/// order either way; a LAZ file of LAS 1.4 point formats 6-10 (COPC's) is then read
/// faster, its other fields' layers skipped.
enum class PointFields { All, Positions };

class CloudReader {
  public:
    static constexpr std::size_t kChunkPoints = 1u << 18;

    /// Opens a PCD (ascii, binary, binary_compressed), PLY (ascii, binary either
    /// endian) or LAS/LAZ (1.0-1.4) file; the content decides, not the extension. Throws
    /// Error("pcd: <file>: ...") / ("ply: ...") / ("las: ...") naming the line or field.
    explicit CloudReader(const std::filesystem::path& path);
    /// The same; with SideRecords::Keep, a LAS/LAZ/COPC file made by another producer (one
    /// without our `label` extra bytes) also gives each point's side record
    /// (core::ForeignPoint and its extra bytes) to nextChunk's `records`, and its header
    /// facts to foreignHeader().
    CloudReader(const std::filesystem::path& path, SideRecords side);
    /// The same without side records, decoding what `fields` asks for.
    CloudReader(const std::filesystem::path& path, PointFields fields);
    /// The same over bytes in memory, which must outlive the reader; `name` is used in
    /// messages; `side` as above. Never reads outside `bytes` whatever they hold (the fuzzing entry point).
    CloudReader(std::string_view bytes, const std::filesystem::path& name, SideRecords side = SideRecords::Drop,
                PointFields fields = PointFields::All);
    ~CloudReader();
    CloudReader(const CloudReader&) = delete;
    CloudReader& operator=(const CloudReader&) = delete;

    /// "pcd: <file>", "ply: <file>" or "las: <file>", as the messages start.
    const std::string& where() const { return prefix_; }
    const glm::dvec3& origin() const;
    const core::CloudFields& fields() const;
    /// The point count the header declares (non-finite points included).
    std::size_t declaredPoints() const;
    /// At most this many points can be in the data (the declared count where the file's
    /// size confirms it): a safe amount to reserve.
    std::size_t pointsBound() const;
    /// The foreign file's header facts where the reader keeps side records, else null.
    std::shared_ptr<const core::ForeignHeader> foreignHeader() const;

    /// Appends the next points, at most `max_points` (>= 1) of the file's records, to
    /// `out`, leaving out non-finite ones. Returns false, appending nothing, once every
    /// point has been read and the end of the data checked. Throws Error on bad data
    /// (points returned before stay valid).
    bool nextChunk(std::vector<core::CloudPoint>& out, std::size_t max_points = kChunkPoints);
    /// The same, appending each point's side record to `records` where foreignHeader()
    /// is set (nothing otherwise).
    bool nextChunk(std::vector<core::CloudPoint>& out, std::vector<unsigned char>& records,
                   std::size_t max_points = kChunkPoints);

    /// Records decoded so far, and how many of them were dropped as non-finite.
    std::size_t pointsRead() const { return read_; }
    std::size_t droppedNonFinite() const { return dropped_; }
    /// "<pcd|ply|las>: <file>: dropped N of M points with a non-finite x, y, z or range
    /// (NaN or inf)" when points were dropped, and/or "N points have an ASPRS class this
    /// reader does not know (the first: C); read as environment", on one line; else empty.
    std::string warning() const;

  private:
    std::string prefix_;
    std::unique_ptr<detail::ByteSource> source_;
    std::unique_ptr<detail::FormatReader> format_;
    std::size_t read_ = 0, dropped_ = 0;
};

/// The header facts for several readers' points written as one file: the first's (the
/// caller checked that their layouts and CRS agree) at the finest scale among them, with
/// that reader's offset, so that its points keep their integer coordinates (the finest
/// scale: the least on any axis; the first of equals). Null where the first has none.
std::shared_ptr<const core::ForeignHeader> mergedForeignHeader(
    const std::vector<std::unique_ptr<CloudReader>>& readers);

/// Calls fn(chunk) for each chunk reader.nextChunk() gives, in order, while the next chunk
/// is read on a thread of its own: decoding the file overlaps what fn does with the
/// points, and two chunks are held at once. fn may change or empty the chunk it is given.
/// An error of the reading or of fn is rethrown once neither is running.
void forEachChunk(CloudReader& reader, const std::function<void(std::vector<core::CloudPoint>&)>& fn);
/// The same with each chunk's side records (empty unless reader.foreignHeader() is set);
/// fn may change them but must keep one per point.
void forEachChunk(CloudReader& reader,
                  const std::function<void(std::vector<core::CloudPoint>&, std::vector<unsigned char>&)>& fn);

}  // namespace io
