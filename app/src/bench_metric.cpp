// Placeholder until the metric benchmark lands.
#include "commands.hpp"
#include <engine/error.hpp>
namespace app {
void registerBenchMetric(CLI::App& bench) {
    bench.add_subcommand("metric", "(not built yet)")->callback([] { throw engine::Error("bench metric: not built yet"); });
}
}  // namespace app
