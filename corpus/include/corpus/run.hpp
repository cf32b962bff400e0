// corpus/run.hpp: building a corpus (resumable, in parallel, one shard of many) and
// merging the shards' manifests.
//
// DIR/corpus.json records the SPEC (its path and SHA-256) and count; DIR/items/<id>/ holds
// the items; DIR/manifest.jsonl (or manifest.<I>.jsonl for shard I) one line per finished
// item, appended only after its folder is in place. A rerun skips the items whose line is
// there and whose files still have the sizes it records; it drops torn or stale lines.
#pragma once
#include <corpus/spec.hpp>
#include <platform/input_set.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace corpus {

struct RunOptions {
    std::filesystem::path spec;
    std::filesystem::path out;
    int jobs = 1;           // items built at once
    int threads = 0;        // generator threads per item; 0 = the cores / jobs
    std::size_t shard = 0;  // this run builds items i with i % shards == shard
    std::size_t shards = 1;
    bool sharded = false;                              // write manifest.<shard>.jsonl (else manifest.jsonl)
    std::function<void(const std::string&)> progress;  // one line per event (stderr)
};

struct RunSummary {
    std::size_t planned = 0;  // items of this shard
    std::size_t skipped = 0;  // already complete
    std::size_t built = 0;
    std::vector<std::string> failed;  // "item <id>: <error>"
    std::size_t dropped_lines = 0;    // torn, duplicated or stale manifest lines dropped
    std::filesystem::path manifest;
};

/// Builds the items of one shard. Throws core::Error before any work for a bad SPEC,
/// an output folder made from another SPEC, or bad options; an item that fails is listed
/// in failed (the others still run).
RunSummary runCorpus(const RunOptions& options);

/// Parses "I/N" (0 <= I < N <= 1e6). Throws core::Error naming `option`.
std::pair<std::size_t, std::size_t> parseShard(const std::string& text, const std::string& option);
/// The shard from SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN) and
/// SLURM_ARRAY_TASK_COUNT, when both are set. Throws core::Error on nonsense values.
std::optional<std::pair<std::size_t, std::size_t>> shardFromSlurm();

struct MergeReport {
    std::size_t count = 0;                 // items the SPEC describes
    std::size_t merged = 0;                // distinct items in manifest.jsonl
    std::vector<std::string> missing;      // ids absent from every manifest
    std::vector<std::string> duplicated;   // ids with more than one line across the manifests
    std::vector<std::string> conflicting;  // ... whose lines disagree on a file's SHA-256
    std::size_t sources = 0;               // manifest files read
};

/// Merges DIR/manifest.jsonl and every DIR/manifest.<I>.jsonl into DIR/manifest.jsonl
/// (atomically), one line per item sorted by index. Throws core::Error when DIR is no
/// corpus folder.
MergeReport mergeManifests(const std::filesystem::path& dir);

/// The manifest lines of DIR (manifest.jsonl, else every shard manifest), one per item,
/// sorted by index, as JSON text. Adds DIR to `inputs` as an input folder (its manifests,
/// its record and its items are no place for the run's outputs; beside them outputs may
/// go) and each manifest read as an input file. Throws core::Error when there is none.
std::vector<std::string> readManifest(const std::filesystem::path& dir, platform::InputSet& inputs);

}  // namespace corpus
