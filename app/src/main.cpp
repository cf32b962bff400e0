// app/src/main.cpp: the `ladarvr` CLI. Every error becomes one line on stderr and an exit
// status from cli_common.hpp: 1 for a failed run, 2 for a command line that does not
// parse, 70 for a bug. Messages quote file contents and arguments: they are printed
// through platform::printMessage, which escapes control bytes and caps the line.
#include "cli_common.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

int main(int argc, char** argv) {
    CLI::App cli{
        "ladarvr: simulate a drone Ladar, view its point cloud in VR, "
        "measure how visible the target is (Berge et al., CEEC 2016)"};
    cli.set_version_flag("--version", "ladarvr " LADARVR_VERSION, "print the version and exit");
    cli.require_subcommand(1);
    app::registerGenerate(cli);
    app::registerMetric(cli);
    app::registerView(cli);
    app::registerScene(cli);
    app::registerDetect(cli);
    app::registerTrain(cli);
    app::registerCorpus(cli);
    app::registerStudy(cli);
    app::registerIndex(cli);
    app::applyConventions(cli);  // after every subcommand: the checks reach all options
    // The benchmarks are a program of their own (bench/), built and run from the checkout.
    if (argc > 1 && std::strcmp(argv[1], "bench") == 0) {
        std::fprintf(stderr,
                     "ladarvr: error: bench: the benchmarks are not part of this program; run './ladarvr "
                     "bench WHAT' in the source checkout (see './ladarvr bench --help')\n");
        return app::kExitUsage;
    }
    try {
        cli.parse(argc, argv);
    } catch (const CLI::RuntimeError& e) {  // a subcommand's own exit status (view)
        return e.get_exit_code();
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) {  // --help, --version
            // CLI11 answers them before it checks the subcommands: help for a subcommand
            // that does not exist is the usage error it is without --help.
            if (const std::string problem = app::subcommandError(cli, argc, argv); !problem.empty()) {
                platform::printMessage("error", problem);
                return app::kExitUsage;
            }
            return cli.exit(e);
        }
        platform::printMessage("error", app::usageError(cli, e, argc, argv));
        return app::kExitUsage;
    } catch (const core::Error& e) {
        platform::printMessage("error", e.what());
        return app::kExitError;
    } catch (const std::exception& e) {
        platform::printMessage("internal error", e.what());
        return app::kExitInternal;
    }
    return app::kExitOk;
}
