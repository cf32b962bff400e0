// app/src/cmd_corpus.cpp: `ladarvr corpus`: build a corpus of varied scenes and clouds from
// a SPEC (resumable, --jobs, --shard I/N or a Slurm array task), merge shard manifests,
// summarise a corpus and select study trials from it (docs/corpus.md).
#include "cli_common.hpp"
#include "commands.hpp"

#include <corpus/run.hpp>
#include <corpus/stats.hpp>

#include <core/error.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace app {
namespace {

struct CorpusCli {
    std::string spec;
    std::string out;
    std::string merge;
    std::string stats;
    std::string shard;
    std::string select;
    std::string plan;
    std::string column;
    std::string histogram;
    int jobs = 1;
    int threads = 0;
    std::size_t count = 0;
    std::uint64_t seed = 1;
    double time_limit_s = 120.0;
    bool json = false;
    // Each option with the modes it belongs to: one given to another mode is refused,
    // not ignored (a --select beside a SPEC would otherwise build a corpus silently).
    enum Mode : unsigned { kBuild = 1, kMerge = 2, kStats = 4, kSelect = 8 };
    std::vector<std::pair<CLI::Option*, unsigned>> options;
};

void refuseOtherModes(const CorpusCli& cli, CorpusCli::Mode mode, const char* mode_text) {
    for (const auto& [option, modes] : cli.options)
        if (option->count() > 0 && !(modes & mode)) {
            std::string allowed;
            for (const auto& [other, other_modes] : cli.options)
                if (other_modes & mode) allowed += (allowed.empty() ? "" : ", ") + other->get_name();
            throw CLI::ValidationError(option->get_name() + " does not go with " + mode_text +
                                       "; allowed with it: " + (allowed.empty() ? std::string("no option") : allowed));
        }
}

std::string firstFew(const std::vector<std::string>& ids) {
    std::string s;
    for (std::size_t i = 0; i < ids.size() && i < 10; ++i) s += (i ? ", " : "") + ids[i];
    if (ids.size() > 10) s += ", ... (" + std::to_string(ids.size()) + " in all)";
    return s;
}

void runMerge(const CorpusCli& cli) {
    const corpus::MergeReport r = corpus::mergeManifests(cli.merge);
    std::fprintf(stderr, "corpus: merged %zu of %zu items from %zu manifest file(s) into %s/manifest.jsonl\n", r.merged,
                 r.count, r.sources, cli.merge.c_str());
    if (!r.duplicated.empty())
        std::fprintf(stderr, "corpus: %zu item(s) appear in more than one line: %s\n", r.duplicated.size(),
                     firstFew(r.duplicated).c_str());
    if (!r.conflicting.empty())
        throw core::Error("corpus: --merge " + cli.merge + ": " + std::to_string(r.conflicting.size()) +
                          " item(s) have lines with different files (SHA-256): " + firstFew(r.conflicting) +
                          "; were they built from different SPECs or versions?");
    if (!r.missing.empty())
        throw core::Error("corpus: --merge " + cli.merge + ": " + std::to_string(r.missing.size()) +
                          " item(s) missing: " + firstFew(r.missing) +
                          "; rerun the shards that hold them (they resume)");
}

void runBuild(const CorpusCli& cli) {
    corpus::RunOptions o;
    o.spec = cli.spec;
    o.out = cli.out;
    o.jobs = cli.jobs;
    o.threads = cli.threads;
    if (!cli.shard.empty()) {
        std::tie(o.shard, o.shards) = corpus::parseShard(cli.shard, "--shard");
        o.sharded = true;
    } else if (const auto slurm = corpus::shardFromSlurm()) {
        std::tie(o.shard, o.shards) = *slurm;
        o.sharded = true;
    }
    o.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    const corpus::RunSummary s = corpus::runCorpus(o);
    std::fprintf(stderr, "corpus: %zu built, %zu already complete, %zu failed; manifest %s\n", s.built, s.skipped,
                 s.failed.size(), s.manifest.string().c_str());
    if (!s.failed.empty())
        throw core::Error("corpus: " + std::to_string(s.failed.size()) + " item(s) failed, first " + s.failed.front());
}

void runStats(const CorpusCli& cli) {
    if (!cli.select.empty()) {
        corpus::SelectOptions so;
        so.expression = cli.select;
        so.count = cli.count;
        so.seed = cli.seed;
        so.time_limit_s = cli.time_limit_s;
        so.plan = cli.plan.empty() ? std::filesystem::path(cli.stats) / "plan.json" : std::filesystem::path(cli.plan);
        createParentFolders(so.plan, "corpus: --plan");
        const corpus::SelectResult r = corpus::selectTrials(cli.stats, so);
        std::fprintf(stderr, "corpus: %zu of %zu items match '%s'; wrote %zu trials to %s\n", r.matching, r.items,
                     cli.select.c_str(), r.written, so.plan.string().c_str());
        return;
    }
    corpus::StatsOptions so;
    so.column = cli.column;
    so.histogram = cli.histogram.empty() ? std::filesystem::path(cli.stats) / "histogram.png"
                                         : std::filesystem::path(cli.histogram);
    createParentFolders(so.histogram, "corpus: --histogram");
    const corpus::Stats st = corpus::computeStats(cli.stats, so);
    if (cli.json)
        std::printf("%s\n", corpus::statsJson(st).c_str());
    else
        std::printf("%s", corpus::statsText(st).c_str());
}

void run(const CorpusCli& cli) {
    const int modes = int(!cli.spec.empty()) + int(!cli.merge.empty()) + int(!cli.stats.empty());
    if (modes != 1) throw CLI::ValidationError("give one of SPEC (with --out DIR), --merge DIR, --stats DIR");
    if (!cli.spec.empty()) {
        refuseOtherModes(cli, CorpusCli::kBuild, "SPEC (building a corpus)");
        if (cli.out.empty()) throw CLI::ValidationError("SPEC needs --out DIR: the folder the items go to");
        runBuild(cli);
    } else if (!cli.merge.empty()) {
        refuseOtherModes(cli, CorpusCli::kMerge, "--merge");
        runMerge(cli);
    } else {
        if (cli.select.empty())
            refuseOtherModes(cli, CorpusCli::kStats, "--stats without --select");
        else
            refuseOtherModes(cli, CorpusCli::kSelect, "--stats --select");
        if (!cli.select.empty() && cli.count == 0)
            throw CLI::ValidationError("--select needs --count N (N >= 1): how many trials the plan holds");
        runStats(cli);
    }
}

}  // namespace

void registerCorpus(CLI::App& cli) {
    auto state = std::make_shared<CorpusCli>();
    CLI::App* c = cli.add_subcommand(
        "corpus",
        "build many varied scenes and clouds from a SPEC (resumable, --jobs, Slurm array shards), "
        "merge shard manifests, summarise a corpus, select study trials by difficulty (docs/corpus.md)");
    using M = CorpusCli::Mode;
    const auto mode = [&](CLI::Option* o, unsigned modes) { state->options.emplace_back(o, modes); };
    c->add_option("SPEC", state->spec, "SPEC.json: the base scene, count, seed and what varies");
    mode(c->add_option("--out", state->out, "corpus folder: items/<id>/, manifest.jsonl (resumes when it exists)"),
         M::kBuild);
    mode(c->add_option("--jobs", state->jobs, "items built at once, [1, 1024]")->capture_default_str(), M::kBuild);
    mode(c->add_option("--threads", state->threads, "generator threads per item; 0 = the cores divided by --jobs")
             ->capture_default_str(),
         M::kBuild);
    mode(c->add_option("--shard", state->shard,
                       "I/N: build items i with i mod N == I into manifest.<I>.jsonl; default "
                       "from SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT"),
         M::kBuild);
    c->add_option("--merge", state->merge,
                  "DIR: merge manifest.<I>.jsonl into manifest.jsonl, sorted by id; "
                  "reports missing and duplicated items");
    c->add_option("--stats", state->stats, "DIR: distribution of the metric and the other columns, histogram PNG");
    mode(c->add_flag("--json", state->json, "with --stats: print the statistics as JSON on stdout"), M::kStats);
    mode(c->add_option("--column", state->column,
                       "with --stats: the histogram's column (default: metric if present, "
                       "else points)"),
         M::kStats);
    mode(c->add_option("--histogram", state->histogram, "with --stats: the histogram PNG (default DIR/histogram.png)"),
         M::kStats);
    mode(c->add_option("--select", state->select,
                       "with --stats: items to pick, e.g. \"metric<0.3\" or "
                       "\"metric>=0.2,metric<0.5\" (all must hold); writes a study plan"),
         M::kSelect);
    mode(c->add_option("--count", state->count, "with --select: trials in the plan")->capture_default_str(),
         M::kSelect);
    mode(c->add_option("--seed", state->seed,
                       "with --select: which matching items are picked, and the plan's "
                       "shuffle_seed")
             ->capture_default_str(),
         M::kSelect);
    mode(c->add_option("--plan", state->plan, "with --select: the plan file (default DIR/plan.json)"), M::kSelect);
    mode(c->add_option("--time-limit-s", state->time_limit_s, "with --select: each trial's time limit, seconds > 0")
             ->capture_default_str(),
         M::kSelect);
    c->callback([state] { run(*state); });
}

}  // namespace app
