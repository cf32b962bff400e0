// tests/viewer/tools/colour_tool_test.cpp: above-ground colours on a cloud without heights
// above ground are shown as height colours, and the run log records it once.
#include "tools/colour_tool.hpp"

#include <doctest/doctest.h>

using namespace viewer;

TEST_CASE("above-ground colours without heights above ground fall back to height colours") {
    CHECK(shownColourMode(ColourMode::AboveGround, false) == ColourMode::HeightJet);
    CHECK(shownColourMode(ColourMode::AboveGround, true) == ColourMode::AboveGround);
    CHECK(shownColourMode(ColourMode::File, false) == ColourMode::File);
    CHECK(shownColourMode(ColourMode::Label, false) == ColourMode::Label);

    ColourTool tool;
    nlohmann::json summary = nlohmann::json::object();
    tool.noteCloud(ColourMode::AboveGround, true);
    tool.noteCloud(ColourMode::File, false);
    tool.logRun(summary);
    CHECK_FALSE(summary.contains("colour_fallback"));
    tool.noteCloud(ColourMode::AboveGround, false);
    tool.noteCloud(ColourMode::AboveGround, false);  // said once
    tool.logRun(summary);
    CHECK(summary["colour_fallback"]["shown"] == "height");
}
