// tests/sim/ground_file_tiles_test.cpp: `ladarvr ground` tile by tile (sim/ground_tiles.hpp):
// a survey classified in small tiles with a buffer gives each point the class of one
// untiled run (every point of the 15 ISPRS samples and a survey in feet in 60 m tiles,
// and in 30 m tiles, narrower than the buffer, floorOf); two files merged into one
// output and the same two classified each as a tile with the other as its buffer agree;
// a sample or a survey in feet cut into a folder of 3 x 3 files, each classified with
// the others as its buffer, or classified together in forced tiles, gets the classes of
// one run over the uncut file (sample 53's files too, whose empty cells make one hole
// across the survey); tiles fitted two at a time write the same bytes as one at a time;
// a survey too wide for one raster runs in tiles; --whiten's colours.
#include <test_paths.hpp>
#include <sim/ground_tiles.hpp>

#include <core/error.hpp>
#include <core/jet.hpp>
#include <io/cloud_io.hpp>
#include <sim/ground_units.hpp>

#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Scratch {
    fs::path dir;
    explicit Scratch(const std::string& name)
        : dir(fs::temp_directory_path() / ("ladarvr-ground-tiles-" + name + "-" + std::to_string(::getpid()))) {
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~Scratch() { fs::remove_all(dir); }
};

sim::GroundTiling tiling(double tile_m, const sim::GroundFileOptions& o, const fs::path& dir, int jobs = 1) {
    sim::GroundTiling t;
    t.tile_m = tile_m;
    t.buffer_m = sim::tileBuffer(o);
    t.jobs = jobs;
    t.max_cells = std::size_t(1) << 24;
    t.scratch_dir = dir;
    return t;
}

void none(std::size_t) {}

// The share of points whose ground label is the same in two files of the same points.
double agreement(const fs::path& a, const fs::path& b) {
    const core::PointCloud x = io::readCloud(a), y = io::readCloud(b);
    REQUIRE(x.points.size() == y.points.size());
    std::size_t same = 0;
    for (std::size_t i = 0; i < x.points.size(); ++i)
        same += (x.points[i].label == core::Role::Ground) == (y.points[i].label == core::Role::Ground);
    return double(same) / double(x.points.size());
}

std::string bytesOf(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The share of `in`'s points whose class in tiles `tile_m` metres wide (its buffer
// tileBuffer's) is the class of one untiled run.
double tiledAgreement(const fs::path& in, double tile_m, const fs::path& dir) {
    const sim::CoordinateUnits units = sim::readCoordinateUnits(in, "test");
    const sim::GroundFileOptions o = sim::inUnits(sim::GroundFileOptions{}, units);
    const sim::GroundFileStats one =
        sim::classifyGroundFile(in, dir / "one.las", o, std::size_t(1) << 24, {}, {}, none);
    const sim::GroundFileStats tiled =
        sim::classifyGroundTiled({in}, dir / "tiled.las", o, tiling(tile_m / units.horizontal_m, o, dir), {}, {}, none);
    CHECK(tiled.tiles >= 4);
    CHECK(tiled.points == one.points);
    const double share = agreement(dir / "one.las", dir / "tiled.las");
    MESSAGE(in.filename().string() << " in " << tile_m << " m tiles: " << tiled.tiles << " tiles, " << 100.0 * share
                                   << " % agree");
    return share;
}

// The agreement each sample keeps: every point. Without a tile's raster spanning the
// survey's cells within its buffer (TerrainFit::setExtent) and the hole filling's fixed
// number of sweeps (SmrfOptions::fill_sweeps), a cell or two of samples 51, 52, 53 and
// 61 flipped an opening's slope test by a few millimetres; without a tile fitted again
// over a raised-segment patch its raster cuts (TerrainFit::testedPatches), sample 42's
// station roofs, one patch 175 m x 203 m, were raised in tiles (99.56 %).
double floorOf(const std::string&) { return 1.0; }

}  // namespace

namespace {

// Each named input of the ISPRS folder (or "real/..." beside it) in tiles `tile_m` wide
// keeps every point's class. The inputs are spread over several test cases so that each
// runs in a few minutes under the sanitizers: the sparse samples fit each tile twice
// (their holes cross every tile's cut edge).
void checkTiles(const char* scratch, double tile_m, std::initializer_list<const char*> names) {
    const Scratch s(scratch);
    const fs::path isprs = test_support::isprsDir();
    for (const char* name : names) {
        CAPTURE(name);
        const fs::path in = std::string_view(name).starts_with("real/") ? isprs.parent_path() / name : isprs / name;
        CHECK(tiledAgreement(in, tile_m, s.dir) >= floorOf(in.filename().string()));
    }
}

}  // namespace

// Tiles of 60 m (a sample is 200-400 m wide): a few dozen, most points near an edge.
TEST_CASE("ground tiles: 60 m tiles with a buffer give samples 11-24 the untiled run's classes") {
    checkTiles("agree_1x2x", 60.0,
               {"samp11.laz", "samp12.laz", "samp21.laz", "samp22.laz", "samp23.laz", "samp24.laz"});
}

TEST_CASE(
    "ground tiles: 60 m tiles with a buffer give samples 31-42, 71 and a survey in feet the untiled run's classes") {
    checkTiles("agree_3x4x", 60.0, {"samp31.laz", "samp41.laz", "samp42.laz", "samp71.laz", "real/4_6_crop.las"});
}

TEST_CASE("ground tiles: 60 m tiles with a buffer give samples 51 and 54 the untiled run's classes") {
    checkTiles("agree_51", 60.0, {"samp51.laz", "samp54.laz"});
}

TEST_CASE("ground tiles: 60 m tiles with a buffer give sample 52 the untiled run's classes") {
    checkTiles("agree_52", 60.0, {"samp52.laz"});
}

TEST_CASE("ground tiles: 60 m tiles with a buffer give sample 53 the untiled run's classes") {
    checkTiles("agree_53", 60.0, {"samp53.laz"});
}

TEST_CASE("ground tiles: 60 m tiles with a buffer give sample 61 the untiled run's classes") {
    checkTiles("agree_61", 60.0, {"samp61.laz"});
}

// 30 m tiles under a 76 m buffer: each point is in the buffer of tiles three away.
TEST_CASE("ground tiles: tiles narrower than their buffer take it from every tile within it (sample 42)") {
    checkTiles("narrow1", 30.0, {"samp42.laz"});
}

TEST_CASE("ground tiles: tiles narrower than their buffer take it from every tile within it (sample 51)") {
    checkTiles("narrow5", 30.0, {"samp51.laz"});
}

TEST_CASE("ground tiles: tiles narrower than their buffer take it from every tile within it (sample 52)") {
    checkTiles("narrow2", 30.0, {"samp52.laz"});
}

TEST_CASE("ground tiles: tiles narrower than their buffer take it from every tile within it (sample 53)") {
    checkTiles("narrow3", 30.0, {"samp53.laz"});
}

TEST_CASE("ground tiles: tiles narrower than their buffer take it from every tile within it (sample 61)") {
    checkTiles("narrow4", 30.0, {"samp61.laz"});
}

TEST_CASE(
    "ground tiles: two files merged and the two classified each with the other as buffer agree, surveys split by CRS "
    "and unit") {
    const Scratch s("merge");
    const core::PointCloud cloud = io::readCloud(fs::path(test_support::isprsDir()) / "samp54.las");
    // The sample cut in two at its middle x, each half in a file of its own.
    const core::Bounds b = cloud.bounds();
    const float mid = float(0.5 * (b.lo.x + b.hi.x));
    core::PointCloud west = cloud, east = cloud;
    west.points.clear();
    east.points.clear();
    west.foreign.reset();
    east.foreign.reset();
    for (const core::CloudPoint& p : cloud.points) (p.position.x < mid ? west : east).points.push_back(p);
    io::writeCloud(s.dir / "west.ply", west, io::CloudFormat::PlyBinary);
    io::writeCloud(s.dir / "east.ply", east, io::CloudFormat::PlyBinary);
    const std::vector<fs::path> inputs = {s.dir / "west.ply", s.dir / "east.ply"};
    CHECK_NOTHROW(sim::checkMergeable(inputs));
    const sim::GroundFileOptions o;
    const sim::GroundTiling t = tiling(1000.0, o, s.dir);
    sim::classifyGroundTiled(inputs, s.dir / "merged.ply", o, t, {}, {}, none);
    const std::vector<sim::GroundBox> boxes = {sim::readGroundBox(inputs[0]), sim::readGroundBox(inputs[1])};
    std::size_t measured = 0;
    sim::GroundTiling each = t;
    each.thickness_m = sim::surveyThickness(inputs, boxes, o, t, [&](std::size_t n) { measured += n; });
    CHECK(measured == cloud.points.size());
    for (std::size_t i = 0; i < 2; ++i)
        sim::classifyGroundNeighbours(inputs, boxes, i, s.dir / ("each" + std::to_string(i) + ".ply"), o, each, {}, {},
                                      none);
    const core::PointCloud merged = io::readCloud(s.dir / "merged.ply");
    const core::PointCloud each0 = io::readCloud(s.dir / "each0.ply"), each1 = io::readCloud(s.dir / "each1.ply");
    REQUIRE(merged.points.size() == each0.points.size() + each1.points.size());
    std::size_t same = 0, ground = 0;
    for (std::size_t i = 0; i < merged.points.size(); ++i) {
        const core::CloudPoint& p = i < each0.points.size() ? each0.points[i] : each1.points[i - each0.points.size()];
        same += merged.points[i].label == p.label;
        ground += p.label == core::Role::Ground;
    }
    CHECK(ground > 1000);
    CHECK(double(same) / double(merged.points.size()) >= 0.9999);
    // Without the buffer, each half's edge is fitted on its own and more points differ.
    sim::GroundTiling bare = t;
    bare.buffer_m = 0;
    sim::classifyGroundNeighbours(inputs, boxes, 0, s.dir / "bare.ply", o, bare, {}, {}, none);
    const core::PointCloud lone = io::readCloud(s.dir / "bare.ply");
    std::size_t lone_same = 0;
    for (std::size_t i = 0; i < lone.points.size(); ++i) lone_same += merged.points[i].label == lone.points[i].label;
    MESSAGE("merged vs each: " << same << " of " << merged.points.size() << " the same; without a buffer " << lone_same
                               << " of " << lone.points.size());
    CHECK(lone_same <= same);
    // Inputs of other fields cannot be merged into one output.
    core::PointCloud other = west;
    other.fields.intensity = !other.fields.intensity;
    io::writeCloud(s.dir / "other.ply", other, io::CloudFormat::PlyBinary);
    CHECK_THROWS_WITH_AS(sim::checkMergeable({inputs[0], s.dir / "other.ply"}),
                         doctest::Contains("have different point formats; allowed"), core::Error);
    // For one output each, fields may differ but a CRS or unit may not: those are surveys
    // of their own (real files in US survey feet and in UTM 42N), in the order of their
    // first input.
    const fs::path real = fs::path(test_support::isprsDir()).parent_path() / "real";
    const std::vector<std::vector<std::size_t>> surveys =
        sim::surveysOf({real / "4_6_crop.las", inputs[0], real / "hexbin-crop.las", s.dir / "other.ply", inputs[1]});
    CHECK(surveys == std::vector<std::vector<std::size_t>>{{0}, {1, 3, 4}, {2}});
}

namespace {

// A survey cut into 3 x 3 LAS files at its x and y terciles (each file's origin its own,
// near its middle, as a reader puts it): the files, their bounds, where each file's
// points came from in the survey, and the options in the survey's units.
struct CutSurvey {
    std::vector<fs::path> inputs;
    std::vector<sim::GroundBox> boxes;
    std::vector<std::vector<std::size_t>> from;
    std::size_t points = 0;
    sim::GroundFileOptions o;
};

CutSurvey cutIntoFiles(const fs::path& in, const fs::path& dir) {
    const core::PointCloud cloud = io::readCloud(in);
    CutSurvey cut;
    cut.points = cloud.points.size();
    cut.o = sim::inUnits(sim::GroundFileOptions{}, sim::readCoordinateUnits(in, "test"));
    const auto terciles = [&](int axis) {
        std::vector<float> v;
        for (const core::CloudPoint& p : cloud.points) v.push_back(p.position[axis]);
        std::sort(v.begin(), v.end());
        return std::pair{v[v.size() / 3], v[2 * v.size() / 3]};
    };
    const auto [x1, x2] = terciles(0);
    const auto [y1, y2] = terciles(1);
    std::vector<core::PointCloud> files(9, cloud);
    cut.from.resize(9);
    for (core::PointCloud& f : files) {
        f.points.clear();
        f.foreign.reset();
    }
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const glm::vec3 p = cloud.points[i].position;
        const std::size_t k = std::size_t((p.x >= x1) + (p.x >= x2)) * 3 + std::size_t((p.y >= y1) + (p.y >= y2));
        files[k].points.push_back(cloud.points[i]);
        cut.from[k].push_back(i);
    }
    const std::string name = in.stem().string();
    for (std::size_t k = 0; k < files.size(); ++k) {
        cut.inputs.push_back(dir / (name + "_t" + std::to_string(k) + ".las"));
        io::writeCloud(cut.inputs.back(), files[k], io::CloudFormat::Las);
        cut.boxes.push_back(sim::readGroundBox(cut.inputs.back()));
    }
    return cut;
}

// Each point's ground flag from one untiled run over the uncut survey `in`.
std::vector<bool> oneRun(const fs::path& in, const sim::GroundFileOptions& o, const fs::path& dir) {
    const fs::path out = dir / (in.stem().string() + "_one.las");
    sim::classifyGroundFile(in, out, o, std::size_t(1) << 24, {}, {}, none);
    std::vector<bool> ground;
    for (const core::CloudPoint& p : io::readCloud(out).points) ground.push_back(p.label == core::Role::Ground);
    return ground;
}

// The share of `in`'s points whose class, when the survey is cut into 3 x 3 files and
// each file is classified with the others as its buffer (a folder of tiles, `ground
// DIR/*.las --out-dir`), is the class of one run over the uncut survey.
double folderAgreement(const fs::path& in, const fs::path& dir) {
    const CutSurvey cut = cutIntoFiles(in, dir);
    const std::vector<bool> one = oneRun(in, cut.o, dir);
    REQUIRE(one.size() == cut.points);
    sim::GroundTiling t = tiling(1000.0, cut.o, dir);
    t.thickness_m = sim::surveyThickness(cut.inputs, cut.boxes, cut.o, t, none);
    std::size_t same = 0;
    for (std::size_t k = 0; k < cut.inputs.size(); ++k) {
        const fs::path out = dir / (in.stem().string() + "_out" + std::to_string(k) + ".las");
        sim::classifyGroundNeighbours(cut.inputs, cut.boxes, k, out, cut.o, t, {}, {}, none);
        const core::PointCloud got = io::readCloud(out);
        REQUIRE(got.points.size() == cut.from[k].size());
        for (std::size_t i = 0; i < got.points.size(); ++i)
            same += (got.points[i].label == core::Role::Ground) == one[cut.from[k][i]];
    }
    const double share = double(same) / double(cut.points);
    MESSAGE(in.filename().string() << " as a folder of 3 x 3 files: " << 100.0 * share << " % agree");
    return share;
}

// The share of `in`'s points whose class, when the survey is cut into 3 x 3 files and
// the files are classified together in forced tiles `tile_m` metres wide (`ground
// DIR/*.las --out ONE --tile-m`), is the class of one run over the uncut survey.
double forcedAgreement(const fs::path& in, double tile_m, const fs::path& dir) {
    const CutSurvey cut = cutIntoFiles(in, dir);
    const std::vector<bool> one = oneRun(in, cut.o, dir);
    REQUIRE(one.size() == cut.points);
    const double unit_m = sim::readCoordinateUnits(in, "test").horizontal_m;
    const fs::path out = dir / (in.stem().string() + "_forced.las");
    const sim::GroundFileStats st =
        sim::classifyGroundTiled(cut.inputs, out, cut.o, tiling(tile_m / unit_m, cut.o, dir), {}, {}, none);
    CHECK(st.tiles >= 4);
    const core::PointCloud got = io::readCloud(out);
    REQUIRE(got.points.size() == cut.points);
    std::size_t same = 0, at = 0;
    for (const std::vector<std::size_t>& from : cut.from)
        for (const std::size_t i : from) same += (got.points[at++].label == core::Role::Ground) == one[i];
    const double share = double(same) / double(cut.points);
    MESSAGE(in.filename().string() << " as 3 x 3 files in " << tile_m << " m tiles: " << 100.0 * share << " % agree");
    return share;
}

}  // namespace

// Without the raised-segment re-fit, sample 42's station roofs, cut by a file's buffer,
// were raised in some files (99.74 %); with each file's raster ending where its
// neighbours' bounds do rather than where the survey's do, a row of cells at sample 52's
// north edge made a patch's border longer and four points were called ground (99.98 %).
TEST_CASE("ground tiles: a folder of tile files gives each point the class of one run over the survey") {
    const Scratch s("folder");
    const fs::path isprs = test_support::isprsDir();
    for (const char* sample : {"samp42.laz", "samp52.laz"}) {
        CAPTURE(sample);
        CHECK(folderAgreement(isprs / sample, s.dir) == 1.0);
    }
}

// A survey in US survey feet: its 1 m cells are 3.28 feet, so with the raster's cells
// placed from each run's first input (whole feet) rather than on one lattice of the
// survey's coordinates (groundFrame), a folder cut from the file had its cells a fraction
// of a cell off the uncut file's (3 points differed, 99.987 %).
TEST_CASE("ground tiles: a folder of tile files in feet gives each point the class of one run over the uncut file") {
    const Scratch s("folder-feet");
    CHECK(folderAgreement(fs::path(test_support::isprsDir()).parent_path() / "real" / "4_6_crop.las", s.dir) == 1.0);
}

// Forced tiles over a survey's files: with a tile's raster ending where the inputs that
// reach its buffer end rather than where the survey does, sample 52's north edge (set by
// a file beyond the buffer of the tiles near it) kept four points' ground (99.98 %); in
// feet, off the survey's cell lattice, points differed as in the folder.
TEST_CASE("ground tiles: forced tiles over a survey's files give each point the class of one run over it") {
    const Scratch s("forced-files");
    const fs::path isprs = test_support::isprsDir();
    CHECK(forcedAgreement(isprs / "samp52.laz", 60.0, s.dir) == 1.0);
    CHECK(forcedAgreement(isprs.parent_path() / "real" / "4_6_crop.las", 60.0, s.dir) == 1.0);
}

// Sample 53's returns lie in strips about 2 m apart, so its empty cells join into one
// hole across the survey, which the fill's fixed sweeps do not settle: a tile's filled
// heights hang on where its raster cuts that hole. Over the sample's files the tiles lie
// elsewhere than over the uncut sample, and with the 76 m buffer alone 7 points near its
// east edge differed (99.980 %); a tile whose raster a hole crosses from a cut edge into
// its square is fitted again with its buffer doubled.
TEST_CASE("ground tiles: forced tiles over sample 53's files, one hole across the survey, agree with one run") {
    const Scratch s("forced-hole");
    CHECK(forcedAgreement(fs::path(test_support::isprsDir()) / "samp53.laz", 60.0, s.dir) == 1.0);
}

TEST_CASE("ground tiles: tiles fitted two at a time write the bytes of one at a time") {
    const Scratch s("jobs");
    const fs::path in = fs::path(test_support::isprsDir()) / "samp11.laz";
    const sim::GroundFileOptions o;
    sim::classifyGroundTiled({in}, s.dir / "one.laz", o, tiling(80.0, o, s.dir, 1), {}, {}, none);
    sim::classifyGroundTiled({in}, s.dir / "two.laz", o, tiling(80.0, o, s.dir, 2), {}, {}, none);
    const std::string one = bytesOf(s.dir / "one.laz");
    CHECK(one.size() > 1000);
    CHECK(one == bytesOf(s.dir / "two.laz"));
}

TEST_CASE("ground tiles: a survey too wide for one raster is classified in tiles") {
    const Scratch s("wide");
    // Two 40 m x 40 m patches of flat ground with a box on each, 5 km apart on the
    // diagonal: one raster of 1 m cells spans 25 M cells, over the filter's 16.8 M.
    core::PointCloud cloud;
    cloud.fields = core::CloudFields{};
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
    std::size_t ground = 0;
    for (const float at : {0.0f, 5000.0f})
        for (int j = 0; j < 80; ++j)
            for (int i = 0; i < 80; ++i) {
                core::CloudPoint p;
                p.position = {at + 0.5f * float(i) + jitter(rng), at + 0.5f * float(j) + jitter(rng), 0.0f};
                const bool box = i >= 30 && i < 50 && j >= 30 && j < 50;
                if (box) p.position.z = 5.0f;
                ground += !box;
                cloud.points.push_back(p);
            }
    io::writeCloud(s.dir / "wide.ply", cloud, io::CloudFormat::PlyBinary);
    const sim::GroundFileOptions o;
    CHECK_THROWS_WITH_AS(
        sim::classifyGroundFile(s.dir / "wide.ply", s.dir / "one.ply", o, std::size_t(1) << 24, {}, {}, none),
        doctest::Contains("allowed at most 16777216"), core::Error);
    const sim::GroundFileStats st =
        sim::classifyGroundTiled({s.dir / "wide.ply"}, s.dir / "tiled.ply", o, tiling(2000.0, o, s.dir), {}, {}, none);
    CHECK(st.tiles >= 2);  // the patches' tiles (a patch may straddle a tile's edge)
    CHECK(st.points == cloud.points.size());
    CHECK(st.ground_points == ground);
}

TEST_CASE("ground tiles: --whiten writes white ground and the jet map by height above it") {
    const Scratch s("whiten");
    const fs::path in = fs::path(test_support::isprsDir()) / "samp54.las";
    sim::GroundFileOptions o;
    o.whiten = true;
    std::size_t progressed = 0;
    const sim::GroundFileStats st = sim::classifyGroundFile(in, s.dir / "white.las", o, std::size_t(1) << 24, {}, {},
                                                            [&](std::size_t n) { progressed += n; });
    const core::PointCloud out = io::readCloud(s.dir / "white.las");
    REQUIRE(out.points.size() == st.points);
    CHECK(progressed == 3 * st.points);
    CHECK(out.fields.rgb);
    CHECK(st.colour_top_m > 5.0f);
    const std::vector<std::uint32_t> jet = core::jetTable(64);
    std::size_t white = 0, red = 0, blue = 0;
    for (const core::CloudPoint& p : out.points) {
        if (p.label == core::Role::Ground) {
            CHECK(p.rgb == core::kWhite);
            white += 1;
            continue;
        }
        const float h = std::max(p.height_above_ground_m, 0.0f);
        CHECK(p.rgb == jet[core::jetIndex(h, 0.0f, st.colour_top_m, 64)]);
        red += p.rgb == jet[core::jetIndex(0.0f, 0.0f, st.colour_top_m, 64)];
        blue += p.rgb == jet[core::jetIndex(st.colour_top_m, 0.0f, st.colour_top_m, 64)];
    }
    CHECK(white == st.ground_points);
    CHECK(red > 0);
    CHECK(blue > 0);
    // Tiled, the same colours (one colour map over the whole output).
    sim::classifyGroundTiled({in}, s.dir / "tiled.las", o, tiling(1000.0, o, s.dir), {}, {}, none);
    const core::PointCloud tiled = io::readCloud(s.dir / "tiled.las");
    REQUIRE(tiled.points.size() == out.points.size());
    std::size_t same = 0;
    for (std::size_t i = 0; i < out.points.size(); ++i) same += tiled.points[i].rgb == out.points[i].rgb;
    CHECK(same == out.points.size());
    // Without --whiten the colours are the file's.
    sim::classifyGroundFile(in, s.dir / "plain.las", sim::GroundFileOptions{}, std::size_t(1) << 24, {}, {}, none);
    CHECK(!io::readCloud(s.dir / "plain.las").fields.rgb);
}

TEST_CASE("ground tiles: --whiten's colour map ends at the survey's objects, not at a few stray returns far above") {
    // Sample 54 with returns 400-500 m above it (birds, clouds): up to a thousandth of its
    // points they are left out of the colour map's range, one run or tiled; more, and they
    // are its top, as before.
    const Scratch s("strays");
    const fs::path in = fs::path(test_support::isprsDir()) / "samp54.las";
    sim::GroundFileOptions o;
    o.whiten = true;
    const sim::GroundFileStats clean =
        sim::classifyGroundFile(in, s.dir / "clean.ply", o, std::size_t(1) << 24, {}, {}, none);
    const core::PointCloud survey = io::readCloud(in);
    const std::size_t most = survey.points.size() / 1000;
    REQUIRE(most >= 4);
    const auto withStrays = [&](std::size_t n, const fs::path& path) {
        core::PointCloud c = survey;
        for (std::size_t k = 0; k < n; ++k) {
            core::CloudPoint p = survey.points[k * 97];
            p.position.z += 400.0f + 100.0f * float(k) / float(n);
            c.points.push_back(p);
        }
        io::writeCloud(path, c, io::CloudFormat::PlyBinary);
    };
    withStrays(most, s.dir / "few.ply");
    const sim::GroundFileStats few =
        sim::classifyGroundFile(s.dir / "few.ply", s.dir / "few_out.ply", o, std::size_t(1) << 24, {}, {}, none);
    CHECK(clean.colour_top_m > 5.0f);
    CHECK(clean.colour_top_m < 50.0f);
    CHECK(few.colour_top_m == clean.colour_top_m);
    const sim::GroundFileStats few_tiled = sim::classifyGroundTiled({s.dir / "few.ply"}, s.dir / "few_tiled.ply", o,
                                                                    tiling(100.0, o, s.dir), {}, {}, none);
    CHECK(few_tiled.tiles >= 2);  // each tile's heights gathered apart, then merged
    CHECK(few_tiled.colour_top_m == clean.colour_top_m);
    // The strays themselves take the map's top colour (blue).
    const core::PointCloud out = io::readCloud(s.dir / "few_out.ply");
    const std::vector<std::uint32_t> jet = core::jetTable(64);
    for (std::size_t k = survey.points.size(); k < out.points.size(); ++k)
        CHECK(out.points[k].rgb == jet[core::jetIndex(clean.colour_top_m, 0.0f, clean.colour_top_m, 64)]);
    withStrays(most + 1, s.dir / "many.ply");
    const sim::GroundFileStats many =
        sim::classifyGroundFile(s.dir / "many.ply", s.dir / "many_out.ply", o, std::size_t(1) << 24, {}, {}, none);
    CHECK(many.colour_top_m > 350.0f);
}
