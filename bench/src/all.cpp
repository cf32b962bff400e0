// bench/src/all.cpp: `ladarvr bench all` and `ladarvr bench fuzz`.
//
// bench all regenerates BENCHMARKS.md from scratch on the current machine: it writes the
// file's header, then runs the benchmarks of its step list (allSteps) one after the other
// as child processes of this same executable, ladarvr-bench (each in a fresh process, so GL
// contexts, Embree devices and thread pools never overlap), with a progress line per
// step. Each benchmark replaces its own `## ` section; a benchmark that prints its table
// instead (bench view) gets a section made of its output. The PNG plots are redrawn
// from the benchmarks' CSV files at the end, and the header is rewritten with the steps'
// times. bench fuzz runs scripts/fuzz.sh (libFuzzer, clang build in build/fuzz) for a
// bounded time per target and writes the `## Fuzzing (ladarvr bench fuzz)` section.
#include "common.hpp"
#include "register.hpp"

#include <core/error.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>

#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;

/// Runs `cmd` through the shell; stdout is echoed line by line and returned, stderr
/// passes through. Returns the exit status in *status.
std::string runEcho(const std::string& cmd, int* status) {
    std::string out;
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) throw core::Error("bench: cannot run '" + cmd + "'");
    char buf[4096];
    while (std::fgets(buf, sizeof buf, p)) {
        out += buf;
        std::fputs(buf, stdout);
        std::fflush(stdout);
    }
    const int rc = ::pclose(p);
    *status = WIFEXITED(rc) ? WEXITSTATUS(rc) : 128;
    return out;
}

// --- bench fuzz -------------------------------------------------------------

struct BenchFuzzCli {
    int seconds = 600;                 // per target: ten minutes, the least a recorded run fuzzes each parser
    std::vector<std::string> targets;  // empty: every target of scripts/fuzz.sh
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
};

struct FuzzRun {
    std::string target;
    long long seconds = 0, runs = 0, corpus = 0, cov = 0, crashes = 0;
    int rc = 0;
};

long long field(const std::string& line, const std::string& key) {
    const std::size_t at = line.find(" " + key + "=");
    return at == std::string::npos ? -1 : std::atoll(line.c_str() + at + key.size() + 2);
}

/// What a fuzz target exercises, for the table.
std::string fuzzParser(const std::string& target) {
    if (target == "fuzz_scene_json") return "`io::loadSceneJson` (scene JSON + Assimp meshes)";
    if (target == "fuzz_cloud_reader")
        return "`io::readCloudData` and `io::CloudReader` (PCD ascii/binary/compressed, PLY)";
    if (target == "fuzz_view_script") return "`viewer::parseScript` (the viewer's --script files)";
    if (target == "fuzz_las_reader")
        return "`io::CloudReader` on LAS/LAZ (our checks, then LASzip), side records kept and positions only too";
    if (target == "fuzz_copc_reader")
        return "`io::checkCopc` and `io::CopcReader` on COPC, the whole hierarchy and by page";
    if (target == "fuzz_las_crs") return "`io::crsFromWkt` and `io::crsFromGeoKeys` (a LAS file's CRS records)";
    if (target == "fuzz_detect_model")
        return "`detect::checkXgboostModel` (the detector model's trees), then XGBoost on what it passes";
    if (target == "fuzz_view_replay") return "`io::parseTrace` and the viewer's replay player (--replay traces)";
    if (target == "fuzz_candidates_file")
        return "`io::parseCandidates` (candidates files of `view --candidates` and study plans), read back when "
               "written";
    if (target == "fuzz_study_file")
        return "`study::parsePlan` and `study::parseDesign` (study files), the sessions a design expands to";
    if (target == "fuzz_study_report")
        return "`study::parseReportTrials` and `study::parseQuestionnaires` (a session's CSV files, `study report`)";
    return "?";
}

void runFuzz(const BenchFuzzCli& cli) {
    if (cli.seconds < 1 || cli.seconds > 86400)
        throw core::Error("bench fuzz: --seconds = " + std::to_string(cli.seconds) + ": allowed [1, 86400]");
    const fs::path script = sourceRoot() / "scripts" / "fuzz.sh";
    if (!fs::exists(script)) throw core::Error("bench fuzz: " + script.string() + " is missing");
    const auto t0 = Clock::now();
    int status = 0;
    std::fprintf(stderr, "bench fuzz: building the clang targets and fuzzing each for %d s\n", cli.seconds);
    std::string command = "bash " + shellQuote(script.string()) + " " + std::to_string(cli.seconds);
    std::string given;
    for (const std::string& t : cli.targets) {
        command += " " + shellQuote(t);
        given += " --target " + t;
    }
    // A run of some targets keeps a section of its own, so the last run of all stays beside it.
    const std::string heading = cli.targets.empty() ? "## Fuzzing (ladarvr bench fuzz)"
                                                    : "## Fuzzing, selected targets (ladarvr bench fuzz --target)";
    const std::string out = runEcho(command, &status);
    std::vector<FuzzRun> runs;
    std::istringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
        if (line.rfind("fuzz: ", 0) != 0 || line.find(" runs=") == std::string::npos) continue;
        FuzzRun r;
        r.target = line.substr(6, line.find(' ', 6) - 6);
        r.seconds = field(line, "seconds");
        r.runs = field(line, "runs");
        r.corpus = field(line, "corpus");
        r.cov = field(line, "cov");
        r.crashes = field(line, "crashes");
        r.rc = int(field(line, "rc"));
        runs.push_back(r);
    }
    if (runs.empty())
        throw core::Error("bench fuzz: " + script.string() + " ran no target (exit " + std::to_string(status) +
                          "); is clang installed? (BENCH_PACKAGES of ./ladarvr)");
    std::ostringstream s;
    s << heading << "\n\n"
      << "Command: `"
      << (std::getenv("LADARVR_FUZZ_JOBS") ? "LADARVR_FUZZ_JOBS=" + std::string(std::getenv("LADARVR_FUZZ_JOBS")) + " "
                                           : "")
      << "./ladarvr bench fuzz --seconds " << cli.seconds << given
      << "` (runs `scripts/fuzz.sh`); machine: " << std::thread::hardware_concurrency() << " cores, " << cpuName()
      << "; " << utcNow() << "; " << fmt("%.0f", secondsSince(t0))
      << " s in all, build included. libFuzzer from Debian's clang, core, platform, io and the sources each "
      << "target compiles in compiled with ASan + UBSan (UB aborts), one process per target (as many at a time as "
         "there are cores, "
      << "or LADARVR_FUZZ_JOBS), "
      << "each held to -rss_limit_mb=2048 and -malloc_limit_mb=512, seeds from fuzz/seeds, "
      << "tests/data and earlier runs (corpus kept in build/fuzz/corpus). Not run in CI.\n\n"
      << "Seconds: how long each target's process ran, loading its corpus included (fewer than asked where it "
         "stopped at a crash).\n\n"
      << "| target | parser | seconds | executions | exec/s | corpus | coverage (edges) | crashes |\n"
      << "|---|---|---|---|---|---|---|---|\n";
    long long crashes = 0;
    for (const FuzzRun& r : runs) {
        crashes += r.crashes;
        s << "| " << r.target << " | " << fuzzParser(r.target) << " | " << r.seconds << " | " << r.runs << " | "
          << fmt("%.0f", r.seconds > 0 ? double(r.runs) / double(r.seconds) : 0.0) << " | " << r.corpus << " | "
          << r.cov << " | " << r.crashes << (r.rc != 0 ? " (exit " + std::to_string(r.rc) + ")" : "") << " |\n";
    }
    s << "\nCrashes found by earlier runs are kept as regression tests (tests/data/io/fuzz_regressions/, "
         "tests/io/fuzz_regression_test.cpp); docs/stress.md lists them.\n";
    if (!cli.no_md) {
        replaceMarkdownSection(cli.md, heading, s.str());
        std::fprintf(stderr, "bench fuzz: wrote the section to %s\n", cli.md.c_str());
    } else {
        std::fputs(s.str().c_str(), stdout);
    }
    if (crashes > 0 || status != 0)
        throw core::Error("bench fuzz: " + std::to_string(crashes) +
                          " crash(es) found; inputs in build/fuzz/artifacts/");
}

// --- bench all --------------------------------------------------------------

struct BenchAllCli {
    bool quick = false;
    bool dry_run = false;
    int fuzz_seconds = 0;  // 0: 90 (30 with --quick)
    std::string only;      // comma-separated subset
    std::string md = "BENCHMARKS.md";
    std::string img_dir;          // default: <source>/docs/img
    std::string csv_dir = "out";  // where benchmarks leave CSV files for the plots
};

struct Step {
    std::string name, args, heading;  // heading: the section the benchmark writes
    bool writes_md = true;            // false: bench all makes the section from stdout
    double seconds = 0;
    int status = 0;
};

const char* kHeader =
    "# Benchmarks\n\n"
    "Figures come from benchmark programs (`./ladarvr bench ...`), never from tests. Each\n"
    "warms up, repeats, reports medians and compares against a baseline measured in the same\n"
    "run; the development machines have 2 noisy cores, so read the ratios, not lone times.\n"
    "`./ladarvr bench all` regenerates this file and its plots on the current machine.\n";

/// The benchmarks `bench all` runs, in order, with the arguments `cli` gives them.
std::vector<Step> allSteps(const BenchAllCli& cli) {
    const int fuzz_s = cli.fuzz_seconds > 0 ? cli.fuzz_seconds : cli.quick ? 30 : 90;
    const std::string q = cli.quick ? " --quick" : "";
    const std::string md = " --md " + shellQuote(cli.md);
    return {
        {"generate", "generate" + q + md, "## Generator (ladarvr bench generate)"},
        {"metric", "metric" + q + md + " --csv " + shellQuote((fs::path(cli.csv_dir) / "bench_metric.csv").string()),
         "## Metric (ladarvr bench metric)"},
        {"view", std::string("view") + (cli.quick ? " --points 1638400 --frames 5 --warmup 2" : ""),
         "## Viewer (ladarvr bench view)", false},
        {"peers", "peers" + q + md, "## Peers (ladarvr bench peers)"},
        {"detect", "detect" + md, "## Detector (ladarvr bench detect)"},
        {"fuzz", "fuzz --seconds " + std::to_string(fuzz_s) + md, "## Fuzzing (ladarvr bench fuzz)"},
    };
}

/// "generate, metric, ...": the names of allSteps, for help and messages.
std::string stepNames() {
    std::string names;
    for (const Step& s : allSteps(BenchAllCli{})) names += (names.empty() ? "" : ", ") + s.name;
    return names;
}

void runAll(const BenchAllCli& cli) {
    std::vector<Step> steps = allSteps(cli);
    if (!cli.only.empty()) {
        std::vector<Step> keep;
        for (const Step& s : steps)
            if (("," + cli.only + ",").find("," + s.name + ",") != std::string::npos) keep.push_back(s);
        if (keep.empty()) throw core::Error("bench all: --only '" + cli.only + "': allowed a list of " + stepNames());
        steps = keep;
    }
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw core::Error("bench all: cannot find this executable (/proc/self/exe)");
    const auto t0 = Clock::now();
    if (cli.dry_run) {
        for (std::size_t i = 0; i < steps.size(); ++i)
            std::printf("bench all: [%zu/%zu] %s %s\n", i + 1, steps.size(), exe.c_str(), steps[i].args.c_str());
        return;
    }
    const std::string started = utcNow();
    // From scratch: the header alone, then each benchmark appends its section.
    platform::writeFileAtomic(cli.md, std::string(kHeader));
    int failed = 0;
    for (std::size_t i = 0; i < steps.size(); ++i) {
        Step& s = steps[i];
        std::fprintf(stderr, "bench all: [%zu/%zu] bench %s (%.0f s so far)\n", i + 1, steps.size(), s.args.c_str(),
                     secondsSince(t0));
        const auto t1 = Clock::now();
        // The viewer's desktop mirror and OpenXR paths need a display and a runtime: without
        // DISPLAY, run it under the viewer tests' private Xvfb + Monado (simulated HMD).
        std::string prefix;
        const fs::path headless = sourceRoot() / "tests" / "viewer" / "headless_env.sh";
        const char* display = std::getenv("DISPLAY");
        if (s.name == "view" && (!display || !*display) && fs::exists(headless))
            prefix = "bash " + shellQuote(headless.string()) + " --monado-stay --timeout 1500 -- ";
        const std::string out = runEcho(prefix + shellQuote(exe.string()) + " " + s.args, &s.status);
        s.seconds = secondsSince(t1);
        std::fprintf(stderr, "bench all: [%zu/%zu] bench %s %s in %.0f s\n", i + 1, steps.size(), s.name.c_str(),
                     s.status == 0 ? "done" : "FAILED", s.seconds);
        failed += s.status != 0;
        const bool has_section = readText(cli.md).find(s.heading) != std::string::npos;
        if (!has_section) {
            // Markdown tables need a blank line before them: add one where the output has none.
            std::string body, line, previous;
            std::istringstream lines(out);
            while (std::getline(lines, line)) {
                if (!line.empty() && line[0] == '|' && !previous.empty() && previous[0] != '|') body += "\n";
                body += line + "\n";
                previous = line;
            }
            std::string section = s.heading + "\n\nCommand: `./ladarvr bench " + s.args +
                                  "` (section written by "
                                  "`bench all` from the program's output); machine: " +
                                  std::to_string(std::thread::hardware_concurrency()) + " cores, " + cpuName() + "; " +
                                  utcNow() + "; " + fmt("%.0f", s.seconds) + " s" +
                                  (s.status ? ", FAILED with exit status " + std::to_string(s.status) : "") + ".\n\n" +
                                  body;
            replaceMarkdownSection(cli.md, s.heading, section);
        }
    }
    // Plots from the benchmarks' CSV files.
    const fs::path root = sourceRoot();
    const fs::path img = cli.img_dir.empty() ? root / "docs" / "img" : fs::path(cli.img_dir);
    const fs::path metric_csv = fs::path(cli.csv_dir) / "bench_metric.csv";
    // Only from a CSV this run wrote: a stale one must not overwrite the committed plot.
    bool metric_ran = false;
    for (const Step& s : steps) metric_ran = metric_ran || (s.name == "metric" && s.status == 0);
    if (metric_ran && fs::exists(metric_csv) && fs::exists(root / "scripts" / "plot_metric_bench.py")) {
        int status = 0;
        fs::create_directories(img, ec);
        const fs::path png = img / "metric_error_vs_time.png";
        runEcho("python3 " + shellQuote((root / "scripts" / "plot_metric_bench.py").string()) + " " +
                    shellQuote(metric_csv.string()) + " " + shellQuote(png.string()),
                &status);
        std::fprintf(stderr, "bench all: plot %s %s\n", png.c_str(), status == 0 ? "drawn" : "FAILED");
        failed += status != 0;
    }
    const double total = secondsSince(t0);
    std::ostringstream h;
    h << kHeader << "\nThis file: `./ladarvr bench all" << (cli.quick ? " --quick" : "")
      << (cli.only.empty() ? "" : " --only " + cli.only) << "`, started " << started << " on "
      << std::thread::hardware_concurrency() << " cores (" << cpuName() << "), " << fmt("%.0f", total) << " s in all: ";
    for (std::size_t i = 0; i < steps.size(); ++i)
        h << (i ? ", " : "") << steps[i].name << " " << fmt("%.0f s", steps[i].seconds)
          << (steps[i].status ? " (FAILED)" : "");
    h << ".\n";
    replaceMarkdownHeader(cli.md, h.str());
    std::fprintf(stderr, "bench all: %s in %.0f s (%s)\n", failed ? "finished with failures" : "done", total,
                 cli.md.c_str());
    if (failed) throw core::Error("bench all: " + std::to_string(failed) + " step(s) failed; see above");
}

}  // namespace

void registerAll(CLI::App& parent) {
    auto fuzz = std::make_shared<BenchFuzzCli>();
    CLI::App* f = parent.add_subcommand(
        "fuzz",
        "libFuzzer targets of the scene JSON, cloud, LAS/COPC, viewer script and replay readers and "
        "the detector model checker "
        "for a bounded time each (clang build in build/fuzz; not CI)");
    f->add_option("--seconds", fuzz->seconds, "seconds per target")->capture_default_str();
    f->add_option("--target", fuzz->targets,
                  "fuzz only this target (repeatable; scripts/fuzz.sh names them); the section is then "
                  "'Fuzzing, selected targets'");
    f->add_option("--md", fuzz->md, "markdown file whose fuzzing section is rewritten")->capture_default_str();
    f->add_flag("--no-md", fuzz->no_md, "print the section, leave the file alone");
    f->callback([fuzz] { runFuzz(*fuzz); });

    auto all = std::make_shared<BenchAllCli>();
    CLI::App* a = parent.add_subcommand("all", "every benchmark in sequence (" + stepNames() +
                                                   "), BENCHMARKS.md and its plots regenerated from scratch");
    a->add_flag("--quick", all->quick, "pass --quick (or small sizes) to every benchmark, 30 s of fuzzing");
    a->add_option("--fuzz-seconds", all->fuzz_seconds, "seconds per fuzz target (default 90, 30 with --quick)");
    a->add_option("--only", all->only, "comma-separated subset of " + stepNames());
    a->add_option("--md", all->md, "the markdown file to regenerate")->capture_default_str();
    a->add_option("--img-dir", all->img_dir, "where the PNG plots go (default: <source>/docs/img)");
    a->add_option("--csv-dir", all->csv_dir, "where benchmarks write their CSV files")->capture_default_str();
    a->add_flag("--dry-run", all->dry_run, "print the steps only");
    a->callback([all] { runAll(*all); });
}

}  // namespace bench
