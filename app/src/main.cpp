// app/src/main.cpp: the `ladarvr` CLI. Catches every error, prints one line, exits 1.
#include "commands.hpp"

#include <bench/bench.hpp>

#include <engine/error.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    CLI::App cli{"ladarvr: simulate a drone Ladar, view its point cloud in VR, "
                 "measure how visible the target is (Berge et al., CEEC 2016)"};
    cli.require_subcommand(1);
    app::registerGenerate(cli);
    app::registerMetric(cli);
    app::registerView(cli);
    bench::registerBench(cli);   // `ladarvr bench WHAT` (bench/)
    try {
        cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return cli.exit(e);
    } catch (const engine::Error& e) {
        std::fprintf(stderr, "ladarvr: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ladarvr: internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}
