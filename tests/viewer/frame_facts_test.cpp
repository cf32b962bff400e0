// tests/viewer/frame_facts_test.cpp: a frame's record in the run log: "points_drawn" stays
// the sum over the eyes, "points_drawn_per_eye" is the most one eye drew.
#include "frame_facts.hpp"

#include <doctest/doctest.h>

using namespace viewer;

TEST_CASE("a headset frame's record keeps the eyes' sum and adds the per-eye figure") {
    FrameResult result;
    result.rendered = true;
    FrameFacts facts;
    facts.frame = 3;
    facts.xr = true;
    facts.points_drawn = 2514128;
    facts.points_drawn_per_eye = 1257100;
    facts.points_uploaded = 1638400;
    facts.result = &result;
    const nlohmann::json record = frameRecord(facts);
    CHECK(record["points_drawn"] == 2514128);
    CHECK(record["points_drawn_per_eye"] == 1257100);
    CHECK(record["points_uploaded"] == 1638400);
}
