// Placeholder until the view benchmark lands.
#include "commands.hpp"
#include <engine/error.hpp>
namespace app {
void registerBenchView(CLI::App& bench) {
    bench.add_subcommand("view", "(not built yet)")->callback([] { throw engine::Error("bench view: not built yet"); });
}
}  // namespace app
