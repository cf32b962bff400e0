// tests/detect/terrain_level_test.cpp: the segmentation's terrain levelling
// (detect/src/terrain_level.hpp) on heights with a known answer: ground the terrain fit
// passed under (a square patch half a metre above it) with a vehicle on it comes back to
// the ground's level, the vehicle keeps its height over that ground, ground that is
// already level stays where it is, and a square without enough low points takes its
// neighbours' level.
#include "terrain_level.hpp"

#include <detect/segmentation.hpp>

#include "test_files.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

namespace {

struct Field {
    core::PointCloud cloud;
    std::vector<float> height_m;
    std::vector<char> vehicle;  // each point: 0 ground, 1 the vehicle's side, 2 its roof
};

void add(Field& f, double x, double y, double h, char vehicle) {
    core::CloudPoint p;
    p.position = glm::vec3(float(x), float(y), float(h));
    f.cloud.points.push_back(p);
    f.height_m.push_back(float(h));
    f.vehicle.push_back(vehicle);
}

// Ground on a 0.25 m grid over 64 x 64 m, heights off the terrain by `raised_m` within
// the patch [16, 40) x [16, 40) m, and a 5 x 2 x 1.5 m vehicle's roof and sides standing
// on that ground at (28, 28).
Field field(double raised_m) {
    Field f;
    for (int i = 0; i < 256; ++i)
        for (int j = 0; j < 256; ++j) {
            const double x = 0.25 * i, y = 0.25 * j;
            const bool patch = x >= 16 && x < 40 && y >= 16 && y < 40;
            const bool under = std::abs(x - 28) < 2.5 && std::abs(y - 28) < 1.0;
            const double noise = 0.01 * double((i * 7 + j * 13) % 5 - 2);
            if (!under) add(f, x, y, (patch ? raised_m : 0.0) + noise, 0);
        }
    for (double x = 25.5; x <= 30.5; x += 0.1)
        for (double y = 27.0; y <= 29.0; y += 0.1) add(f, x, y, raised_m + 1.5, 2);
    for (double x = 25.5; x <= 30.5; x += 0.1)
        for (double z = 0.3; z < 1.5; z += 0.1) {
            add(f, x, 27.0, raised_m + z, 1);
            add(f, x, 29.0, raised_m + z, 1);
        }
    return f;
}

}  // namespace

TEST_CASE("ground the terrain passed under is levelled and a vehicle on it keeps its height") {
    Field f = field(0.5);
    detect::detail::levelTerrain(f.cloud, 8.0, f.height_m);
    double ground_max = 0, roof_min = 10, roof_max = 0;
    for (std::size_t i = 0; i < f.height_m.size(); ++i) {
        const glm::vec3 p = f.cloud.points[i].position;
        // Away from the patch's rim, where the interpolation between squares blends levels.
        const bool inner = p.x >= 22 && p.x < 34 && p.y >= 22 && p.y < 34;
        if (!f.vehicle[i] && inner) ground_max = std::max(ground_max, std::abs(double(f.height_m[i])));
        if (f.vehicle[i] == 2) {
            roof_min = std::min(roof_min, double(f.height_m[i]));
            roof_max = std::max(roof_max, double(f.height_m[i]));
        }
    }
    CHECK(ground_max < 0.1);  // was 0.5 above the terrain: a sheet of ground standing out
    CHECK(roof_min > 1.4);
    CHECK(roof_max < 1.6);
}

TEST_CASE("ground already level stays where it is") {
    Field f = field(0.0);
    const std::vector<float> before = f.height_m;
    detect::detail::levelTerrain(f.cloud, 8.0, f.height_m);
    double moved = 0;
    for (std::size_t i = 0; i < before.size(); ++i)
        moved = std::max(moved, std::abs(double(f.height_m[i] - before[i])));
    CHECK(moved < 0.03);
}

TEST_CASE("a square without enough low points takes its neighbours' level") {
    Field f;
    // Two squares of ground 0.4 m above the terrain, and between them a square holding
    // only a roof 3 m up: that roof is lowered by its neighbours' 0.4 m.
    for (int i = 0; i < 96; ++i)
        for (int j = 0; j < 32; ++j) {
            const double x = 0.25 * i, y = 0.25 * j;
            if (x >= 8 && x < 16)
                add(f, x, y, 3.4, 2);
            else
                add(f, x, y, 0.4, 0);
        }
    detect::detail::levelTerrain(f.cloud, 8.0, f.height_m);
    for (std::size_t i = 0; i < f.height_m.size(); ++i)
        if (f.vehicle[i] && std::abs(f.cloud.points[i].position.x - 12.0f) < 0.5f)
            CHECK(f.height_m[i] == doctest::Approx(3.0).epsilon(0.01));
}

TEST_CASE("the levelling square is 0 (none) or 1 to 100 m") {
    detect::SegmentOptions o;
    o.level_cell_m = 0.5;
    CHECK(test_support::errorOf([&] { detect::validate(o); }) ==
          "detect: --level-cell-m = 0.5: allowed 0 (no levelling) or [1, 100] m");
    o.level_cell_m = 0.0;
    CHECK_NOTHROW(detect::validate(o));
}
