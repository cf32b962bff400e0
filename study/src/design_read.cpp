// study/src/design_read.cpp: a design file read from disk (study/design.hpp): the text
// parsed by parseDesign, each corpus block's items picked from its corpus folder, and
// every file the design names checked. Apart from design.cpp, which parses and expands
// text alone and needs no corpus, so a parser of outside text is built without it.
#include <study/design.hpp>

#include "json_fields.hpp"

#include <core/error.hpp>
#include <corpus/stats.hpp>
#include <platform/safe_file.hpp>
#include <platform/sha256.hpp>

namespace study {

Design readDesign(const std::filesystem::path& file, std::string* sha256) {
    const std::string shown = core::printable(file.string(), 400);
    const std::string text = platform::readTextFile(file, kMaxDesignBytes, "study: " + shown + ":");
    Design design =
        parseDesign(text, shown, file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path());
    // A corpus block's trials: the items its condition picks, each a cloud trial named by
    // its item (as `corpus --select` writes them into a plan).
    for (std::size_t b = 0; b < design.blocks.size(); ++b) {
        DesignBlock& block = design.blocks[b];
        if (block.corpus.empty()) continue;
        const std::string w = "study: " + shown + ": blocks[" + std::to_string(b) + "]";
        std::vector<corpus::SelectedItem> items;
        try {
            items = corpus::selectItems(block.corpus, block.select, block.count, block.select_seed, "count");
        } catch (const core::Error& e) {
            throw core::Error(w + ": " + e.what());
        }
        for (const corpus::SelectedItem& item : items) {
            PlanTrial t;
            t.cloud = item.cloud;
            t.source = item.cloud.string();
            t.name = "item " + item.id;
            t.time_limit_s = block.time_limit_s;
            block.trials.push_back(std::move(t));
        }
    }
    for (std::size_t b = 0; b < design.blocks.size(); ++b)
        for (std::size_t i = 0; i < design.blocks[b].trials.size(); ++i)
            detail::checkTrialFiles(design.blocks[b].trials[i], "study: " + shown + ": blocks[" + std::to_string(b) +
                                                                    "].trials[" + std::to_string(i) + "]");
    for (std::size_t i = 0; i < design.practice.size(); ++i)
        detail::checkTrialFiles(design.practice[i], "study: " + shown + ": practice[" + std::to_string(i) + "]");
    for (std::size_t i = 0; i < design.conditions.size(); ++i)
        if (!design.conditions[i].detector.empty() && design.conditions[i].detector != "baseline")
            platform::checkInputFile(design.conditions[i].detector,
                                     "study: " + shown + ": conditions[" + std::to_string(i) + "].detector");
    if (sha256) *sha256 = platform::sha256Hex(text);
    return design;
}

}  // namespace study
