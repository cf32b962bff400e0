// app/src/cloud_budget.hpp: the --memory-mb rule of the commands that hold whole cloud
// files in memory (metric's --p1/--p2/--p3, view's cloud file), as detect and generate
// have it: the need is weighed from the files' headers before a point is read, and a
// run that would not fit is refused with one line naming the least budget that does.
#pragma once
#include <CLI/CLI.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace app {

/// Adds `--memory-mb` (default sim::kDefaultMemoryMb) to `command`; `holds` says in the
/// help what the budget covers.
void addCloudMemoryOption(CLI::App& command, double& memory_mb, std::string_view holds);

/// Opens each cloud's header (no point is read) and throws Error("<command>: --memory-mb
/// <mb> is too small: this run needs at least <need> MiB (<points> points, <why>); raise
/// --memory-mb ...") when `bytes_per_point` times the points they declare is over
/// `memory_mb`, or Error("<command>: --memory-mb = ...: allowed [1, 1048576]").
void refuseCloudsOverBudget(std::string_view command, double memory_mb,
                            const std::vector<std::filesystem::path>& clouds, std::uint64_t bytes_per_point,
                            std::string_view why);

}  // namespace app
