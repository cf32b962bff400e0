// tests/sim/ground_units_test.cpp: the units of a file's coordinates from its CRS and the
// ground filter's options (given in metres) turned into them (sim/ground_units.hpp): US
// survey feet read from a real survey's GeoTIFF keys (tests/data/real/4_6_crop.las), a
// geographic CRS refused, a file without CRS left in metres with its options unchanged;
// a survey in feet classified as the same survey in metres.
#include <test_paths.hpp>
#include <sim/ground_units.hpp>

#include <core/error.hpp>
#include <io/cloud_info.hpp>
#include <io/las_crs.hpp>

#include <doctest/doctest.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kReal = fs::path(test_support::isprsDir()) / ".." / "real";
constexpr double kUsFoot_m = 1200.0 / 3937.0;

std::string errorOf(const io::LasCrs& crs) {
    try {
        sim::coordinateUnits(crs, "survey.las", "ground");
    } catch (const core::Error& e) {
        return e.what();
    }
    return {};
}

}  // namespace

TEST_CASE("ground_units: a CRS's units, metres without one, a geographic CRS refused") {
    const sim::CoordinateUnits none = sim::coordinateUnits(io::LasCrs{}, "a.las", "ground");
    CHECK(none.metres());
    CHECK(sim::describe(none) == "metres");

    const sim::CoordinateUnits feet = sim::coordinateUnits(
        io::crsFromWkt("PROJCS[\"NAD83(HARN) / Oregon North (ft)\",GEOGCS[\"NAD83(HARN)\",DATUM[\"x\",SPHEROID[\"GRS "
                       "1980\",6378137,298.257222101]],UNIT[\"degree\",0.0174532925199433]],PROJECTION[\"Lambert_"
                       "Conformal_Conic_2SP\"],UNIT[\"foot\",0.3048,AUTHORITY[\"EPSG\",\"9002\"]]]"),
        "a.las", "ground");
    CHECK_FALSE(feet.metres());
    CHECK(feet.horizontal_m == 0.3048);
    CHECK(feet.vertical_m == 0.3048);  // no vertical CRS: z as x and y
    CHECK(sim::describe(feet) == "feet (0.3048 m)");

    io::LasCrs mixed;
    mixed.source = "wkt";
    mixed.kind = "compound";
    mixed.horizontal_unit = io::epsgUnit(9001);
    mixed.vertical_unit = io::epsgUnit(9003);
    const sim::CoordinateUnits m = sim::coordinateUnits(mixed, "a.las", "ground");
    CHECK(m.horizontal_m == 1.0);
    CHECK(m.vertical_m == kUsFoot_m);
    CHECK(sim::describe(m) == "metres horizontally, US survey feet (0.3048006 m) vertically");

    const io::LasCrs geo = io::crsFromWkt(
        "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
        "UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]]");
    CHECK(errorOf(geo) ==
          "ground: survey.las: its CRS 'WGS 84' (EPSG:4326) is geographic (x and y in degrees), and distances "
          "in degrees cannot take options in metres; allowed a projected CRS in metres or feet (reproject it, e.g. "
          "with PDAL's filters.reprojection)");
    io::LasCrs odd = mixed;
    odd.horizontal_unit = io::epsgUnit(9999);
    CHECK(errorOf(odd).find("a unit of unknown length; allowed") != std::string::npos);
}

TEST_CASE("ground_units: the units of real files: US survey feet from GeoTIFF keys, metres, none") {
    const sim::CoordinateUnits ft = sim::readCoordinateUnits(kReal / "4_6_crop.las", "ground");
    CHECK(ft.horizontal_m == kUsFoot_m);
    CHECK(ft.vertical_m == kUsFoot_m);
    CHECK(sim::describe(ft) == "US survey feet (0.3048006 m)");
    CHECK(sim::readCoordinateUnits(kReal / "hexbin-crop.las", "ground").metres());
    CHECK(sim::readCoordinateUnits(kReal / "sample_c.las", "ground").metres());  // no CRS
    CHECK(sim::readCoordinateUnits(fs::path(test_support::isprsDir()) / "samp24.las", "ground").metres());
    CHECK_THROWS_WITH_AS(sim::readCoordinateUnits(kReal / "missing.las", "ground"), doctest::Contains("missing.las"),
                         core::Error);
}

TEST_CASE("ground_units: options in metres turned into the file's units") {
    sim::GroundFileOptions o;
    const sim::GroundFileOptions same = sim::inUnits(o, sim::CoordinateUnits{});
    CHECK(same.smrf.cell_m == o.smrf.cell_m);
    CHECK(same.smrf.window_m == o.smrf.window_m);
    CHECK(same.smrf.threshold_m == o.smrf.threshold_m);
    CHECK(same.smrf.slope == o.smrf.slope);
    CHECK(same.smrf.scalar == o.smrf.scalar);
    CHECK(same.smrf.low_outlier_m == o.smrf.low_outlier_m);
    CHECK(same.csf.cloth_m == o.csf.cloth_m);
    CHECK(same.csf.threshold_m == o.csf.threshold_m);
    CHECK(same.csf.low_outlier_m == o.csf.low_outlier_m);
    CHECK(same.csf.slope_join_m == o.csf.slope_join_m);

    sim::CoordinateUnits ft;
    ft.horizontal_m = ft.vertical_m = kUsFoot_m;
    const sim::GroundFileOptions f = sim::inUnits(o, ft);
    CHECK(f.smrf.cell_m == doctest::Approx(3.2808333).epsilon(1e-7));
    CHECK(f.smrf.window_m == doctest::Approx(18 * 3.2808333).epsilon(1e-7));
    CHECK(f.smrf.threshold_m == doctest::Approx(0.5 * 3.2808333).epsilon(1e-7));
    CHECK(f.smrf.low_outlier_m == doctest::Approx(6 * 3.2808333).epsilon(1e-7));
    CHECK(f.smrf.slope == doctest::Approx(0.15));  // a rise over a run in the same unit
    CHECK(f.smrf.scalar == doctest::Approx(1.25 * 3.2808333).epsilon(1e-7));
    CHECK(f.csf.cloth_m == doctest::Approx(3.2808333).epsilon(1e-7));
    CHECK(f.csf.threshold_m == doctest::Approx(0.5 * 3.2808333).epsilon(1e-7));
    CHECK(f.csf.slope_join_m == doctest::Approx(0.3 * 3.2808333).epsilon(1e-7));
    CHECK(f.csf.rigidness == o.csf.rigidness);
    CHECK(same.smrf.z_unit_m == 1.0);
    CHECK(f.smrf.z_unit_m == doctest::Approx(kUsFoot_m));
    CHECK(f.csf.z_unit_m == doctest::Approx(kUsFoot_m));

    // Metres across, feet up: a slope of 0.15 m/m is 0.49 ft/m; the scalar's height per
    // slope stays 1.25 m (4.1 ft) at a 1 m/m slope, which is 3.28 ft/m: 1.25 ft per ft/m.
    sim::CoordinateUnits up;
    up.vertical_m = 0.3048;
    const sim::GroundFileOptions u = sim::inUnits(o, up);
    CHECK(u.smrf.cell_m == 1.0);
    CHECK(u.smrf.slope == doctest::Approx(0.15 / 0.3048));
    CHECK(u.smrf.scalar == 1.25);
    CHECK(u.smrf.threshold_m == doctest::Approx(0.5 / 0.3048));
}

TEST_CASE("ground_units: a survey in feet gets the classes of the same survey in metres") {
    // A dense ground (40 points a square metre) 0.05 m thick, under a thin layer 0.45 m
    // above it. In metres the ground is thin (under kThinGround_m, 0.1 m): the terrain is
    // each cell's lowest point, about 0.1 m down, and most of the layer stands over the
    // 0.5 m threshold. The same ground in feet is 0.16 ft thick; were the raster's thickness
    // windows taken in feet, it would read as thick, the terrain would be its centre, and
    // most of the layer would be ground (4 % of the points classed otherwise).
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> across(0.0, 60.0);
    std::normal_distribution<double> noise(0.0, 0.05);
    std::vector<core::CloudPoint> metres;
    for (int i = 0; i < 40 * 60 * 60; ++i) {
        core::CloudPoint p;
        const double x = across(rng), y = across(rng);
        p.position = glm::vec3(float(x), float(y), float(0.02 * x + noise(rng)));
        metres.push_back(p);
    }
    const std::size_t ground_points = metres.size();
    for (int i = 0; i < 2 * 60 * 60; ++i) {
        core::CloudPoint p;
        const double x = across(rng), y = across(rng);
        p.position = glm::vec3(float(x), float(y), float(0.02 * x + 0.45));
        metres.push_back(p);
    }
    std::vector<core::CloudPoint> feet = metres;
    for (core::CloudPoint& p : feet) p.position = glm::vec3(glm::dvec3(p.position) / kUsFoot_m);
    sim::CoordinateUnits ft;
    ft.horizontal_m = ft.vertical_m = kUsFoot_m;
    const sim::GroundFileOptions o;
    const std::vector<std::uint8_t> in_metres = sim::classifyGround(metres, o);
    const std::vector<std::uint8_t> in_feet = sim::classifyGround(feet, sim::inUnits(o, ft));
    std::size_t layer_ground = 0, same = 0;
    for (std::size_t i = 0; i < metres.size(); ++i) {
        same += in_metres[i] == in_feet[i];
        if (i >= ground_points) layer_ground += in_metres[i];
    }
    CHECK(layer_ground < (metres.size() - ground_points) / 4);  // the layer is mostly no ground in metres
    CHECK(double(same) >= 0.999 * double(metres.size()));
}

TEST_CASE("ground_units: the units for a display, a geographic CRS included, never throwing") {
    CHECK(sim::describeUnits(io::LasCrs{}).empty());
    CHECK(sim::describeUnits(io::readCloudCrs(kReal / "4_6_crop.las", "view")) == "US survey feet (0.3048006 m)");
    CHECK(sim::describeUnits(io::readCloudCrs(kReal / "hexbin-crop.las", "view")) == "metres");
    const io::LasCrs geo = io::crsFromWkt(
        "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
        "UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]]");
    CHECK(sim::describeUnits(geo) == "degrees (geographic 'WGS 84' (EPSG:4326))");
}

TEST_CASE("ground_units: the units' symbols for labels, metres without a CRS") {
    const sim::UnitSymbols none = sim::unitSymbols(io::LasCrs{});
    CHECK(none.horizontal == "m");
    CHECK(none.vertical == "m");
    const sim::UnitSymbols ft = sim::unitSymbols(io::readCloudCrs(kReal / "4_6_crop.las", "view"));
    CHECK(ft.horizontal == "US ft");
    CHECK(ft.vertical == "US ft");  // no vertical unit stated: z as x and y
    CHECK(sim::unitSymbols(io::readCloudCrs(kReal / "hexbin-crop.las", "view")).vertical == "m");
    io::LasCrs mixed;
    mixed.source = "wkt";
    mixed.horizontal_unit = io::epsgUnit(9001);
    mixed.vertical_unit = io::epsgUnit(9002);
    CHECK(sim::unitSymbols(mixed).horizontal == "m");
    CHECK(sim::unitSymbols(mixed).vertical == "ft");
}
