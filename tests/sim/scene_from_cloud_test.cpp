// tests/sim/scene_from_cloud_test.cpp: a real survey turned into a scene
// (sim/scene_from_cloud.hpp) on the small real files of tests/data/real: the terrain mesh
// follows the class-2 points, every other point lies in a box, the vehicle sits on the
// ground, the generator flies the folder's scene with the vehicle's points labelled
// target; a survey in feet converted to metres; the filter used where the file has no
// ground class; refusals in one line (no points, a geographic CRS, too many boxes).
#include <test_paths.hpp>
#include <sim/scene_from_cloud.hpp>

#include <core/error.hpp>
#include <core/scene_info.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <io/scene_file.hpp>
#include <sim/generator.hpp>

#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kReal = fs::path(test_support::isprsDir()) / ".." / "real";
const fs::path kVan = fs::path(test_support::isprsDir()) / ".." / ".." / ".." / "assets" / "common" / "van.obj";

void noProgress(std::size_t) {}

struct Scratch {
    fs::path dir = fs::temp_directory_path() / ("ladarvr-scene-from-cloud-" + std::to_string(::getpid()));
    Scratch() { fs::create_directories(dir); }
    ~Scratch() { fs::remove_all(dir); }
};

// Every point of `file` in the scene's local frame (metres), with whether it is class 2.
struct LocalPoint {
    glm::dvec3 p;
    bool ground;
};
std::vector<LocalPoint> localPoints(const fs::path& file, const sim::SceneFromCloud& s) {
    io::CloudReader reader(file);
    std::vector<core::CloudPoint> chunk;
    std::vector<LocalPoint> out;
    while (reader.nextChunk(chunk)) {
        for (const core::CloudPoint& c : chunk) {
            const glm::dvec3 w = reader.origin() + glm::dvec3(c.position);
            out.push_back(
                {glm::dvec3(w.x * s.units.horizontal_m, w.y * s.units.horizontal_m, w.z * s.units.vertical_m) -
                     s.offset_m,
                 c.label == core::Role::Ground});
        }
        chunk.clear();
    }
    return out;
}

std::string errorOf(const fs::path& file, const sim::SceneFromCloudOptions& o) {
    try {
        sim::buildSceneFromCloud(file, o, noProgress);
    } catch (const core::Error& e) {
        return e.what();
    }
    return {};
}

}  // namespace

TEST_CASE("scene_from_cloud: a real survey's ground as terrain, its other points in boxes, a vehicle on it") {
    const fs::path survey = kReal / "hexbin-crop.las";  // UTM metres, class 1 and 2
    sim::SceneFromCloudOptions o;
    o.vehicle.mesh = kVan;
    o.vehicle.seed = 3;
    const sim::SceneFromCloud s = sim::buildSceneFromCloud(survey, o, noProgress);
    CHECK(s.ground_from == "class 2");
    CHECK(s.points == 38367);
    CHECK(s.ground_points == 35318);
    CHECK(s.units.metres());
    // The local frame lies near (0, 0): the offset is the survey's centre.
    CHECK(std::abs(s.offset_m.x - 393923.0) < 200.0);
    CHECK(std::abs(s.offset_m.y - 3689173.0) < 200.0);

    const std::vector<LocalPoint> points = localPoints(survey, s);
    std::vector<double> residuals;
    std::size_t outside = 0;
    for (const LocalPoint& lp : points) {
        if (lp.ground) {
            residuals.push_back(std::abs(lp.p.z - s.terrain.heightAt(lp.p.x, lp.p.y)));
            continue;
        }
        const std::array<std::int32_t, 3> key{std::int32_t(std::floor(lp.p.x / s.voxel_m)),
                                              std::int32_t(std::floor(lp.p.y / s.voxel_m)),
                                              std::int32_t(std::floor(lp.p.z / s.voxel_m))};
        outside += !std::binary_search(s.boxes.begin(), s.boxes.end(), key);
    }
    CHECK(s.dropped_high + s.dropped_low == 0);
    CHECK(outside == 0);  // every point that is not ground lies in a box
    CHECK(s.boxes.size() > 100);
    std::nth_element(residuals.begin(), residuals.begin() + std::ptrdiff_t(residuals.size() / 2), residuals.end());
    const double median = residuals[residuals.size() / 2];
    MESSAGE("median |z - terrain| of the class-2 points: " << median << " m, cell " << s.terrain.cell_m << " m");
    CHECK(median < 0.15);

    // The folder: its scene loads, the vehicle's lowest corners touch the ground mesh.
    Scratch scratch;
    const fs::path dir = scratch.dir / "scene";
    sim::writeSceneFolder(dir, s, o);
    const core::Scene scene = io::loadScene(dir / "scene.json");
    REQUIRE(s.vehicle);
    double lowest_gap = 1e9, highest_sink = 0;
    core::Bounds target;
    for (const core::Mesh& m : scene.meshes) {
        if (m.role != core::Role::Target) continue;
        for (const glm::vec3& v : m.vertices) {
            target.extend(glm::dvec3(v));
            const std::optional<double> g = core::groundHeightAt(scene, v.x, v.y);
            REQUIRE(g);
            lowest_gap = std::min(lowest_gap, v.z - *g);
            highest_sink = std::max(highest_sink, *g - v.z);
        }
    }
    MESSAGE("vehicle: slope " << s.vehicle->slope << ", lowest gap to the ground " << lowest_gap << " m");
    CHECK(std::abs(lowest_gap) <= s.vehicle->roughness_m + 0.05);  // it touches the ground, neither floats nor sinks
    CHECK(highest_sink <= o.vehicle.max_roughness_m + 0.05);
    CHECK(core::targetWarnings(core::summarize(scene)).empty());

    // The generator flies the paper's orbit over it (fewer, smaller views): the target's
    // points are labelled target and lie on the vehicle.
    sim::GenerateOptions g;
    g.orbit.views = 6;
    g.orbit.xres = g.orbit.yres = 48;
    g.threads = 1;
    const core::PointCloud cloud = sim::generateCloud(scene, g);
    std::size_t on_target = 0, off_box = 0, ground = 0;
    for (const core::CloudPoint& p : cloud.points) {
        ground += p.label == core::Role::Ground;
        if (p.label != core::Role::Target) continue;
        ++on_target;
        const glm::dvec3 q(p.position);
        off_box += glm::any(glm::lessThan(q, target.lo - 0.01)) || glm::any(glm::greaterThan(q, target.hi + 0.01));
    }
    MESSAGE("generated: " << cloud.points.size() << " points, " << on_target << " target, " << ground << " ground");
    CHECK(on_target > 20);
    CHECK(off_box == 0);
    CHECK(ground > cloud.points.size() / 4);
}

TEST_CASE("scene_from_cloud: a survey in US survey feet is converted to metres") {
    const fs::path survey = kReal / "4_6_crop.las";
    sim::SceneFromCloudOptions o;
    const sim::SceneFromCloud s = sim::buildSceneFromCloud(survey, o, noProgress);
    CHECK_FALSE(s.units.metres());
    CHECK(s.ground_from == "class 2");
    // The terrain's extent in metres is the feet extent times 0.3048006.
    io::CloudReader reader(survey);
    std::vector<core::CloudPoint> chunk;
    float lo = 1e30f, hi = -1e30f;
    while (reader.nextChunk(chunk)) {
        for (const core::CloudPoint& p : chunk) lo = std::min(lo, p.position.x), hi = std::max(hi, p.position.x);
        chunk.clear();
    }
    const double extent_m = double(hi - lo) * 1200.0 / 3937.0;
    CHECK(std::abs((s.terrain.nx - 1) * s.terrain.cell_m - extent_m) <= s.terrain.cell_m);
    const std::vector<LocalPoint> points = localPoints(survey, s);
    std::vector<double> residuals;
    for (const LocalPoint& lp : points)
        if (lp.ground) residuals.push_back(std::abs(lp.p.z - s.terrain.heightAt(lp.p.x, lp.p.y)));
    std::nth_element(residuals.begin(), residuals.begin() + std::ptrdiff_t(residuals.size() / 2), residuals.end());
    CHECK(residuals[residuals.size() / 2] < 0.15);
}

TEST_CASE("scene_from_cloud: the ground filter where the file has no ground class, or when asked") {
    const fs::path survey =
        fs::path(test_support::isprsDir()) / "samp24.las";  // ISPRS reference: bare earth is class 2
    sim::SceneFromCloudOptions o;
    o.ground_source = sim::SceneGroundSource::Filter;
    const sim::SceneFromCloud f = sim::buildSceneFromCloud(survey, o, noProgress);
    CHECK(f.ground_from.starts_with("smrf"));
    o.ground_source = sim::SceneGroundSource::Auto;
    const sim::SceneFromCloud c = sim::buildSceneFromCloud(survey, o, noProgress);
    CHECK(c.ground_from == "class 2");
    // The filter finds about the reference's ground.
    CHECK(std::abs(double(f.ground_points) - double(c.ground_points)) < 0.1 * double(c.ground_points));
}

TEST_CASE("scene_from_cloud: refusals in one line: no points, degrees, too many boxes, --coarsen") {
    Scratch scratch;
    sim::SceneFromCloudOptions o;

    core::PointCloud empty;
    empty.fields = core::CloudFields{};
    const fs::path none = scratch.dir / "none.las";
    io::writeCloud(none, empty, io::CloudFormat::Las);
    CHECK(errorOf(none, o) ==
          "scene from-cloud: " + none.string() + ": the cloud has no points; allowed a survey with points");

    // hexbin-crop.las with its WKT record's UTM 42N overwritten by WGS 84 (x, y in degrees).
    std::ifstream in(kReal / "hexbin-crop.las", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = bytes.find("PROJCS[\"WGS 84 / UTM zone 42N\"");
    REQUIRE(at != std::string::npos);
    const std::size_t end = bytes.find('\0', at);
    const std::string wkt =
        "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
        "UNIT[\"degree\",0.0174532925199433,AUTHORITY[\"EPSG\",\"9122\"]],AUTHORITY[\"EPSG\",\"4326\"]]";
    REQUIRE(end - at > wkt.size());
    bytes.replace(at, end - at, wkt + std::string(end - at - wkt.size(), '\0'));
    const fs::path degrees = scratch.dir / "degrees.las";
    std::ofstream(degrees, std::ios::binary) << bytes;
    const std::string geo = errorOf(degrees, o);
    CHECK(geo.starts_with("scene from-cloud: " + degrees.string() + ": its CRS 'WGS 84' (EPSG:4326) is geographic"));
    CHECK(geo.find('\n') == std::string::npos);

    const fs::path survey = kReal / "hexbin-crop.las";
    o.max_boxes = 10;
    CHECK(errorOf(survey, o) == "scene from-cloud: " + survey.string() +
                                    ": more than 10 boxes at --voxel-m 0.5; allowed at most --max-boxes 10: raise "
                                    "--voxel-m or --max-boxes, or give --coarsen");
    o.coarsen = true;
    const sim::SceneFromCloud s = sim::buildSceneFromCloud(survey, o, noProgress);
    CHECK(s.boxes.size() <= 10);
    CHECK(s.voxel_m > 0.5);
    CHECK(s.voxel_requested_m == 0.5);

    sim::SceneFromCloudOptions bad;
    bad.voxel_m = 0;
    CHECK_THROWS_WITH_AS(sim::validate(bad), "scene from-cloud: --voxel-m is 0; allowed (0.05, 100] metres",
                         core::Error);
    // A vehicle asked where the ground is too steep for it.
    sim::SceneFromCloudOptions steep;
    steep.vehicle.mesh = kVan;
    steep.vehicle.max_slope = 0.0;
    CHECK(errorOf(survey, steep).find("no flat, free spot") != std::string::npos);
}
