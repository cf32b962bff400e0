// app/src/view_index.cpp: streamed whole, or indexed (cached) and read node by node
// (view_index.hpp).
//
// The cache folder is platform's (cache_folder.hpp): made 0700, refused when it is a link
// or not this user's folder. An index is named "index-<key>.copc.laz", the key hashed from
// the cloud's identity (device, inode, size, modification time in ns, canonical path) and
// the index format's version, so a changed cloud gets a new index and the old one ages out
// under the size bound; a survey of several files is keyed by every file's identity in
// order. The index is written as every cloud is (a TempFile created
// O_EXCL|O_NOFOLLOW in the cache folder, scratch files that vanish with the process, one
// rename at the end): two views of the same cloud at once each write a whole index and
// rename it into place, the last rename wins with the same bytes (the writer is
// deterministic), and a view that opened the earlier one keeps reading it through its open
// descriptor. The bound removes only regular files of this user named like an index.
#include "view_index.hpp"

#include "cli_common.hpp"
#include "cloud_index.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <platform/atomic_file.hpp>
#include <platform/cache_folder.hpp>
#include <platform/safe_file.hpp>
#include <platform/sha256.hpp>
#include <sim/memory_budget.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace app {

namespace fs = std::filesystem;

namespace {

// The index format's version: a writer that lays nodes out differently changes it, so
// indexes of an older writer are not reused (and age out).
constexpr std::string_view kIndexSalt = "ladarvr COPC index 1";
// What a survey's key hashes before its files' keys, so no survey shares a single file's key.
constexpr std::string_view kSurveySalt = "ladarvr COPC survey index 1\n";

// "index-" + 32 lowercase hex digits + ".copc.laz": the only names the cache bound touches.
bool isIndexName(const std::string& name) {
    constexpr std::string_view head = "index-", tail = ".copc.laz";
    if (name.size() != head.size() + 32 + tail.size()) return false;
    if (name.compare(0, head.size(), head) != 0 || name.compare(name.size() - tail.size(), tail.size(), tail) != 0)
        return false;
    return std::all_of(name.begin() + std::ptrdiff_t(head.size()), name.end() - std::ptrdiff_t(tail.size()),
                       [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

std::uint64_t mebibytes(double mb) { return static_cast<std::uint64_t>(mb * 1048576.0); }

// Writes the index of `clouds` (merged in order) at `out` within --memory-mb, with a
// progress line at each quarter; `shown` names them in the lines.
void indexClouds(const std::vector<fs::path>& clouds, const std::string& shown, const fs::path& out,
                 const ViewIndexOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::unique_ptr<io::CloudReader>> readers;
    std::size_t total = 0;
    for (const fs::path& cloud : clouds) {
        readers.push_back(std::make_unique<io::CloudReader>(cloud));
        checkMergeable(*readers.back(), *readers.front(), "view");
        total += readers.back()->pointsBound();
    }
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    const IndexPlan plan = planIndex(sim::memoryBudgetBytes(o.memory_mb, "view"), o.memory_mb, cores, "view", true);
    std::fprintf(stderr, "ladarvr: view: indexing %s (%zu points) into %s within %.6g MB\n", shown.c_str(), total,
                 core::printable(out.string(), 400).c_str(), o.memory_mb);
    std::size_t done = 0;
    int quarter = 0;
    const auto advance = [&](std::size_t n) {
        done += n;
        while (quarter < 3 && total > 0 && done * 4 >= total * std::size_t(quarter + 1)) {
            ++quarter;
            std::fprintf(stderr, "ladarvr: view: indexing %s: %d%% read\n", shown.c_str(), 25 * quarter);
        }
    };
    const auto read_done = [&] {
        std::fprintf(stderr, "ladarvr: view: indexing %s: %zu points read, writing the octree\n", shown.c_str(), done);
    };
    const std::size_t points = writeIndex(readers, out, plan, advance, read_done);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "ladarvr: view: indexing %s: done, %zu points in %.3f s\n", shown.c_str(), points, seconds);
}

// The index of `clouds` (one file, or a survey's files) named by `key`, as
// indexForView describes; `shown` names the cloud or the survey in the lines.
ViewCloud findOrIndex(const std::vector<fs::path>& clouds, const std::string& shown, const std::string& key,
                      const ViewIndexOptions& o, bool force_reindex) {
    if (!o.index_to.empty()) {
        const fs::path out = o.index_to;
        if (io::formatForPath(out, "view: --index-to") != io::CloudFormat::Copc)
            throw core::Error("view: --index-to " + core::printable(o.index_to, 400) +
                              ": allowed a name ending in .copc.laz");
        createParentFolders(out, "view: --index-to");
        platform::checkWritableDestination(out);
        indexClouds(clouds, shown, out, o);
        std::fprintf(stderr, "ladarvr: view: %s is not COPC: indexed now into %s (--index-to)\n", shown.c_str(),
                     core::printable(out.string(), 400).c_str());
        return {ViewPath::IndexedNow, out};
    }
    const fs::path folder = platform::userCacheFolder("ladarvr", "view: index cache");
    platform::makeCacheFolder(folder, "view: index cache");
    const std::string name = "index-" + key + ".copc.laz";
    const fs::path index = folder / name;
    const std::string shown_index = core::printable(index.string(), 400);
    ViewCloud v;
    if (!force_reindex && platform::useCachedFile(index, "view: index cache: index")) {
        std::fprintf(stderr, "ladarvr: view: %s is not COPC: its cached index %s is reused\n", shown.c_str(),
                     shown_index.c_str());
        v = {ViewPath::IndexReused, index};
    } else {
        indexClouds(clouds, shown, index, o);
        std::fprintf(stderr, "ladarvr: view: %s is not COPC: indexed now into %s\n", shown.c_str(),
                     shown_index.c_str());
        v = {ViewPath::IndexedNow, index};
    }
    for (const std::string& gone : platform::boundCacheFolder(folder, isIndexName, mebibytes(o.index_cache_mb), name))
        std::fprintf(stderr, "ladarvr: view: index cache: removed %s (least recently used; --index-cache-mb %s)\n",
                     core::printable((folder / gone).string(), 400).c_str(),
                     core::shownNumber(o.index_cache_mb).c_str());
    return v;
}

}  // namespace

void validate(const ViewIndexOptions& o) {
    if (!(o.index_above_mb >= 0.0 && o.index_above_mb <= 1048576.0))
        throw core::Error("view: --index-above-mb " + core::shownNumber(o.index_above_mb) +
                          ": allowed [0, 1048576] MiB");
    if (!(o.index_cache_mb >= 0.0 && o.index_cache_mb <= 1073741824.0))
        throw core::Error("view: --index-cache-mb " + core::shownNumber(o.index_cache_mb) +
                          ": allowed [0, 1073741824] MiB");
    if (o.in_core && !o.index_to.empty())
        throw core::Error("view: --in-core and --index-to exclude each other; allowed: one of them");
}

bool shouldIndex(const fs::path& cloud, const ViewIndexOptions& o) {
    if (!o.index_to.empty()) return true;
    if (o.in_core) return false;
    std::uint64_t points = 0;
    try {
        points = io::CloudReader(cloud).pointsBound();
    } catch (const core::Error&) {
        return false;  // a bad header: the in-core path refuses it with the loader's words
    }
    return double(points * kInCoreBytesPerPoint) > o.index_above_mb * 1048576.0;
}

ViewCloud indexForView(const fs::path& cloud, const ViewIndexOptions& o, bool force_reindex) {
    const std::string key = o.index_to.empty()
                                ? platform::identityKey(platform::fileIdentity(cloud, "view: cloud"), kIndexSalt)
                                : std::string();
    return findOrIndex({cloud}, core::printable(cloud.string(), 400), key, o, force_reindex);
}

ViewCloud indexSurveyForView(const std::vector<fs::path>& clouds, const ViewIndexOptions& o, bool force_reindex) {
    std::string key;
    if (o.index_to.empty()) {
        // Every file's own key, in order, hashed into one of the same form.
        std::string keys(kSurveySalt);
        for (const fs::path& cloud : clouds)
            keys += platform::identityKey(platform::fileIdentity(cloud, "view: cloud"), kIndexSalt) + "\n";
        key = platform::sha256Hex(keys).substr(0, 32);
    }
    return findOrIndex(clouds, "the survey of " + std::to_string(clouds.size()) + " files", key, o, force_reindex);
}

}  // namespace app
