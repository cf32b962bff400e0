// bench/src/formats.hpp: LAZ against binary PCD on a generated cloud (formats.cpp).
#pragma once
#include <core/scene.hpp>
#include <sim/generator.hpp>

#include <filesystem>
#include <string>

namespace bench {

/// Generates the cloud of (`scene`, `options`) (`config` names the configuration) to a
/// binary PCD in `dir`, reads it back chunk by chunk and writes the points again as
/// binary PCD and as LAZ, timing only the writers; prints the table and, unless `md` is
/// empty, replaces its "## Cloud formats" section. The files are removed after.
void benchFormats(const core::Scene& scene, const sim::GenerateOptions& options, const std::filesystem::path& dir,
                  const std::string& config, const std::string& md);

}  // namespace bench
