// bench/src/main.cpp: `ladarvr-bench`, the benchmark programs' executable, which
// `./ladarvr bench WHAT ...` builds and runs. This file is the one list of the benchmarks.
// Its command line reads as `ladarvr bench`: the words after the program name are parsed as
// the `bench` subcommand's, so usage errors and --help name `ladarvr bench WHAT`, the
// command a user types. Errors and exit statuses follow app's conventions (cli_common.hpp).
#include "register.hpp"

#include <cli_common.hpp>

#include <core/error.hpp>

#include <cstdio>
#include <exception>
#include <vector>

int main(int argc, char** argv) {
    CLI::App cli{"", "ladarvr"};
    cli.require_subcommand(1);
    CLI::App* sub = cli.add_subcommand("bench",
                                       "benchmark programs (warm-up, repeats, medians, "
                                       "ratios against an in-run baseline)");
    sub->require_subcommand(1);
    bench::registerGenerate(*sub);
    bench::registerMetric(*sub);
    bench::registerView(*sub);
    bench::registerPeers(*sub);
    bench::registerAll(*sub);
    bench::registerMutants(*sub);
    bench::registerDetect(*sub);
    bench::registerCorpus(*sub);
    bench::registerIndex(*sub);
    bench::registerGroundIsprs(*sub);
    bench::registerGroundSurvey(*sub);
    bench::registerGroundReal(*sub);
    bench::registerHeights(*sub);
    app::applyConventions(cli);

    // argv with "bench" after the program name: `ladarvr-bench generate` is `ladarvr bench generate`.
    char bench_word[] = "bench";
    std::vector<char*> args(argv, argv + argc);
    args.insert(args.begin() + 1, bench_word);
    const int n = int(args.size());
    try {
        cli.parse(n, args.data());
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return cli.exit(e);  // --help
        std::fprintf(stderr, "ladarvr: error: %s\n", app::usageError(cli, e, n, args.data()).c_str());
        return app::kExitUsage;
    } catch (const core::Error& e) {
        std::fprintf(stderr, "ladarvr: error: %s\n", e.what());
        return app::kExitError;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ladarvr: internal error: %s\n", e.what());
        return app::kExitInternal;
    }
    return app::kExitOk;
}
