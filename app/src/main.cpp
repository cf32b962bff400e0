// app/src/main.cpp: the `ladarvr` CLI. Catches every error, prints one line, exits 1.
#include "commands.hpp"

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
    CLI::App* bench = cli.add_subcommand("bench", "benchmark programs (warm-up, repeats, medians, "
                                                  "ratios against an in-run baseline)");
    bench->require_subcommand(1);
    app::registerBenchGenerate(*bench);
    app::registerBenchMetric(*bench);
    app::registerBenchView(*bench);
    app::registerBenchPeers(*bench);
    app::registerBenchAll(*bench);
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
