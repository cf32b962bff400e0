// bench/src/ground_survey.cpp: `ladarvr bench ground-survey`: how fast `ladarvr ground`
// classifies a large survey end to end, LAZ in to LAZ out, within --memory-mb, against
// `ladarvr index` of the same file in the same run (the baseline: one read of the same
// COPC, an octree and COPC written).
//
// The survey is the generator's demo cloud written as COPC (`ladarvr generate --xres X
// --yres X`, 100 views of X x X rays: X = sqrt(--points / 100)), made once and kept in the
// work folder, or the file given with --in. Each repeat runs the shipped `ladarvr`
// binary as a child process (fork and exec), `ground IN --out ground.laz --memory-mb M`
// then `index IN --out index.copc.laz --memory-mb M`, in turn, after --warmup runs of each;
// wall time from the fork to the child's exit, peak RSS from wait4 (the child's and its
// LAZ decoder's, whichever is larger). Reports points per second (median [min..max]),
// peak RSS and the ratio of the medians; rewrites the section "## Ground on a survey
// (ladarvr bench ground-survey)" of BENCHMARKS.md unless --no-md.
#include "common.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <io/cloud_reader.hpp>
#include <platform/safe_file.hpp>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

const char* const kHeading = "## Ground on a survey (ladarvr bench ground-survey)";

struct GroundSurveyCli {
    double points = 1e8;
    std::string in;  // a survey to classify instead of the generated one
    int repeats = 3, warmup = 1;
    double memory_mb = 1024.0;
    std::string dir;      // the work folder; the generated survey is kept there
    std::string ladarvr;  // the shipped binary; default: app/ladarvr beside this build's bench/
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
};

struct Run {
    double seconds = 0;
    double rss_mib = 0;
};

// Runs `exe args...` as a child with stdout and stderr appended to `log`; its wall time
// and peak RSS. Throws core::Error naming the command and the log when it fails.
Run runChild(const fs::path& exe, const std::vector<std::string>& args, const fs::path& log) {
    std::vector<std::string> words = {exe.string()};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    std::string shown;
    for (const std::string& w : words) shown += (shown.empty() ? "" : " ") + w;
    std::fflush(nullptr);
    const auto t0 = Clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) throw core::Error("bench ground-survey: fork failed");
    if (pid == 0) {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
        if (fd < 0) ::_exit(126);
        ::dup2(fd, STDOUT_FILENO);
        ::dup2(fd, STDERR_FILENO);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    int status = 0;
    struct rusage usage{};
    if (::wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw core::Error("bench ground-survey: `" + shown + "` failed (exit " +
                          std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + "); its output is in " +
                          log.string());
    return {secondsSince(t0), double(usage.ru_maxrss) / 1024.0};
}

// The last line of `log` that starts with `prefix`, or empty.
std::string lastLine(const fs::path& log, const std::string& prefix) {
    std::istringstream text(readText(log));
    std::string line, last;
    while (std::getline(text, line))
        if (line.rfind(prefix, 0) == 0) last = line;
    return last;
}

fs::path shippedBinary(const GroundSurveyCli& cli) {
    if (!cli.ladarvr.empty()) return cli.ladarvr;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw core::Error("bench ground-survey: cannot find this executable (/proc/self/exe); give --ladarvr");
    return exe.parent_path().parent_path() / "app" / "ladarvr";
}

void checkOptions(const GroundSurveyCli& cli) {
    if (!(cli.points >= 1e4 && cli.points <= 1e10))
        throw core::Error("bench ground-survey: --points " + core::shownNumber(cli.points) + ": allowed [1e4, 1e10]");
    if (cli.repeats < 1 || cli.repeats > 100)
        throw core::Error("bench ground-survey: --repeats " + std::to_string(cli.repeats) + ": allowed [1, 100]");
    if (cli.warmup < 0 || cli.warmup > 10)
        throw core::Error("bench ground-survey: --warmup " + std::to_string(cli.warmup) + ": allowed [0, 10]");
    if (!(cli.memory_mb >= 64 && cli.memory_mb <= 1e7))
        throw core::Error("bench ground-survey: --memory-mb " + core::shownNumber(cli.memory_mb) +
                          ": allowed [64, 1e7]");
    if (!cli.in.empty() && !fs::is_regular_file(cli.in))
        throw core::Error("bench ground-survey: --in " + cli.in + ": allowed a LAS, LAZ or COPC file");
}

// The generator's survey of about `points` points as COPC in `dir`, written once.
fs::path survey(const fs::path& exe, const fs::path& dir, double points, const fs::path& log) {
    const int side = std::max(1, int(std::lround(std::sqrt(points / 100.0))));
    const std::string xres = std::to_string(side);
    const fs::path file = dir / ("survey_" + xres + "x" + xres + ".copc.laz");
    if (fs::is_regular_file(file)) {
        std::fprintf(stderr, "bench ground-survey: reusing %s\n", file.c_str());
        return file;
    }
    std::fprintf(stderr, "bench ground-survey: generating %s (100 views of %s x %s rays)\n", file.c_str(), xres.c_str(),
                 xres.c_str());
    runChild(exe, {"generate", "--xres", xres, "--yres", xres, "--out", file.string()}, log);
    return file;
}

std::string row(const std::string& name, const std::vector<double>& seconds, double n, double rss_mib) {
    const Spread s = spread(seconds);
    std::vector<double> rates;
    for (double t : seconds) rates.push_back(n / t / 1e6);
    return "| " + name + " | " + fmtSpread("%.2f", s) + " | " + fmtSpread("%.2f", spread(rates)) + " | " +
           fmt("%.0f", rss_mib) + " |\n";
}

void run(const GroundSurveyCli& cli) {
    checkOptions(cli);
    const fs::path exe = shippedBinary(cli);
    if (!fs::is_regular_file(exe))
        throw core::Error("bench ground-survey: the shipped binary " + exe.string() +
                          " is not there; build the `ladarvr` target or give --ladarvr");
    const fs::path dir =
        cli.dir.empty() ? fs::temp_directory_path() / "ladarvr-bench-ground-survey" : fs::path(cli.dir);
    fs::create_directories(dir);
    const fs::path log = dir / "children.log";
    fs::remove(log);
    const fs::path in = cli.in.empty() ? survey(exe, dir, cli.points, log) : fs::path(cli.in);
    const double n = double(io::CloudReader(in).declaredPoints());
    const fs::path ground_out = dir / "ground.laz", index_out = dir / "index.copc.laz";
    const std::string memory = core::shownNumber(cli.memory_mb);
    const std::vector<std::string> ground = {"ground",      in.string(), "--out", ground_out.string(),
                                             "--memory-mb", memory};
    const std::vector<std::string> index = {"index", in.string(), "--out", index_out.string(), "--memory-mb", memory};
    std::vector<double> ground_s, index_s;
    double ground_rss = 0, index_rss = 0;
    for (int r = 0; r < cli.warmup + cli.repeats; ++r) {
        const bool warm = r < cli.warmup;
        const Run g = runChild(exe, ground, log);
        const Run i = runChild(exe, index, log);
        std::fprintf(stderr, "bench ground-survey: %s: ground %.2f s (%.0f MiB), index %.2f s (%.0f MiB)\n",
                     warm ? "warm-up" : ("repeat " + std::to_string(r - cli.warmup + 1)).c_str(), g.seconds, g.rss_mib,
                     i.seconds, i.rss_mib);
        if (warm) continue;
        ground_s.push_back(g.seconds);
        index_s.push_back(i.seconds);
        ground_rss = std::max(ground_rss, g.rss_mib);
        index_rss = std::max(index_rss, i.rss_mib);
    }
    const std::string summary = lastLine(log, "ground: wrote ");
    fs::remove(ground_out);
    fs::remove(index_out);

    const Spread gs = spread(ground_s), is = spread(index_s);
    const double rate = n / gs.median;
    std::ostringstream s;
    s << kHeading << "\n\n"
      << "`./ladarvr bench ground-survey "
      << (cli.in.empty() ? "--points " + core::shownNumber(cli.points) : "--in " + in.filename().string())
      << " --repeats " << cli.repeats << " --memory-mb " << memory << "` on " << cpuName() << ", " << utcNow()
      << ". The survey: " << (cli.in.empty() ? "the generator's demo cloud as COPC, " : "") << in.filename().string()
      << " (" << fmt("%.0f", n) << " points). Each command is the shipped binary in a process of its own, in turn, "
      << cli.warmup << " warm-up run(s) of each first; wall s and M points/s are median [min..max] of " << cli.repeats
      << ", peak RSS the largest.\n\n"
      << "| command | wall s | M points/s | peak RSS MiB |\n|---|---:|---:|---:|\n"
      << row("`ground IN --out OUT.laz --memory-mb " + memory + "`", ground_s, n, ground_rss)
      << row("`index IN --out OUT.copc.laz --memory-mb " + memory + "` (baseline)", index_s, n, index_rss) << "\n"
      << "ground / index: " << fmt("%.2f", gs.median / is.median) << "x the time" << spreadNote(gs, is)
      << ". Goal 2 M points/s: " << (rate >= 2e6 ? "met" : "missed") << " (" << fmt("%.2f", rate / 1e6)
      << " M); within --memory-mb: " << (ground_rss <= cli.memory_mb ? "met" : "missed") << " ("
      << fmt("%.0f", ground_rss) << " MiB).\n";
    if (!summary.empty()) s << "\nThe last run: `" << summary << "`\n";
    std::printf("%s", s.str().c_str());
    if (!cli.no_md) replaceMarkdownSection(cli.md, kHeading, s.str());
}

}  // namespace

void registerGroundSurvey(CLI::App& parent) {
    auto state = std::make_shared<GroundSurveyCli>();
    CLI::App* c = parent.add_subcommand(
        "ground-survey",
        "points per second and peak memory of `ladarvr ground` on a large survey (COPC in, LAZ out), against "
        "`ladarvr index` of the same file in the same run");
    c->add_option("--points", state->points,
                  "points of the generated survey (the generator's demo cloud, 100 views), [1e4, 1e10]")
        ->capture_default_str();
    c->add_option("--in", state->in, "classify this LAS/LAZ/COPC survey instead of the generated one");
    c->add_option("--repeats", state->repeats, "measured runs of each command, [1, 100]")->capture_default_str();
    c->add_option("--warmup", state->warmup, "unmeasured runs of each command first, [0, 10]")->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb, "both commands' --memory-mb")->capture_default_str();
    c->add_option("--dir", state->dir,
                  "work folder: the generated survey is kept there and reused (default: "
                  "ladarvr-bench-ground-survey in the system's temporary folder)");
    c->add_option("--ladarvr", state->ladarvr, "the shipped binary to run (default: app/ladarvr of this build)");
    c->add_option("--md", state->md, "markdown file whose ground-survey section is rewritten")->capture_default_str();
    c->add_flag("--no-md", state->no_md, "print only, leave BENCHMARKS.md alone");
    c->callback([state] { run(*state); });
}

}  // namespace bench
