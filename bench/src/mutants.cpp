// bench/src/mutants.cpp: `ladarvr bench mutants`, the mutation check. Runs
// scripts/mutants.sh (one-line mutants listed in bench/mutants.txt, each applied to a
// clean copy of the tree, rebuilt and run against its module's tests), echoes its lines
// and writes its table as the "## Mutation check" section of BENCHMARKS.md. Not run in CI.
#include "common.hpp"
#include "register.hpp"

#include <core/error.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>
#include <sys/wait.h>

namespace bench {
namespace {

struct BenchMutantsCli {
    std::vector<std::string> names;  // empty: every mutant of the list
    std::string md = "BENCHMARKS.md";
    bool no_md = false;
};

void runMutants(const BenchMutantsCli& cli) {
    const std::filesystem::path script = sourceRoot() / "scripts" / "mutants.sh";
    if (!std::filesystem::exists(script)) throw core::Error("bench mutants: " + script.string() + " is missing");
    std::string cmd = "bash " + shellQuote(script.string());
    for (const std::string& n : cli.names) cmd += " " + shellQuote(n);
    const auto t0 = Clock::now();
    FILE* pipe = ::popen(cmd.c_str(), "r");
    if (!pipe) throw core::Error("bench mutants: cannot run " + script.string());
    std::string table, line;
    bool in_table = false;
    int killed = 0, survived = 0, errors = 0;
    char buf[4096];
    while (std::fgets(buf, sizeof buf, pipe)) {
        line = buf;
        std::fputs(buf, stdout);
        std::fflush(stdout);
        if (line.rfind("mutants-table-begin", 0) == 0)
            in_table = true;
        else if (line.rfind("mutants-table-end", 0) == 0)
            in_table = false;
        else if (in_table)
            table += line;
        if (line.rfind("mutant: ", 0) == 0) {
            killed += line.find(" status=killed") != std::string::npos;
            survived += line.find(" status=survived") != std::string::npos;
            errors += line.find(" status=error") != std::string::npos;
        }
    }
    const int rc = ::pclose(pipe);
    const int status = WIFEXITED(rc) ? WEXITSTATUS(rc) : 128;
    if (table.empty())
        throw core::Error("bench mutants: " + script.string() + " printed no table (exit " + std::to_string(status) +
                          ")");
    std::ostringstream s;
    s << "## Mutation check (ladarvr bench mutants)\n\n"
      << "Command: `./ladarvr bench mutants" << (cli.names.empty() ? "" : " NAME...") << "` (runs `scripts/mutants.sh` "
      << "over `bench/mutants.txt`); " << utcNow() << "; " << fmt("%.0f", secondsSince(t0)) << " s in all. Each "
      << "one-line mutant is applied to a clean copy of the tree, rebuilt, and run against its module's tests; "
      << "killed means the build or a test failed. " << killed << " killed, " << survived << " survived, " << errors
      << " did not apply" << (cli.names.empty() ? "" : " (a subset of the list was run)") << ". Not run in CI.\n\n"
      << table;
    if (!cli.no_md) {
        replaceMarkdownSection(cli.md, "## Mutation check (ladarvr bench mutants)", s.str());
        std::fprintf(stderr, "bench mutants: wrote the section to %s\n", cli.md.c_str());
    }
    if (status != 0) throw core::Error("bench mutants: " + script.string() + " exited with " + std::to_string(status));
}

}  // namespace

void registerMutants(CLI::App& parent) {
    auto cli = std::make_shared<BenchMutantsCli>();
    CLI::App* m = parent.add_subcommand("mutants",
                                        "one-line mutants (bench/mutants.txt) each rebuilt in a clean copy "
                                        "and run against its module's tests: killed or survived (not CI)");
    m->add_option("names", cli->names, "mutants to run (default: all of bench/mutants.txt)");
    m->add_option("--md", cli->md, "markdown file whose mutation section is rewritten")->capture_default_str();
    m->add_flag("--no-md", cli->no_md, "leave the file alone");
    m->callback([cli] { runMutants(*cli); });
}

}  // namespace bench
