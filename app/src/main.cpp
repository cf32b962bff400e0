// app/src/main.cpp: the `ladarvr` CLI. Every error becomes one line on stderr and an exit
// status from cli_common.hpp: 1 for a failed run, 2 for a command line that does not
// parse, 70 for a bug. Messages quote file contents and arguments: they are printed
// through platform::printMessage, which escapes control bytes and caps the line. What
// was printed on stdout and never reached it (a full disk) fails the run too.
#include "cli_common.hpp"
#include "commands.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

namespace {

// After the command: flushes stdout. Output that did not reach it (a full disk, an I/O
// error) is one error line and exit 1 where the command had succeeded. A pipe or socket
// whose reader has gone is not an error: with SIGPIPE ignored by the caller, that is how
// `| head` ends a writer (with SIGPIPE's default the process ends at the first write
// and prints nothing either), so the status is kept and nothing is printed.
int finishStdout(int status) {
    errno = 0;
    std::cout.flush();  // in step with stdio: this flushes stdout, and may meet the error
    const bool flushed = std::fflush(stdout) == 0;
    const int error = errno;
    if (flushed && !std::ferror(stdout) && std::cout.good()) return status;
    struct stat st{};
    const bool pipe = fstat(STDOUT_FILENO, &st) == 0 && (S_ISFIFO(st.st_mode) || S_ISSOCK(st.st_mode));
    if (error == EPIPE || (error == 0 && pipe)) return status;
    // The errno of a write that failed before these flushes (std::flush mid-run) is gone.
    platform::printMessage("error", std::string("stdout: write failed") +
                                        (error != 0 ? std::string(": ") + std::strerror(error) : std::string()) +
                                        "; the output is incomplete");
    return status == app::kExitOk ? app::kExitError : status;
}

int run(int argc, char** argv) {
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
    app::registerInfo(cli);
    app::registerGround(cli);
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

}  // namespace

int main(int argc, char** argv) { return finishStdout(run(argc, argv)); }
