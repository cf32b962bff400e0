// tests/core/jet_test.cpp: MATLAB's jet table and the height-to-entry rule shared by the generator's
// files and the viewer's height colours.
#include <core/jet.hpp>

#include <core/point_cloud.hpp>

#include <doctest/doctest.h>

#include <vector>

TEST_CASE("jet(4) is MATLAB's: blue, cyan, yellow, red") {
    CHECK(core::jetTable(4) == std::vector<std::uint32_t>{core::packRgb(0, 0, 255), core::packRgb(0, 255, 255),
                                                          core::packRgb(255, 255, 0), core::packRgb(255, 0, 0)});
    const auto jet = core::jetTable(64);
    REQUIRE(jet.size() == 64);
    CHECK(jet[0] == core::packRgb(0, 0, 143));   // [0 0 0.5625]
    CHECK(jet[63] == core::packRgb(128, 0, 0));  // [0.5 0 0]
}

TEST_CASE("jet index: equal bins over [z_min, z_max], lowest bin the last (red) entry") {
    // 4 bins of 2.5 m over [10, 20]: bin = floor((z - 10) / 2.5), index = 3 - bin.
    CHECK(core::jetIndex(10.0, 10.0, 20.0, 4) == 3);
    CHECK(core::jetIndex(12.49, 10.0, 20.0, 4) == 3);
    CHECK(core::jetIndex(12.5, 10.0, 20.0, 4) == 2);
    CHECK(core::jetIndex(17.5, 10.0, 20.0, 4) == 0);
    CHECK(core::jetIndex(20.0, 10.0, 20.0, 4) == 0);  // the top clamps into the last bin
    // Outside the range clamps; an empty range gives the lowest bin's entry.
    CHECK(core::jetIndex(-1e9, 10.0, 20.0, 4) == 3);
    CHECK(core::jetIndex(1e9, 10.0, 20.0, 4) == 0);
    CHECK(core::jetIndex(5.0, 5.0, 5.0, 64) == 63);
    CHECK(core::jetIndex(5.0, 6.0, 5.0, 64) == 63);
}
