// bench/src/bench.cpp: the `bench` subcommand and its benchmark programs.
#include <bench/bench.hpp>

#include "register.hpp"

namespace bench {

void registerBench(CLI::App& cli) {
    CLI::App* sub = cli.add_subcommand("bench", "benchmark programs (warm-up, repeats, medians, "
                                                "ratios against an in-run baseline)");
    sub->require_subcommand(1);
    registerGenerate(*sub);
    registerMetric(*sub);
    registerView(*sub);
    registerPeers(*sub);
    registerAll(*sub);
    registerMutants(*sub);
    registerDetect(*sub);
    registerCorpus(*sub);
}

}  // namespace bench
