// corpus/stats.hpp: what a finished corpus holds, for picking trials by difficulty: the
// distribution of every numeric manifest column, a histogram PNG, and study plans of
// items selected by a condition (read by `ladarvr study`).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace corpus {

struct ColumnStats {
    std::string name;   // "metric", "points", "altitude_m" (a sampled value), "points_target", ...
    std::size_t n = 0;  // items with a value (null values are left out)
    double min = 0, p10 = 0, median = 0, p90 = 0, max = 0, mean = 0;
};

struct Stats {
    std::size_t items = 0;
    std::vector<ColumnStats> columns;  // sorted by name
    std::string histogram_column;
    std::vector<std::size_t> histogram;  // item counts per bin over [min, max] of that column
    double histogram_lo = 0, histogram_hi = 0;
    std::filesystem::path histogram_png;
};

struct StatsOptions {
    std::string column;               // histogram column; empty: metric if any, else points
    std::filesystem::path histogram;  // PNG written there
    int bins = 20;
};

/// Reads DIR's manifest (corpus::readManifest) and summarises it; writes the histogram.
/// Throws core::Error naming DIR or the column (listing the columns there are).
Stats computeStats(const std::filesystem::path& dir, const StatsOptions& options);
std::string statsText(const Stats& stats);
std::string statsJson(const Stats& stats);

/// The numeric columns of one manifest line (JSON text), flattened as computeStats names them.
std::vector<std::pair<std::string, double>> manifestColumns(const std::string& line);

struct SelectOptions {
    std::string expression;  // "metric<0.3", conditions joined by ',' all hold
    std::size_t count = 0;
    std::uint64_t seed = 1;
    double time_limit_s = 120.0;
    std::filesystem::path plan;
};

struct SelectResult {
    std::size_t items = 0, matching = 0, written = 0;
};

/// An item picked by selectItems: its id and its cloud file (absolute).
struct SelectedItem {
    std::string id;
    std::filesystem::path cloud;
};
/// Picks `count` of the items of the corpus DIR where `expression` holds, as selectTrials
/// does, without writing anything; `count_name` names the count in the error when fewer
/// items match.
std::vector<SelectedItem> selectItems(const std::filesystem::path& dir, const std::string& expression,
                                      std::size_t count, std::uint64_t seed, const std::string& count_name);

/// Picks `count` of the items where the expression holds (a seeded shuffle, then by id)
/// and writes the plan {"trials": [{"cloud", "scene", "time_limit_s"}], "shuffle_seed"}
/// with paths relative to the plan file. Throws core::Error for a bad expression (naming
/// the columns), or when fewer than `count` items match.
SelectResult selectTrials(const std::filesystem::path& dir, const SelectOptions& options);

}  // namespace corpus
