// viewer/src/pcd_stream.hpp: reads a binary PCD chunk by chunk into a CloudFeed, so the
// viewer shows the first points while the rest of a large file is still being read.
#pragma once
#include <viewer/cloud_feed.hpp>

#include <filesystem>

namespace viewer {

/// If `path` is an uncompressed binary PCD with float x y z, streams it into `feed`
/// (origin from the "# ladarvr origin X Y Z" comment) and returns true. Returns false
/// without feeding anything for any other file (the caller uses engine::readCloud, which
/// also gives the precise errors). Throws engine::Error("pcd: <file>: ...") if the data
/// section is truncated after streaming started.
bool streamBinaryPcd(const std::filesystem::path& path, CloudFeed& feed, std::size_t chunk_points);

}  // namespace viewer
