// app/src/view_index.hpp: the path a cloud file that is not COPC takes in `view`: streamed
// and held whole (small clouds), or indexed into COPC first (once, into the user's cache
// folder, or into --index-to) and then read node by node; several files viewed as one
// survey always take the second path. docs/viewer.md, "Which path a cloud takes".
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace app {

/// What the in-core path holds per point: the point as read (40 bytes), its GPU copy (20)
/// and the pick index over it (24).
inline constexpr std::uint64_t kInCoreBytesPerPoint = 40 + 20 + 24;

struct ViewIndexOptions {
    /// Index a cloud whose in-core need (kInCoreBytesPerPoint times the points its header
    /// declares) is above this many MiB. 256 MiB is about 3.2 M points: the paper's 1.6 M
    /// point cloud (134 MiB) and the demo stay in core, where they load whole in one go
    /// and the default --point-budget (3 M) draws every point; above it the in-core path
    /// could no longer draw the whole cloud at once anyway.
    double index_above_mb = 256.0;
    /// The cache folder's bound: indexes least recently used are removed past it.
    double index_cache_mb = 10240.0;
    bool in_core = false;      // --in-core: the in-core path whatever the size
    std::string index_to;      // --index-to: index into this file, not the cache
    double memory_mb = 512.0;  // the writer's bound while indexing (--memory-mb)
};

/// "--index-above-mb" etc. out of range, or --in-core with --index-to: throws
/// Error("view: --index-above-mb X: allowed [0, 1048576]") and the like.
void validate(const ViewIndexOptions& o);

enum class ViewPath { InCore, IndexReused, IndexedNow };

struct ViewCloud {
    ViewPath path = ViewPath::InCore;
    std::filesystem::path copc;  // the index to open (empty in core)
};

/// Whether `cloud` (a regular file that is not COPC, already checked as an input) is to
/// be indexed: --index-to, or not --in-core and its header's points over --index-above-mb
/// (a header that does not read: false, so the in-core path says what is wrong).
bool shouldIndex(const std::filesystem::path& cloud, const ViewIndexOptions& o);

/// Finds or writes the index of `cloud`: progress lines while indexing, then one line
/// naming the path taken ("ladarvr: view: X is not COPC: indexed now into ..." or "...:
/// its cached index ... is reused"). With `force_reindex` a cached index is written again
/// (it did not open). Throws Error("view: ...") naming the cache folder, the index or the
/// option.
ViewCloud indexForView(const std::filesystem::path& cloud, const ViewIndexOptions& o, bool force_reindex = false);

/// The same for several cloud files viewed as one survey (their points merged, in the
/// order given): one index, cached under a key from every file's identity (a changed file
/// gives another), or written into --index-to. The lines name "the survey of N files".
/// Throws Error("view: ...") as indexForView, and as `index` when the files cannot be
/// merged (their fields differ, or they lie more than 10 km apart).
ViewCloud indexSurveyForView(const std::vector<std::filesystem::path>& clouds, const ViewIndexOptions& o,
                             bool force_reindex = false);

}  // namespace app
