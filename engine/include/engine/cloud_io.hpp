// engine/cloud_io.hpp: PCD and PLY reading and (atomic, streaming) writing.
//
// Files carry the fields x y z (float, local frame), rgb (PCL's packed float),
// label (uint8: 0 ground, 1 environment, 2 target), view (uint16), range (float),
// and the double-precision origin as a header comment
// ("# ladarvr origin X Y Z" in PCD, "comment ladarvr origin X Y Z" in PLY), so
// world = origin + (x, y, z). Readers of PCL, Open3D and CloudCompare load them.
#pragma once
#include <engine/point_cloud.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace engine {

class TempFile;

enum class CloudFormat { PcdBinary, PcdAscii, PlyBinary, PlyAscii };

/// From a name: "pcd" (binary), "pcd-ascii", "ply" (binary), "ply-ascii".
/// Throws Error("<parameter>: format 'x' is not one of pcd, pcd-ascii, ply, ply-ascii").
CloudFormat parseCloudFormat(std::string_view name, std::string_view parameter);
/// The default format for a path: .ply -> PlyBinary, anything else -> PcdBinary.
CloudFormat formatForPath(const std::filesystem::path& path);

/// Writes a cloud of unknown final size in a stream: points are appended in chunks,
/// nothing is held in memory. The data go to an engine::TempFile in the same folder
/// (engine/safe_file.hpp) and commit() renames it to `path`; destroying the writer
/// without commit() removes the temporary file, so a failed run never leaves a truncated
/// file under the final name.
class CloudWriter {
public:
    /// Throws Error("output: <path>: ...") if the directory is missing or not writable, or
    /// `path` exists and is not a regular file, or is an input of this run.
    CloudWriter(std::filesystem::path path, CloudFormat format, glm::dvec3 origin,
                CloudFields fields = {});
    ~CloudWriter();
    CloudWriter(const CloudWriter&) = delete;
    CloudWriter& operator=(const CloudWriter&) = delete;

    void append(std::span<const CloudPoint> points);
    /// Fixes up the point count in the header, flushes, renames into place.
    void commit();
    std::size_t count() const { return count_; }

private:
    std::filesystem::path path_;
    CloudFormat format_;
    CloudFields fields_;
    std::unique_ptr<TempFile> temp_;
    std::FILE* file_ = nullptr;  // temp_'s stream while writing
    long count_offset_[2] = {-1, -1};
    std::size_t count_ = 0;
    std::string buffer_;
};

/// Writes a whole cloud atomically (a CloudWriter in one go).
void writeCloud(const std::filesystem::path& path, const PointCloud& cloud,
                CloudFormat format);

/// Reads PCD (ascii, binary, binary_compressed) or PLY (ascii, binary either endian)
/// whole, through engine::CloudReader (cloud_reader.hpp). Needs x y z; rgb/rgba, label,
/// view, range are used when present (fields says which). Points with a non-finite x, y,
/// z or range are dropped, with one warning line on stderr giving the count.
/// Throws Error("pcd: <file>: ...") / ("ply: <file>: ...") naming the line or field.
PointCloud readCloud(const std::filesystem::path& path);

/// As readCloud, from the file's bytes already in memory (no warning is printed);
/// `name` is used in messages. Never reads outside `bytes` whatever they hold.
PointCloud readCloudData(std::string_view bytes, const std::filesystem::path& name);

}  // namespace engine
