// bench/src/register.hpp: each benchmark program adds one subcommand under `ladarvr bench`
// (main.cpp calls them).
#pragma once
#include <CLI/CLI.hpp>

namespace bench {

void registerGenerate(CLI::App& parent);      // generate.cpp: `bench generate`
void registerMetric(CLI::App& parent);        // metric.cpp:   `bench metric`
void registerView(CLI::App& parent);          // view.cpp:     `bench view`
void registerPeers(CLI::App& parent);         // peers.cpp:    `bench peers`
void registerAll(CLI::App& parent);           // all.cpp:      `bench all` and `bench fuzz`
void registerMutants(CLI::App& parent);       // mutants.cpp:  `bench mutants`
void registerDetect(CLI::App& parent);        // detect.cpp:   `bench detect`
void registerCorpus(CLI::App& parent);        // corpus.cpp:   `bench corpus`
void registerIndex(CLI::App& parent);         // index.cpp:    `bench index`
void registerGroundIsprs(CLI::App& parent);   // ground_isprs.cpp: `bench ground-isprs`
void registerGroundSurvey(CLI::App& parent);  // ground_survey.cpp: `bench ground-survey`
void registerGroundReal(CLI::App& parent);    // ground_real.cpp: `bench ground-real`
void registerHeights(CLI::App& parent);       // heights.cpp: `bench heights`

}  // namespace bench
