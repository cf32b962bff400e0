// app/src/commands.hpp: each subcommand registers itself on the CLI11 app.
// A register function adds the subcommand and its options and sets a callback that
// does the work; callbacks throw core::Error on bad input, which main() reports.
#pragma once
#include <CLI/CLI.hpp>

namespace app {

void registerGenerate(CLI::App& cli);  // cmd_generate.cpp: `ladarvr generate`
void registerMetric(CLI::App& cli);    // cmd_metric.cpp:   `ladarvr metric`
void registerView(CLI::App& cli);      // cmd_view.cpp:     `ladarvr view`
void registerScene(CLI::App& cli);     // cmd_scene.cpp:    `ladarvr scene info`
void registerDetect(CLI::App& cli);    // cmd_detect.cpp:   `ladarvr detect`
void registerTrain(CLI::App& cli);     // cmd_train.cpp:    `ladarvr train`
void registerCorpus(CLI::App& cli);    // cmd_corpus.cpp:   `ladarvr corpus`
void registerStudy(CLI::App& cli);     // cmd_study.cpp:    `ladarvr study`
void registerIndex(CLI::App& cli);     // cmd_index.cpp:    `ladarvr index`
void registerInfo(CLI::App& cli);      // cmd_info.cpp:     `ladarvr info`
void registerGround(CLI::App& cli);    // cmd_ground.cpp:   `ladarvr ground`
/// cmd_study_report.cpp: `ladarvr study report`, added under `study`; returns it.
CLI::App* registerStudyReport(CLI::App& study);

}  // namespace app
