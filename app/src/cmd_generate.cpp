// Placeholder until the generate work lands.
#include "commands.hpp"
#include <engine/error.hpp>
namespace app {
void registerGenerate(CLI::App& cli) {
    cli.add_subcommand("generate", "(not built yet)")->callback([] { throw engine::Error("generate: not built yet"); });
}
}  // namespace app
