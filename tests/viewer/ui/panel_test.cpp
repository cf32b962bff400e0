// tests/viewer/ui/panel_test.cpp: the settings panel's text (no window): the points drawn
// are shown per eye against the one copy of the cloud on the GPU; the line saying why the
// colours shown are not the mode chosen.
#include "points/point_attributes.hpp"
#include "ui/panel.hpp"

#include <doctest/doctest.h>

using namespace viewer;

TEST_CASE("the panel shows the points drawn per eye against the points on the GPU") {
    PanelView v;
    v.points_drawn = 1257064;  // one eye's, of a headset frame that drew 2514128 in all
    v.points_uploaded = 1638400;
    v.point_budget = 3000000;
    v.cells = 512;
    CHECK(pointsDrawnText(v) == "points drawn per eye 1257064 / 1638400 (budget 3000000, 512 cells)");
    v.point_budget = 0;
    CHECK(pointsDrawnText(v) == "points drawn per eye 1257064 / 1638400 (budget unlimited, 512 cells)");
}

TEST_CASE("the panel says why the colours shown are not the mode chosen") {
    const ColourSources survey{false, false, true, true};
    const ColourSources bound{false, true, true, true};
    CHECK(colourNote(ColourMode::AboveGround, survey, true, false) == "above-ground: waiting for the terrain");
    CHECK(colourNote(ColourMode::AboveGround, survey, true, true) == "above-ground: no terrain; showing heights");
    CHECK(colourNote(ColourMode::AboveGround, survey, false, false) == "above-ground: no terrain; showing heights");
    CHECK(colourNote(ColourMode::AboveGround, bound, true, false).empty());
    CHECK(colourNote(ColourMode::Intensity, ColourSources{}, false, false) ==
          "intensity: not in this cloud; showing heights");
    CHECK(colourNote(ColourMode::Class, ColourSources{}, false, false).empty());
    CHECK(colourNote(ColourMode::File, ColourSources{false, false, true, true, false}, false, false) ==
          "file: no colours in this cloud; showing heights");
    CHECK(colourNote(ColourMode::File, survey, false, false).empty());
    // `ladarvr ground`'s output: its intensities and returns are in the file, not on the GPU.
    const ColourSources classified{true, false, true, true, true};
    CHECK(colourNote(ColourMode::Intensity, classified, false, false) ==
          "intensity: not drawn beside heights above ground; showing heights");
    CHECK(colourNote(ColourMode::Return, classified, false, false) ==
          "return: not drawn beside heights above ground; showing heights");
}

TEST_CASE("the pick panel gives lengths in the cloud's own units") {
    PickHit hit;
    hit.local = {3.0, 4.0, 1.0};
    hit.height_above_ground_m = 2.5f;
    PanelView v;
    std::array<std::string, 3> lines = pickPanelLines(hit, {100.0, 200.0, 10.0}, {0.0, 0.0, 1.0}, v);
    CHECK(lines[0] == "103.00 204.00 11.00 m");
    CHECK(lines[1].starts_with("range 5.0 m  "));
    CHECK(lines[2] == "height 2.50 m");
    v.length_unit = "US ft";
    v.height_unit = "ft";
    lines = pickPanelLines(hit, {100.0, 200.0, 10.0}, {0.0, 0.0, 1.0}, v);
    CHECK(lines[0] == "103.00 204.00 11.00 US ft");
    CHECK(lines[1].starts_with("range 5.0 US ft  "));
    CHECK(lines[2] == "height 2.50 ft");
}

TEST_CASE("the pick panel names a survey's ASPRS class in place of our role") {
    PickHit hit;
    hit.local = {3.0, 4.0, 1.0};
    PanelView v;
    CHECK(pickPanelLines(hit, {}, {0.0, 0.0, 1.0}, v)[1] == "range 5.0 m  environment");
    hit.asprs_class = 6;
    CHECK(pickPanelLines(hit, {}, {0.0, 0.0, 1.0}, v)[1] == "range 5.0 m  class 6 building");
    hit.asprs_class = classOfPacked(float(packAttributes(2, 200, 1, 1)));
    CHECK(pickPanelLines(hit, {}, {0.0, 0.0, 1.0}, v)[1] == "range 5.0 m  class 2 ground");
}
