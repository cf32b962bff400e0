// Placeholder until the generate benchmark lands.
#include "commands.hpp"
#include <engine/error.hpp>
namespace app {
void registerBenchGenerate(CLI::App& bench) {
    bench.add_subcommand("generate", "(not built yet)")->callback([] { throw engine::Error("bench generate: not built yet"); });
}
}  // namespace app
