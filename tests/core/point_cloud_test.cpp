// tests/core/point_cloud_test.cpp: the field names of a cloud, in the writers' order.
#include <core/point_cloud.hpp>

#include <doctest/doctest.h>

#include <string>
#include <vector>

TEST_CASE("fieldNames: x, y and z first, then each field the cloud holds, in the writers' order") {
    core::CloudFields f;  // rgb, label, view and range by default
    CHECK(core::fieldNames(f) == std::vector<std::string>{"x", "y", "z", "rgb", "label", "view", "range"});
    f = core::CloudFields{false, false, false, false, false, false, false, false, false};
    CHECK(core::fieldNames(f) == std::vector<std::string>{"x", "y", "z"});
    f = core::CloudFields{true, true, true, true, true, true, true, true, true};
    CHECK(core::fieldNames(f) == std::vector<std::string>{"x", "y", "z", "rgb", "label", "view", "range", "intensity",
                                                          "returns", "incidence", "scan_angle", "height_above_ground"});
    f = core::CloudFields{false, true, false, false, false, false, false, true, false};
    CHECK(core::fieldNames(f) == std::vector<std::string>{"x", "y", "z", "label", "scan_angle"});
}
