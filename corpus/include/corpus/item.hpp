// corpus/item.hpp: building one item: DIR/items/<id>/ with scene.json, the cloud and, with
// the metric, summary.json and views.csv, written into a hidden folder that then
// moves into place whole, and its manifest line.
#pragma once
#include <corpus/plan.hpp>
#include <platform/output_folder.hpp>

#include <filesystem>
#include <string>

namespace corpus {

/// The names an item folder holds (for platform::checkOutputFolder and resume checks).
bool isItemFile(const std::string& name);

struct ItemOutcome {
    std::string id;
    std::string manifest_line;  // one JSON object, no newline
    double seconds = 0.0;
    std::uint64_t points = 0;
    double metric = 0.0;  // NaN without the metric
};

/// Plans and builds item `index` into `out`/items/<id>/ (replacing a folder left there by
/// a run killed before its manifest line), with `threads` generator threads (0 = all).
/// Throws core::Error naming the item.
///
/// Test hook: with the environment variable LADARVR_TEST_HOLD_ITEM="<index>:<fifo>" (a
/// FIFO the test made), item <index> is held with its files written into its hidden
/// temporary folder and not yet moved into place: the run writes "held <id>" into the
/// FIFO (opening it waits for the test to read) and then waits until the FIFO is opened
/// for writing and closed (`: >fifo` releases it). Tests signal the run at that point.
ItemOutcome buildItem(const Planner& planner, std::size_t index, const std::filesystem::path& out, int threads);

}  // namespace corpus
