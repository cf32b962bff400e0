// corpus: the resumable, parallel, sharded run and the merge of shard manifests.
#include <corpus/item.hpp>
#include <corpus/plan.hpp>
#include <corpus/run.hpp>

#include <core/error.hpp>
#include <platform/atomic_file.hpp>
#include <platform/safe_file.hpp>

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <thread>

namespace corpus {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr std::size_t kMaxManifestBytes = std::size_t(1) << 30;
constexpr std::size_t kMaxRecordBytes = std::size_t(1) << 20;

std::string shown(const fs::path& p) { return core::printable(p.string()); }

/// Whether the files a manifest line lists are in DIR/items/<id>/ with those sizes.
bool itemIntact(const fs::path& dir, const json& line) {
    if (!line.is_object() || !line.contains("id") || !line["id"].is_string() || !line.contains("files") ||
        !line["files"].is_object() || line["files"].empty())
        return false;
    const fs::path folder = dir / "items" / line["id"].get<std::string>();
    for (auto it = line["files"].begin(); it != line["files"].end(); ++it) {
        struct stat st{};
        if (!isItemFile(it.key()) || !it.value().contains("bytes")) return false;
        if (::lstat((folder / it.key()).c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
        if (std::uint64_t(st.st_size) != it.value()["bytes"].get<std::uint64_t>()) return false;
    }
    return true;
}

struct ManifestLine {
    std::size_t index;
    std::string id;
    std::string text;
    json value;
};

/// The complete, parseable lines of a manifest file (a torn last line is left out);
/// `torn` counts what was left out. Absent file: no line.
std::vector<ManifestLine> parseLines(const std::string& text, std::size_t* torn) {
    std::vector<ManifestLine> lines;
    std::size_t start = 0;
    while (start < text.size()) {
        const std::size_t end = text.find('\n', start);
        if (end == std::string::npos) {  // no newline: a line torn by a kill
            if (torn) ++*torn;
            break;
        }
        const std::string line = text.substr(start, end - start);
        start = end + 1;
        try {
            json j = json::parse(line);
            if (!j.is_object() || !j.contains("index") || !j["index"].is_number_unsigned() || !j.contains("id") ||
                !j["id"].is_string())
                throw std::runtime_error("no index");
            lines.push_back({j["index"].get<std::size_t>(), j["id"].get<std::string>(), line, std::move(j)});
        } catch (const std::exception&) {
            if (torn) ++*torn;
        }
    }
    return lines;
}

/// parseLines of a manifest this command wrote and may rewrite (platform::readOwnFile).
std::vector<ManifestLine> readLines(const fs::path& file, std::size_t* torn) {
    struct stat st{};
    if (::lstat(file.c_str(), &st) != 0) return {};
    return parseLines(platform::readOwnFile(file, kMaxManifestBytes, "corpus: manifest"), torn);
}

std::string joinLines(const std::vector<ManifestLine>& lines) {
    std::string s;
    for (const ManifestLine& l : lines) s += l.text + "\n";
    return s;
}

json readCorpusRecord(const fs::path& dir) {
    const fs::path file = dir / "corpus.json";
    try {
        return json::parse(platform::readOwnFile(file, kMaxRecordBytes, "corpus: record"));
    } catch (const json::exception& e) {
        throw core::Error("corpus: " + shown(file) + ": not valid JSON (" + core::printable(e.what(), 100) + ")");
    }
}

/// DIR/corpus.json: written once; a later run with another SPEC is refused.
void recordSpec(const fs::path& dir, const Spec& spec) {
    const fs::path file = dir / "corpus.json";
    json rec{{"spec", spec.file.string()}, {"spec_sha256", spec.sha256}, {"count", spec.count}, {"seed", spec.seed}};
    struct stat st{};
    if (::lstat(file.c_str(), &st) == 0) {
        const json old = readCorpusRecord(dir);
        if (old.value("spec_sha256", "") != spec.sha256)
            throw core::Error("corpus: --out " + shown(dir) + " was made from another SPEC (" +
                              core::printable(old.value("spec", "?")) +
                              ", a different SHA-256); allowed: the same SPEC to resume, or a new --out folder");
        return;
    }
    platform::writeFileAtomic(file, rec.dump(2) + "\n");
}

}  // namespace

std::pair<std::size_t, std::size_t> parseShard(const std::string& text, const std::string& option) {
    const auto bad = [&] {
        return core::Error("corpus: " + option + " '" + core::printable(text, 40) +
                           "': allowed I/N with integers 0 <= I < N <= 1000000");
    };
    const std::size_t slash = text.find('/');
    if (slash == std::string::npos) throw bad();
    const auto number = [&](const std::string& s) {
        if (s.empty() || s.size() > 7 || s.find_first_not_of("0123456789") != std::string::npos) throw bad();
        return std::size_t(std::stoul(s));
    };
    const std::size_t i = number(text.substr(0, slash)), n = number(text.substr(slash + 1));
    if (n < 1 || n > 1000000 || i >= n) throw bad();
    return {i, n};
}

std::optional<std::pair<std::size_t, std::size_t>> shardFromSlurm() {
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
    if (!id || !count) return std::nullopt;
    const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
    const auto number = [](const char* s, const char* name) {
        const std::string t = s;
        if (t.empty() || t.size() > 7 || t.find_first_not_of("0123456789") != std::string::npos)
            throw core::Error(std::string("corpus: ") + name + "='" + core::printable(t, 20) +
                              "': allowed a whole number (or give --shard I/N)");
        return std::size_t(std::stoul(t));
    };
    const std::size_t i = number(id, "SLURM_ARRAY_TASK_ID") - (min ? number(min, "SLURM_ARRAY_TASK_MIN") : 0);
    const std::size_t n = number(count, "SLURM_ARRAY_TASK_COUNT");
    return parseShard(std::to_string(i) + "/" + std::to_string(n),
                      "shard from SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN / SLURM_ARRAY_TASK_COUNT (use a "
                      "contiguous --array=0-(N-1))");
}

RunSummary runCorpus(const RunOptions& o) {
    if (o.jobs < 1 || o.jobs > 1024)
        throw core::Error("corpus: --jobs " + std::to_string(o.jobs) + ": allowed [1, 1024]");
    if (o.threads < 0 || o.threads > 1024)
        throw core::Error("corpus: --threads " + std::to_string(o.threads) + ": allowed [0, 1024]");
    if (o.shards < 1 || o.shard >= o.shards) throw core::Error("corpus: --shard: allowed I/N with 0 <= I < N");
    const Spec spec = loadSpec(o.spec);
    const Planner planner(spec);  // loads the base scene and the target models: their errors come first
    const auto say = [&](const std::string& s) {
        if (o.progress) o.progress(s);
    };

    struct stat st{};
    if (::stat(o.out.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
        throw core::Error("corpus: --out " + shown(o.out) + " exists and is not a folder; allowed a folder");
    std::error_code ec;
    fs::create_directories(o.out, ec);
    if (ec) throw core::Error("corpus: --out " + shown(o.out) + ": cannot create the folder: " + ec.message());
    // DIR/items is ours: a real folder, never a link planted to send the items elsewhere.
    platform::makeOwnFolder(o.out / "items", "output:");
    recordSpec(o.out, spec);
    platform::removeStaleTemporaries(o.out / "items", isItemFile);

    RunSummary summary;
    summary.manifest = o.out / (o.sharded ? "manifest." + std::to_string(o.shard) + ".jsonl" : "manifest.jsonl");
    // One run per manifest at a time: two would build the same items and append the same
    // lines. The lock goes with the process (flock), so a killed run never leaves it held.
    const fs::path lock_path = summary.manifest.string() + ".lock";
    const int lock_fd = platform::openOwnFile(lock_path, O_RDWR | O_CREAT, "output: lock file");
    struct LockCloser {
        int fd;
        ~LockCloser() { ::close(fd); }
    } lock_closer{lock_fd};
    if (::flock(lock_fd, LOCK_EX | LOCK_NB) != 0)
        throw core::Error("corpus: " + shown(summary.manifest) + " is in use by another run of the same " +
                          (o.sharded ? "shard" : "corpus") +
                          "; allowed: one run per manifest at a time (wait, or "
                          "stop the other run: this one would resume it)");

    // What is done: intact lines of our manifest (torn, duplicated or stale ones dropped,
    // the file rewritten without them) and, for a shard, of the merged manifest.
    std::set<std::size_t> done;
    std::size_t torn = 0;
    std::vector<ManifestLine> kept;
    for (ManifestLine& l : readLines(summary.manifest, &torn)) {
        if (l.index < spec.count && l.id == planner.itemId(l.index) && !done.count(l.index) &&
            itemIntact(o.out, l.value)) {
            done.insert(l.index);
            kept.push_back(std::move(l));
        } else {
            ++torn;
        }
    }
    summary.dropped_lines = torn;
    if (torn > 0) {
        platform::writeFileAtomic(summary.manifest, joinLines(kept));
        say("corpus: dropped " + std::to_string(torn) + " torn, duplicated or stale line(s) from " +
            shown(summary.manifest));
    }
    if (o.sharded)
        for (const ManifestLine& l : readLines(o.out / "manifest.jsonl", nullptr))
            if (l.index < spec.count && l.id == planner.itemId(l.index) && itemIntact(o.out, l.value))
                done.insert(l.index);

    // The items to build are this shard's indices minus `done`, handed out one at a time
    // (a SPEC may count 10^8 items: no list of them is held).
    summary.planned = o.shard < spec.count ? (spec.count - o.shard + o.shards - 1) / o.shards : 0;
    for (std::size_t i : done)
        if (i % o.shards == o.shard) ++summary.skipped;
    const std::size_t to_build = summary.planned - summary.skipped;
    say("corpus: " + std::to_string(summary.planned) + " items in this run" +
        (o.shards > 1 ? " (shard " + std::to_string(o.shard) + "/" + std::to_string(o.shards) + ")" : "") + ", " +
        std::to_string(summary.skipped) + " already complete, " + std::to_string(to_build) + " to build with " +
        std::to_string(o.jobs) + " job(s)");
    if (to_build == 0) return summary;

    const int fd = platform::openOwnFile(summary.manifest, O_WRONLY | O_APPEND | O_CREAT, "output: manifest");
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};

    const int hardware = int(std::max(1u, std::thread::hardware_concurrency()));
    const int threads = o.threads > 0 ? o.threads : std::max(1, hardware / o.jobs);
    std::mutex mutex;
    std::size_t next = o.shard;  // the next index to look at, under `mutex`
    std::size_t finished = 0;
    const auto take = [&]() -> std::optional<std::size_t> {
        std::lock_guard lock(mutex);
        for (; next < spec.count; next += o.shards)
            if (!done.count(next)) {
                const std::size_t index = next;
                next += o.shards;
                return index;
            }
        return std::nullopt;
    };
    const auto work = [&] {
        for (;;) {
            const std::optional<std::size_t> taken = take();
            if (!taken) return;
            const std::size_t index = *taken;
            try {
                const ItemOutcome r = buildItem(planner, index, o.out, threads);
                const std::string line = r.manifest_line + "\n";
                std::lock_guard lock(mutex);
                // One write of the whole line: appended after the folder is in place.
                const ssize_t wrote = ::write(fd, line.data(), line.size());
                if (wrote != ssize_t(line.size()) || ::fdatasync(fd) != 0)
                    throw core::Error("output: " + shown(summary.manifest) +
                                      ": cannot append: " + std::strerror(errno));
                ++summary.built;
                ++finished;
                char text[256];
                std::snprintf(text, sizeof text, "corpus: [%zu/%zu] item %s built in %.2f s, %llu points%s", finished,
                              to_build, r.id.c_str(), r.seconds, (unsigned long long)r.points,
                              std::isnan(r.metric) ? "" : (", metric " + std::to_string(r.metric)).c_str());
                say(text);
            } catch (const std::exception& e) {
                std::lock_guard lock(mutex);
                ++finished;
                const std::string what = e.what();
                summary.failed.push_back(what.rfind("corpus: item ", 0) == 0
                                             ? what.substr(8)
                                             : "item " + planner.itemId(index) + ": " + what);
                say("corpus: [" + std::to_string(finished) + "/" + std::to_string(to_build) + "] " +
                    summary.failed.back());
            }
        }
    };
    std::vector<std::thread> pool;
    for (std::size_t j = 1; j < std::min<std::size_t>(std::size_t(o.jobs), to_build); ++j) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    std::sort(summary.failed.begin(), summary.failed.end());
    return summary;
}

MergeReport mergeManifests(const fs::path& dir) {
    const json rec = readCorpusRecord(dir);
    MergeReport report;
    report.count = rec.value("count", std::size_t(0));
    std::vector<fs::path> sources;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind("manifest.", 0) == 0 && name.size() > 15 && name.ends_with(".jsonl") &&
            name.find_first_not_of("0123456789", 9) == name.size() - 6)
            sources.push_back(it->path());
    }
    if (ec) throw core::Error("corpus: --merge " + shown(dir) + ": cannot list the folder: " + ec.message());
    std::sort(sources.begin(), sources.end());
    sources.insert(sources.begin(), dir / "manifest.jsonl");
    std::map<std::size_t, ManifestLine> merged;
    std::set<std::string> seen_texts;
    std::set<std::string> duplicated, conflicting;
    for (const fs::path& file : sources) {
        struct stat st{};
        if (::lstat(file.c_str(), &st) != 0) continue;
        ++report.sources;
        for (ManifestLine& l : readLines(file, nullptr)) {
            if (!seen_texts.insert(l.text).second) continue;  // the same line again (merged before)
            const auto it = merged.find(l.index);
            if (it == merged.end()) {
                merged.emplace(l.index, std::move(l));
                continue;
            }
            duplicated.insert(l.id);
            for (auto f = l.value["files"].begin(); f != l.value["files"].end(); ++f) {
                const json& other = it->second.value["files"];
                if (!other.contains(f.key()) || other[f.key()].value("sha256", "") != f.value().value("sha256", ""))
                    conflicting.insert(l.id);
            }
        }
    }
    std::vector<ManifestLine> lines;
    std::set<std::size_t> present;
    for (auto& [index, l] : merged) {
        present.insert(index);
        lines.push_back(std::move(l));
    }
    for (std::size_t i = 0; i < report.count; ++i)
        if (!present.count(i)) report.missing.push_back(itemId(i, report.count));
    report.merged = lines.size();
    report.duplicated.assign(duplicated.begin(), duplicated.end());
    report.conflicting.assign(conflicting.begin(), conflicting.end());
    platform::writeFileAtomic(dir / "manifest.jsonl", joinLines(lines));
    return report;
}

std::vector<std::string> readManifest(const fs::path& dir, platform::InputSet& inputs) {
    std::map<std::size_t, std::string> by_index;
    std::vector<fs::path> files;
    struct stat st{};
    if (::lstat((dir / "manifest.jsonl").c_str(), &st) == 0) {
        files.push_back(dir / "manifest.jsonl");
    } else {
        std::error_code ec;
        for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            if (name.rfind("manifest.", 0) == 0 && name.ends_with(".jsonl")) files.push_back(it->path());
        }
    }
    if (files.empty())
        throw core::Error("corpus: " + shown(dir) +
                          ": no manifest.jsonl or manifest.<I>.jsonl; allowed a folder "
                          "made by 'ladarvr corpus SPEC --out DIR'");
    // A corpus read as an input: its manifests, its record and its items are no place
    // for this run's outputs; beside them outputs may go (histogram.png, plan.json).
    inputs.addFolder(dir, [](const std::string& rel) {
        const std::string first = rel.substr(0, rel.find('/'));
        return first != "corpus.json" && first != "items" && first.rfind("manifest.", 0) != 0 &&
               first.rfind(platform::kTempPrefix, 0) != 0;
    });
    for (const fs::path& f : files) {
        const std::string text = platform::readTextFile(f, kMaxManifestBytes, "corpus: manifest " + shown(f));
        inputs.addFile(f);
        for (ManifestLine& l : parseLines(text, nullptr)) by_index.emplace(l.index, std::move(l.text));
    }
    std::vector<std::string> out;
    for (auto& [index, text] : by_index) out.push_back(std::move(text));
    return out;
}

}  // namespace corpus
