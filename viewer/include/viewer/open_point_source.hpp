// viewer/open_point_source.hpp: the one place that decides how a cloud file reaches the
// viewer. A COPC file is read node by node (CopcSource); a file that is not COPC is read
// node by node from a COPC index of it when the caller's indexer wants one, else streamed
// and held whole (CloudFeed). `view`, `study` and `bench view` all open clouds here, so
// they take the same path for the same file; the indexing itself (writing a COPC file,
// the cache folder) stays with the caller, which links the writers.
#pragma once
#include <viewer/cloud_feed.hpp>
#include <viewer/copc_source.hpp>

#include <filesystem>
#include <memory>
#include <string>

namespace viewer {

/// How a cloud file is read for viewing.
enum class SourcePath {
    Copc,     // the file is COPC: node by node
    Indexed,  // not COPC: node by node from its COPC index
    Whole,    // not COPC: streamed and held whole
};

/// Makes or finds the COPC index of a cloud file that is not COPC.
class CloudIndexer {
  public:
    virtual ~CloudIndexer() = default;
    /// Whether `cloud` is to be read through an index rather than held whole.
    virtual bool wantsIndex(const std::filesystem::path& cloud) = 0;
    /// The COPC index of `cloud` to read. A non-empty `failed_open` is the error the index
    /// returned before gave when opened: return one written again, or an empty path to
    /// give up (that error is then thrown).
    virtual std::filesystem::path index(const std::filesystem::path& cloud, const std::string& failed_open) = 0;
};

/// Whether the caller needs every point of the cloud at once (a study judges a designation
/// against every target point, which the resident nodes of a COPC file would not give).
enum class EveryPoint { NotNeeded, Needed };

/// The path `cloud` takes: Whole when every point is needed; else Copc when
/// io::isCopcFile says so, else Indexed when `indexer` (may be null: never) wants an
/// index, else Whole. Writes nothing.
SourcePath choosePath(const std::filesystem::path& cloud, CloudIndexer* indexer,
                      EveryPoint every_point = EveryPoint::NotNeeded);

struct OpenSourceOptions {
    CopcSourceOptions copc;           // for the Copc and Indexed paths
    CloudIndexer* indexer = nullptr;  // needed for the Indexed path
    /// Whole: stream into this feed (as its owner set it up) instead of a new one.
    CloudFeed* feed = nullptr;
};

/// A cloud file opened for viewing: one of `copc` (node by node) and `feed` (streamed,
/// its loader thread started) is set; neither when it streams into OpenSourceOptions::feed.
struct OpenedCloud {
    SourcePath path = SourcePath::Whole;
    std::filesystem::path file;  // what is read: the cloud itself, or its index
    std::unique_ptr<CopcSource> copc;
    std::unique_ptr<CloudFeed> feed;
};

/// Opens `cloud` on `path` (choosePath's answer). Throws core::Error naming the file when a
/// COPC file or index does not open; a streamed file's errors come through the feed.
OpenedCloud openPointSource(const std::filesystem::path& cloud, SourcePath path, const OpenSourceOptions& options);

}  // namespace viewer
