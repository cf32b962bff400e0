// Placeholder until the view work lands.
#include "commands.hpp"
#include <engine/error.hpp>
namespace app {
void registerView(CLI::App& cli) {
    cli.add_subcommand("view", "(not built yet)")->callback([] { throw engine::Error("view: not built yet"); });
}
}  // namespace app
