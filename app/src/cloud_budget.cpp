// app/src/cloud_budget.cpp: the --memory-mb rule for whole cloud files (cloud_budget.hpp).
#include "cloud_budget.hpp"

#include <io/cloud_reader.hpp>
#include <sim/memory_budget.hpp>

namespace app {

void addCloudMemoryOption(CLI::App& command, double& memory_mb, std::string_view holds) {
    memory_mb = sim::kDefaultMemoryMb;
    command
        .add_option("--memory-mb", memory_mb,
                    "memory for " + std::string(holds) +
                        ", MiB [1, 1048576]; a cloud file that would not fit is refused from its header")
        ->capture_default_str();
}

void refuseCloudsOverBudget(std::string_view command, double memory_mb,
                            const std::vector<std::filesystem::path>& clouds, std::uint64_t bytes_per_point,
                            std::string_view why) {
    const std::uint64_t budget = sim::memoryBudgetBytes(memory_mb, command);
    std::uint64_t points = 0;
    for (const std::filesystem::path& file : clouds) points += io::CloudReader(file).pointsBound();
    sim::refuseOverBudget(command, budget, points * bytes_per_point,
                          std::to_string(points) + " points, " + std::string(why),
                          "raise --memory-mb, or give thinned or cropped clouds");
}

}  // namespace app
