// app/src/cmd_index.cpp: `ladarvr index IN... --out OUT.copc.laz`: any clouds we read
// (PCD, PLY, LAS, LAZ, COPC), merged, to one COPC file (io/copc_writer.hpp). The inputs
// must carry the same fields. The writer works within --memory-mb: a cloud that does not
// fit is spilled to scratch files beside the output and indexed a part at a time.
#include "cli_common.hpp"
#include "cloud_index.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc.hpp>
#include <io/copc_writer.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>
#include <platform/progress.hpp>
#include <platform/safe_file.hpp>
#include <sim/memory_budget.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace app {
namespace {

namespace fs = std::filesystem;

// Input files of one run at most (a folder's tiles included).
constexpr std::size_t kMostInputs = 65536;

struct IndexCli {
    std::vector<std::string> inputs;
    std::string out;
    std::string check;
    int threads = 0;
    double memory_mb = 1024.0;
    long long node_points = io::kDefaultMaxNodePoints;
};

// The inputs' LAS grids, where they differ: the output keeps one, the finest
// (io::mergedForeignHeader), and says so, since the other inputs' integer coordinates
// are then rewritten on it.
void warnOfScales(const std::vector<std::unique_ptr<io::CloudReader>>& readers) {
    const auto merged = io::mergedForeignHeader(readers);
    if (!merged) return;
    bool differ = false;
    for (const auto& r : readers)
        if (const auto h = r->foreignHeader(); h && (h->scale != merged->scale || h->offset != merged->offset))
            differ = true;
    if (!differ) return;
    char grid[160];
    std::snprintf(grid, sizeof grid, "scale %.9g %.9g %.9g, offset %.9g %.9g %.9g", merged->scale.x, merged->scale.y,
                  merged->scale.z, merged->offset.x, merged->offset.y, merged->offset.z);
    warn("index: the inputs' LAS scales or offsets differ; written on the finest input's grid (" + std::string(grid) +
         ")");
}

// "N rules broken" for the distinct rules of `findings`, with the lines they take on stdout
// when a rule has several (io::checkCopc gives one per finding, up to 20 a rule and a line
// counting the rest).
std::string brokenRules(const std::vector<io::CopcFinding>& findings) {
    std::set<std::string> rules;
    for (const io::CopcFinding& f : findings) rules.insert(f.rule);
    std::string s = std::to_string(rules.size()) + (rules.size() == 1 ? " rule" : " rules") + " broken";
    if (findings.size() > rules.size()) s += " in " + std::to_string(findings.size()) + " lines";
    return s;
}

// `index --check FILE`: the COPC rules (io::checkCopc), one line on stdout per finding,
// exit 1 when any rule is broken; a valid file says so with its node and point counts.
int check(const std::string& file) {
    platform::checkInputFile(file, "index: --check " + core::printable(file, 400) + ":");
    const std::vector<io::CopcFinding> findings = io::checkCopc(file);
    const std::string shown = core::printable(file, 400);
    for (const io::CopcFinding& f : findings)
        std::printf("%s\n",
                    platform::messageLine("index --check: " + shown + ": " + f.rule + ": " + f.message).c_str());
    if (!findings.empty()) {
        std::fflush(stdout);
        platform::printMessage("error", "index --check: " + shown + ": not a valid COPC file (" +
                                            brokenRules(findings) + ", listed on stdout)");
        return 1;
    }
    const io::CopcReader reader(file);
    std::uint64_t points = 0;
    for (const io::CopcNode& n : reader.nodes()) points += std::uint64_t(n.point_count);
    std::printf("index --check: %s: valid COPC (%zu node%s with points, %llu points)\n", shown.c_str(),
                reader.nodes().size(), reader.nodes().size() == 1 ? "" : "s", static_cast<unsigned long long>(points));
    return 0;
}

void run(IndexCli& cli) {
    if (!cli.check.empty()) {
        if (!cli.inputs.empty() || !cli.out.empty())
            throw core::Error("index: --check FILE goes alone; allowed: index --check FILE, or index IN... --out OUT");
        if (const int status = check(cli.check); status != 0) throw CLI::RuntimeError(status);
        return;
    }
    if (cli.inputs.empty() || cli.out.empty())
        throw core::Error("index: give the input clouds and --out OUT.copc.laz (or --check FILE)");
    const std::vector<std::string> folders = folderInputs(cli.inputs);
    expandFolderInputs(cli.inputs, "index", kMostInputs);
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path out = cli.out;
    if (io::formatForPath(out, "index: --out") != io::CloudFormat::Copc)
        throw core::Error("index: --out " + cli.out + ": allowed a name ending in .copc.laz");
    if (cli.threads < 0 || cli.threads > 1024) throw core::Error("index: --threads: allowed 0 (all cores) to 1024");
    if (cli.node_points < io::kLeastNodeCap || cli.node_points > io::kMostNodeCap)
        throw core::Error("index: --node-points " + std::to_string(cli.node_points) + ": allowed " +
                          std::to_string(io::kLeastNodeCap) + " to " + std::to_string(io::kMostNodeCap));
    const std::uint64_t budget = sim::memoryBudgetBytes(cli.memory_mb, "index");
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    const int threads = cli.threads == 0 ? cores : cli.threads;

    // Every input's header first: a bad input fails before anything is written, and the
    // inputs are known as such before the output is checked.
    std::vector<std::unique_ptr<io::CloudReader>> readers;
    std::uint64_t bound = 0;
    platform::InputSet inputs;  // the output may not be one of them
    for (const std::string& in : cli.inputs) {
        platform::checkInputFile(in, "index: input " + in);
        inputs.addFile(in);
        readers.push_back(std::make_unique<io::CloudReader>(in, io::SideRecords::Keep));
        const io::CloudReader& r = *readers.back();
        checkMergeable(r, *readers.front(), "index");
        bound += r.pointsBound();
    }
    addTileFolders(inputs, folders);
    createParentFolders(out, "index: --out");
    platform::checkWritableDestination(out, inputs);
    warnOfScales(readers);

    const auto side = readers.front()->foreignHeader();
    const IndexPlan plan = planIndex(budget, cli.memory_mb, threads, "index", false, std::uint32_t(cli.node_points),
                                     side ? side->stride() : 0);
    platform::Progress progress("index: reading", std::size_t(bound));
    const std::size_t points =
        writeIndex(readers, out, plan, [&](std::size_t n) { progress.advance(n); }, [&] { progress.finish(); });
    std::error_code ec;
    const auto bytes = fs::file_size(out, ec);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "index: wrote %s: %zu points from %zu input%s, %llu bytes, %.3f s (threads: %d)\n",
                 out.string().c_str(), points, cli.inputs.size(), cli.inputs.size() == 1 ? "" : "s",
                 static_cast<unsigned long long>(ec ? 0 : bytes), seconds, threads);
}

}  // namespace

void registerIndex(CLI::App& cli) {
    auto state = std::make_shared<IndexCli>();
    CLI::App* c = cli.add_subcommand(
        "index",
        "write clouds (PCD, PLY, LAS, LAZ, COPC; several are merged) as one COPC 1.0 file: a LAZ file "
        "whose chunks are the nodes of a level-of-detail octree");
    c->add_option("inputs", state->inputs,
                  "the input clouds (a folder gives its .las/.laz files in name order); they must carry the same "
                  "fields");
    c->add_option("--out", state->out, "the COPC file to write, a name ending in .copc.laz");
    c->add_option("--check", state->check,
                  "check FILE against the COPC 1.0 rules instead (one line per finding on stdout; exit 1 "
                  "if any rule is broken)");
    c->add_option("--threads", state->threads, "threads, 0 = all cores")->capture_default_str();
    c->add_option("--node-points", state->node_points,
                  "the most points a node of the octree holds: larger nodes make a smaller file, smaller ones let "
                  "a viewer load the cloud in finer steps")
        ->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb,
                  "bound on memory; a cloud that does not fit is spilled to scratch files beside the output and "
                  "indexed a part at a time")
        ->capture_default_str();
    c->callback([state] { run(*state); });
}

}  // namespace app
