// Placeholder until the metric work lands.
#include "commands.hpp"
#include <engine/error.hpp>
namespace app {
void registerMetric(CLI::App& cli) {
    cli.add_subcommand("metric", "(not built yet)")->callback([] { throw engine::Error("metric: not built yet"); });
}
}  // namespace app
