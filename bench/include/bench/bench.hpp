// bench/bench.hpp: `ladarvr bench WHAT`, the benchmark programs (not tests): warm-up,
// repeats, medians and ratios against a baseline measured in the same run.
#pragma once
#include <CLI/CLI.hpp>

namespace bench {

/// Adds the `bench` subcommand to `cli` with one sub-subcommand per benchmark (generate,
/// metric, view, peers, fuzz, all); each callback throws core::Error on bad input.
void registerBench(CLI::App& cli);

}  // namespace bench
