// app/src/cloud_index.hpp: clouds written as one COPC index within a memory bound, the one
// way `ladarvr index` and `view` (which indexes a large cloud before it opens it) do it.
#pragma once
#include <io/cloud_io.hpp>
#include <io/copc_writer.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

namespace io {
class CloudReader;
}

namespace app {

/// Throws Error("<command>: <reader>: its LAS point layout or CRS (...) differs from
/// <first>'s (...); merged inputs must be alike"), "...: its fields (...) differ from
/// ...", or "...: its origin lies more than 10 km from <first>'s; ..." when `reader`'s
/// points cannot be merged into one index with `first`'s.
void checkMergeable(const io::CloudReader& reader, const io::CloudReader& first, std::string_view command);

/// The COPC writer's options for indexing within `budget_bytes`.
struct IndexPlan {
    io::LasOptions las;
    io::CopcOptions copc;
    int threads = 1;  // the caller's and las.threads workers
};

/// The writer's share of `budget_bytes` (the reader's chunk taken out first) on `threads`
/// threads, for nodes of at most `max_node_points`; with `fewer_threads`, the most threads
/// (down to one) that fit instead of a refusal. Throws Error("<command>: --memory-mb <mb> is below the N MiB indexing needs
/// with T threads; raise --memory-mb or lower --threads") (with `fewer_threads`: "... with
/// 1 thread; raise --memory-mb").
/// `side_record_bytes`: the bytes of each point's side record the readers give besides it
/// (io::CloudReader::foreignHeader()->stride(); 0 for none), held with the chunks read.
IndexPlan planIndex(std::uint64_t budget_bytes, double memory_mb, int threads, std::string_view command,
                    bool fewer_threads = false, std::uint32_t max_node_points = io::kDefaultMaxNodePoints,
                    std::size_t side_record_bytes = 0);

/// Appends every reader's points (shifted into the first one's frame) to a COPC writer at
/// `out`, then renames the whole file into place (CloudWriter). `advance(n)` is called
/// after each chunk of n points and `read_done()` once every point is read, before the
/// octree is written. A reader's warning is printed as it finishes. Returns the points
/// written. Throws as CloudReader and CloudWriter do; nothing is left under `out` then.
std::size_t writeIndex(std::vector<std::unique_ptr<io::CloudReader>>& readers, const std::filesystem::path& out,
                       const IndexPlan& plan, const std::function<void(std::size_t)>& advance,
                       const std::function<void()>& read_done);

}  // namespace app
