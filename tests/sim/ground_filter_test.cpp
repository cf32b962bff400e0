// tests/sim/ground_filter_test.cpp: the ground filter seams inside the generator: the
// paper's RANSAC untouched, SMRF on the whole cloud (threads, spool), the DTM file, and
// the line `generate` prints when RANSAC leaves the terrain coloured.
#include <test_files.hpp>
#include <scene_builders.hpp>

#include <sim/dtm.hpp>
#include <sim/generator.hpp>

#include <core/error.hpp>
#include <io/scene_file.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

sim::GenerateOptions smallOptions(sim::GroundMethod method) {
    sim::GenerateOptions o;
    o.orbit.xres = 96;
    o.orbit.yres = 64;
    o.orbit.views = 12;
    o.ground.method = method;
    return o;
}

std::size_t differentPoints(const core::PointCloud& a, const core::PointCloud& b) {
    REQUIRE(a.points.size() == b.points.size());
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.points.size(); ++i)
        n += std::memcmp(&a.points[i], &b.points[i], sizeof(core::CloudPoint)) != 0;
    return n;
}

double hillyHeight(double x, double y) {
    return 3.0 * std::sin(x / 13.0) * std::cos(y / 9.0) + 2.0 * std::sin((x + 2.0 * y) / 23.0);
}

}  // namespace

TEST_CASE("the ground filter factories: RANSAC per view (the default), SMRF and CSF on the whole cloud") {
    const sim::GroundChoice defaults;
    CHECK(defaults.method == sim::GroundMethod::Ransac);
    CHECK(sim::isPerView(defaults.method));
    const auto ransac = sim::makeViewFilter(defaults);
    REQUIRE(ransac != nullptr);
    CHECK(ransac->method() == sim::GroundMethod::Ransac);
    CHECK(sim::makeCloudFilter(defaults) == nullptr);
    // Through the seam, RANSAC is findGround itself, with the choice's RANSAC options.
    std::vector<glm::vec3> pts;
    for (int i = 0; i < 2000; ++i) pts.emplace_back(float(i % 50), float(i / 50), (i % 7 == 0) ? 5.0f : 0.0f);
    CHECK(ransac->classifyView(pts, 9, nullptr) == sim::findGround(pts, defaults.ransac, 9));
    sim::GroundChoice narrow;
    narrow.ransac.band_m = 1.0;  // the view's z = 5 points leave the band: never ground
    const std::vector<std::uint8_t> narrow_flags = sim::makeViewFilter(narrow)->classifyView(pts, 9, nullptr);
    CHECK(narrow_flags == sim::findGround(pts, narrow.ransac, 9));
    CHECK(narrow_flags[0] == 0);  // pts[0] is at z = 5

    for (const sim::GroundMethod m : {sim::GroundMethod::Smrf, sim::GroundMethod::Csf}) {
        sim::GroundChoice o;
        o.method = m;
        CHECK_FALSE(sim::isPerView(m));
        CHECK(sim::makeViewFilter(o) == nullptr);
        const auto cloud = sim::makeCloudFilter(o);
        REQUIRE(cloud != nullptr);
        CHECK(cloud->method() == m);
        CHECK(cloud->startCloud() != nullptr);
    }

    CHECK(sim::parseGroundMethod("smrf", "x") == sim::GroundMethod::Smrf);
    CHECK(std::string(sim::groundMethodName(sim::GroundMethod::Ransac)) == "ransac");
    CHECK(sim::parseGroundMethod("csf", "x") == sim::GroundMethod::Csf);
    CHECK_THROWS_WITH_AS(sim::parseGroundMethod("pmf", "generate: --ground"),
                         "generate: --ground 'pmf': allowed ransac, smrf, csf", core::Error);
}

TEST_CASE("checking RANSAC against SMRF's terrain changes no point of RANSAC's cloud") {
    const core::Scene scene = test_support::hillyTownScene();
    sim::GenerateOptions o = smallOptions(sim::GroundMethod::Ransac);
    sim::GenerateStats checked, unchecked;
    o.fit_terrain = true;  // as --dtm asks
    const core::PointCloud a = sim::generateCloud(scene, o, &checked);
    o.fit_terrain = false;
    o.ground_check = false;
    const core::PointCloud b = sim::generateCloud(scene, o, &unchecked);
    CHECK(differentPoints(a, b) == 0);
    CHECK_FALSE(a.fields.height_above_ground);
    CHECK(checked.ground_found == unchecked.ground_found);
    CHECK(checked.terrain != nullptr);
    CHECK(unchecked.terrain == nullptr);
    // Rolling terrain: RANSAC leaves much of it coloured, and the check sees it.
    CHECK(checked.terrain_points > 1000);
    CHECK(double(checked.terrain_points_coloured) > 0.3 * double(checked.terrain_points));
}

TEST_CASE("RANSAC's terrain check runs only where no ground labels measure RANSAC") {
    core::Scene scene = test_support::hillyTownScene();
    const sim::GenerateOptions o = smallOptions(sim::GroundMethod::Ransac);
    sim::GenerateStats labelled, unlabelled;
    sim::generateCloud(scene, o, &labelled);
    CHECK(labelled.terrain == nullptr);
    CHECK(labelled.terrain_points == 0);
    REQUIRE(labelled.ground_recall);
    CHECK(*labelled.ground_recall < 0.8);  // the labels alone show RANSAC missing the slopes
    std::size_t relabelled = 0;
    for (core::Mesh& m : scene.meshes)
        if (m.role == core::Role::Ground) {
            m.role = core::Role::Environment;
            ++relabelled;
        }
    REQUIRE(relabelled > 0);
    sim::generateCloud(scene, o, &unlabelled);
    CHECK(unlabelled.ground_truth == 0);
    CHECK(unlabelled.terrain != nullptr);
    CHECK(unlabelled.terrain_points > 1000);
    CHECK(double(unlabelled.terrain_points_coloured) > 0.3 * double(unlabelled.terrain_points));
}

TEST_CASE("SMRF in the generator: follows rolling terrain, bit-identical with 1 and 3 threads") {
    const core::Scene scene = test_support::hillyTownScene();
    sim::GenerateOptions o = smallOptions(sim::GroundMethod::Smrf);
    o.threads = 1;
    sim::GenerateStats st1, st3;
    const core::PointCloud one = sim::generateCloud(scene, o, &st1);
    o.threads = 3;
    const core::PointCloud three = sim::generateCloud(scene, o, &st3);
    CHECK(differentPoints(one, three) == 0);
    CHECK(st1.ground_found == st3.ground_found);
    CHECK(one.fields.height_above_ground);
    REQUIRE(st1.ground_precision);
    REQUIRE(st1.ground_recall);
    CHECK(*st1.ground_precision >= 0.95);
    CHECK(*st1.ground_recall >= 0.95);
    CHECK(st1.ground_method == sim::GroundMethod::Smrf);
    CHECK(st1.planes_accepted == 0);
    CHECK(st1.views_without_ransac == 0);
    // Height above ground: ~0 on whitened ground, the roofs well above it.
    std::size_t roofs = 0;
    for (const core::CloudPoint& p : one.points) {
        // (the foot of a wall that SMRF's slope-scaled threshold whitens counts in
        // the precision above, not here)
        if (p.rgb == core::kWhite && p.label == core::Role::Ground) CHECK(std::abs(p.height_above_ground_m) <= 1.5f);
        if (p.label == core::Role::Environment && p.position.z > hillyHeight(p.position.x, p.position.y) + 5.0f) {
            ++roofs;
            CHECK(p.height_above_ground_m > 3.0f);
        }
    }
    CHECK(roofs > 100);
}

TEST_CASE("SMRF streamed through a spool file writes the same bytes as in memory") {
    const core::Scene scene = test_support::hillyTownScene();
    const test_support::TempDir scratch("sim_ground_filter");
    sim::GenerateOptions o = smallOptions(sim::GroundMethod::Smrf);
    o.threads = 2;
    o.orbit.views = 40;  // 245,760 hits: 9.4 MiB fused, over the budget below
    sim::GenerateStats in_memory, streamed;
    o.memory_budget_bytes = std::size_t(1) << 30;
    sim::generateToFile(scene, o, scratch.path / "memory.pcd", io::CloudFormat::PcdBinary, &in_memory);
    o.memory_budget_bytes = std::size_t(10) << 20;
    sim::generateToFile(scene, o, scratch.path / "spool.pcd", io::CloudFormat::PcdBinary, &streamed);
    CHECK_FALSE(in_memory.streamed);
    CHECK(streamed.streamed);
    CHECK(streamed.ground_found == in_memory.ground_found);
    CHECK(streamed.ground_found > 0);
    const std::string a = test_support::slurp(scratch.path / "memory.pcd");
    CHECK(a.size() > 1000);
    CHECK(a == test_support::slurp(scratch.path / "spool.pcd"));
}

TEST_CASE("the DTM file holds the known terrain's heights, in world coordinates") {
    const core::Scene scene = test_support::hillyTownScene();
    sim::GenerateOptions o = smallOptions(sim::GroundMethod::Smrf);
    sim::GenerateStats st;
    sim::generateCloud(scene, o, &st);
    REQUIRE(st.terrain);
    const test_support::TempDir scratch("sim_dtm");
    const fs::path file = scratch.path / "terrain.asc";
    sim::writeDtm(file, *st.terrain, scene.origin);
    std::istringstream in(test_support::slurp(file));
    std::string key;
    int ncols = 0, nrows = 0;
    double xll = 0, yll = 0, cell = 0, nodata = 0;
    in >> key >> ncols >> key >> nrows >> key >> xll >> key >> yll >> key >> cell >> key >> nodata;
    CHECK(key == "NODATA_value");
    CHECK(ncols == st.terrain->nx);
    CHECK(nrows == st.terrain->ny);
    CHECK(cell == 1.0);
    // Compare each observed-area cell with the terrain mesh's height at its centre;
    // the mesh interpolates hillyHeight linearly over 1 m cells, the cell's minimum
    // sits below its centre on a slope: a few centimetres, decimetres at worst.
    std::size_t compared = 0, far = 0;
    double worst = 0;
    for (int row = 0; row < nrows; ++row)
        for (int col = 0; col < ncols; ++col) {
            double z = 0;
            REQUIRE(static_cast<bool>(in >> z));
            const double x = xll + (col + 0.5) * cell - scene.origin.x;
            const double y = yll + (nrows - 1 - row + 0.5) * cell - scene.origin.y;
            if (std::hypot(x, y) > 30.0) continue;  // the footprint's well-seen middle
            // Skip the houses' footprints and the target (interpolated under them).
            bool under = std::abs(x) < 5 && std::abs(y) < 3;
            for (int k = 0; k < 8; ++k) {
                const double a = k * 0.785398, hx = 25 * std::cos(a), hy = 25 * std::sin(a);
                under |= std::abs(x - hx) < 6.5 && std::abs(y - hy) < 5.5;
            }
            if (under) continue;
            const double err = std::abs(z - scene.origin.z - hillyHeight(x, y));
            worst = std::max(worst, err);
            far += err > 0.35;
            ++compared;
        }
    CHECK(compared > 1000);
    CHECK(far == 0);
    MESSAGE("DTM worst error " << worst << " m over " << compared << " cells");
    // An empty terrain is refused, and nothing is written.
    CHECK_THROWS_AS(sim::writeDtm(scratch.path / "empty.asc", sim::TerrainGrid{}, scene.origin), core::Error);
    CHECK_FALSE(fs::exists(scratch.path / "empty.asc"));
}

// The demo scene under CSF and the riegl-vux1uav preset, seen along `orbit`: the run's stats.
sim::GenerateStats csfUnderVux(const sim::OrbitOptions& orbit) {
    const core::Scene scene = io::loadScene(io::demoScenePath());
    sim::GenerateOptions o;
    o.orbit = orbit;
    o.ground.method = sim::GroundMethod::Csf;
    o.sensor = sim::sensorPreset("riegl-vux1uav");
    sim::GenerateStats st;
    sim::generateCloud(scene, o, &st);
    return st;
}

TEST_CASE("CSF under the riegl-vux1uav preset keeps the demo target above 0.5 m and whitens the ground") {
    // Misregistered views make the ground thick; once they are corrected the terrain must
    // not sit above the corrected ground, or the foot of the target is whitened with it.
    sim::OrbitOptions orbit;
    orbit.xres = 96;
    orbit.yres = 96;
    orbit.views = 40;
    const sim::GenerateStats st = csfUnderVux(orbit);
    REQUIRE(st.terrain);
    CHECK(st.terrain->views_corrected == 40);
    REQUIRE(st.target_kept);
    REQUIRE(st.ground_recall);
    REQUIRE(st.ground_precision);
    CHECK(*st.target_kept >= 0.999);
    CHECK(*st.ground_recall >= 0.999);
    CHECK(*st.ground_precision >= 0.99);
}

TEST_CASE("CSF under riegl-vux1uav over a dense, 9 cm thick ground corrects the views and whitens it") {
    // From 287 m at 34 degrees the demo's ground is about 280 points a square metre and
    // 0.09 m thick before the views are registered. Taken as a thin ground, each cell's
    // lowest point lay 0.27 m below its centre and 4 % of the ground stayed coloured.
    sim::OrbitOptions orbit;
    orbit.altitude_m = 287.0;
    orbit.inclination_deg = 34.0;
    const sim::GenerateStats st = csfUnderVux(orbit);
    REQUIRE(st.terrain);
    CHECK(st.terrain->ground_sigma_uncorrected_m > 0.08);
    CHECK(st.terrain->ground_sigma_uncorrected_m < 0.1);
    CHECK(st.terrain->views_corrected == 100);
    REQUIRE(st.ground_recall);
    REQUIRE(st.target_kept);
    CHECK(*st.ground_recall >= 0.999);
    CHECK(*st.target_kept >= 0.999);
}
