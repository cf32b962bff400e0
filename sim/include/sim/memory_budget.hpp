// sim/memory_budget.hpp: the --memory-mb rule every command that holds a whole cloud or
// a whole run in memory shares (generate plans its buffers to fit, sim/src/memory_plan;
// detect and the others check their need): the option's range, and the one-line
// refusal that names the least budget that would do, before any work.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace sim {

/// The default of every --memory-mb option, MiB.
inline constexpr double kDefaultMemoryMb = 512.0;

/// --memory-mb in bytes. Throws core::Error("<command>: --memory-mb = <mb>: allowed
/// [1, 1048576]") for a value outside that range (or not finite).
std::size_t memoryBudgetBytes(double memory_mb, std::string_view command);

/// Throws core::Error("<command>: --memory-mb <mb> is too small: this run needs at
/// least <need> MiB (<why>); <advice>") when need_bytes > budget_bytes; nothing else.
void refuseOverBudget(std::string_view command, std::uint64_t budget_bytes, std::uint64_t need_bytes,
                      const std::string& why, const std::string& advice);

}  // namespace sim
