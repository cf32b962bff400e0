// bench/src/formats.hpp: LAZ against binary PCD on a generated cloud (formats.cpp).
#pragma once
#include <core/scene.hpp>
#include <sim/generator.hpp>

#include <filesystem>
#include <string>

namespace bench {

/// Generates the cloud of (`scene`, `options`) (`config` names the configuration) to a
/// binary PCD in `dir`, reads it back chunk by chunk and writes the points again as
/// binary PCD, LAZ and COPC, timing only the writers, then makes benchFormatRuns; prints the
/// tables and, unless `md` is empty, replaces its "## Cloud formats" section. The files
/// are removed after.
/// Four whole `generate` runs of (`scene`, `options`) at the default memory bound, to LAZ,
/// COPC, COPC and LAZ in `dir` (removed after): their totals and write stages as a table,
/// and the verdict on COPC's goal of at most 1.5x LAZ's time.
struct FormatRuns {
    std::string table, verdict;
};
FormatRuns benchFormatRuns(const core::Scene& scene, const sim::GenerateOptions& options,
                           const std::filesystem::path& dir);

void benchFormats(const core::Scene& scene, const sim::GenerateOptions& options, const std::filesystem::path& dir,
                  const std::string& config, const std::string& md);

}  // namespace bench
