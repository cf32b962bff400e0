// app/src/main.cpp: the `ladarvr` CLI. Every error becomes one line on stderr and an exit
// status from cli_common.hpp: 1 for a failed run, 2 for a command line that does not
// parse, 70 for a bug. Messages quote file contents and arguments: they are printed
// through engine::printMessage, which escapes control bytes and caps the line.
#include "cli_common.hpp"
#include "commands.hpp"

#include <bench/bench.hpp>

#include <engine/error.hpp>
#include <engine/safe_file.hpp>

#include <exception>

int main(int argc, char** argv) {
    CLI::App cli{"ladarvr: simulate a drone Ladar, view its point cloud in VR, "
                 "measure how visible the target is (Berge et al., CEEC 2016)"};
    cli.set_version_flag("--version", "ladarvr " LADARVR_VERSION, "print the version and exit");
    cli.require_subcommand(1);
    app::registerGenerate(cli);
    app::registerMetric(cli);
    app::registerView(cli);
    app::registerScene(cli);
    app::registerDetect(cli);
    app::registerCorpus(cli);
    app::registerStudy(cli);
    bench::registerBench(cli);   // `ladarvr bench WHAT` (bench/)
    app::applyConventions(cli);  // after every subcommand: the checks reach all options
    try {
        cli.parse(argc, argv);
    } catch (const CLI::RuntimeError& e) {  // a subcommand's own exit status (view)
        return e.get_exit_code();
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return cli.exit(e);  // --help, --version
        engine::printMessage("error", app::usageError(cli, e, argc, argv));
        return app::kExitUsage;
    } catch (const engine::Error& e) {
        engine::printMessage("error", e.what());
        return app::kExitError;
    } catch (const std::exception& e) {
        engine::printMessage("internal error", e.what());
        return app::kExitInternal;
    }
    return app::kExitOk;
}
