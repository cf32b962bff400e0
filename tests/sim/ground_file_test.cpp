// tests/sim/ground_file_test.cpp: the ground of a file we did not generate
// (sim/ground_file.hpp): low outliers left out of the terrain (a known plane under a
// cluster of returns 20 m low), the file path giving the labels the in-memory filter
// gives, and the accuracy of `ladarvr ground`'s default on the ISPRS reference samples
// (tests/data/isprs: two published LAS files, and all 15 as LAZ) kept under a floor just
// above what it reaches.
#include <test_paths.hpp>
#include <sim/ground_file.hpp>

#include "ground_label.hpp"

#include <core/error.hpp>
#include <io/cloud_io.hpp>

#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

// A flat 60 m x 60 m ground at z = 0, 4 returns a square metre (jittered grid), with
// every 40th return in a 20 m x 20 m patch 20 m low (multipath: about one 1 m cell in
// ten there holds one, as in ISPRS sample 41). label: Ground on the plane, Environment
// for the low returns.
std::vector<core::CloudPoint> planeWithLowCluster() {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
    std::vector<core::CloudPoint> points;
    int k = 0;
    for (int j = 0; j < 120; ++j)
        for (int i = 0; i < 120; ++i) {
            core::CloudPoint p;
            p.position = {0.5f * float(i) + jitter(rng), 0.5f * float(j) + jitter(rng), 0.02f * jitter(rng)};
            p.label = core::Role::Ground;
            const bool patch = p.position.x > 20 && p.position.x < 40 && p.position.y > 20 && p.position.y < 40;
            if (patch && ++k % 40 == 0) {
                p.position.z = -20.0f + jitter(rng);
                p.label = core::Role::Environment;
            }
            points.push_back(p);
        }
    return points;
}

// Points whose label the filter got wrong.
std::size_t wrong(const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& ground) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < points.size(); ++i) n += (points[i].label == core::Role::Ground) != (ground[i] != 0);
    return n;
}

}  // namespace

TEST_CASE("ground file: low outliers are left out of the terrain, so the ground around them stays ground") {
    const std::vector<core::CloudPoint> points = planeWithLowCluster();
    for (const sim::GroundMethod method : {sim::GroundMethod::Smrf, sim::GroundMethod::Csf}) {
        CAPTURE(sim::groundMethodName(method));
        sim::GroundFileOptions o;
        o.method = method;
        CHECK(o.smrf.low_outlier_m == sim::kSurveyLowOutlier_m);
        CHECK(o.csf.low_outlier_m == sim::kSurveyLowOutlier_m);
        sim::validate(o);
        CHECK(wrong(points, sim::classifyGround(points, o)) == 0);
        // Without it the terrain dips into the pits and the plane's points over them
        // are called objects.
        o.smrf.low_outlier_m = o.csf.low_outlier_m = 0;
        CHECK(wrong(points, sim::classifyGround(points, o)) > 40);
    }
}

TEST_CASE(
    "ground file: a discrete-return cloud's earlier returns are never ground, first and last echo sets keep them") {
    // The plane's points, every 10th one made the first of two returns (a pulse that
    // also hit something below it in a discrete-return survey), the rest single returns.
    std::vector<core::CloudPoint> points = planeWithLowCluster();
    std::size_t marked = 0;
    for (std::size_t i = 0; i < points.size(); i += 10) {
        if (points[i].label != core::Role::Ground) continue;
        points[i].return_number = 1;
        points[i].returns = 2;
        ++marked;
    }
    sim::ReturnCounts counts;
    counts.add(points);
    CHECK(counts.not_last == marked);
    CHECK(counts.single == points.size() - marked);
    CHECK(counts.discrete());
    sim::GroundFileOptions all;
    all.returns = sim::GroundReturns::All;
    const std::vector<std::uint8_t> every = sim::classifyGround(points, all);
    CHECK(wrong(points, every) == 0);  // the fit does not look at the returns
    const std::vector<std::uint8_t> last = sim::classifyGround(points, sim::GroundFileOptions{});
    std::size_t dropped = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (sim::notLastReturn(points[i]))
            dropped += every[i] && !last[i];
        else
            CHECK(every[i] == last[i]);
    }
    CHECK(dropped == marked);
    // A return number of 0 (not recorded) or above the count is taken as last.
    core::CloudPoint odd;
    odd.return_number = 0;
    odd.returns = 3;
    CHECK(!sim::notLastReturn(odd));
    odd.return_number = 4;
    CHECK(!sim::notLastReturn(odd));

    // Every pulse stored as a first and a last echo (no single return): auto keeps every
    // return the fit calls ground; last, asked for, drops the first echoes.
    for (std::size_t i = 0; i < points.size(); ++i) {
        points[i].returns = 2;
        points[i].return_number = std::uint8_t(1 + i % 2);
    }
    counts = {};
    counts.add(points);
    CHECK(!counts.discrete());
    CHECK(!sim::lastReturnsOnly(sim::GroundFileOptions{}, counts));
    CHECK(sim::classifyGround(points, sim::GroundFileOptions{}) == every);
    sim::GroundFileOptions last_only;
    last_only.returns = sim::GroundReturns::Last;
    CHECK(sim::lastReturnsOnly(last_only, counts));
    const std::vector<std::uint8_t> halved = sim::classifyGround(points, last_only);
    for (std::size_t i = 0; i < points.size(); ++i) CHECK(halved[i] == (every[i] && i % 2 == 1));

    CHECK(sim::parseGroundReturns("last", "--returns") == sim::GroundReturns::Last);
    CHECK_THROWS_WITH_AS(sim::parseGroundReturns("first", "ground: --returns"),
                         "ground: --returns first: allowed auto, last, all", core::Error);
}

TEST_CASE("ground file: the file's returns decide as the in-memory filter's, whether read by chunk or by COPC node") {
    const fs::path dir = fs::temp_directory_path() / ("ladarvr-ground-returns-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    core::PointCloud cloud;
    cloud.points = planeWithLowCluster();
    for (std::size_t i = 0; i < cloud.points.size(); i += 7) {
        cloud.points[i].return_number = 1;
        cloud.points[i].returns = 3;
    }
    // Whole millimetres, which the files hold exactly: a point is found again by them.
    for (core::CloudPoint& p : cloud.points) p.position = glm::round(p.position * 1000.0f) / 1000.0f;
    cloud.fields.returns = true;
    const sim::GroundFileOptions o;
    const std::vector<std::uint8_t> expected = sim::classifyGround(cloud.points, o);
    for (const char* name : {"in.las", "in.copc.laz"}) {
        CAPTURE(name);
        const fs::path in = dir / name;
        io::writeCloud(in, cloud, io::formatForPath(in, "test"));
        const fs::path out = dir / "out.las";
        const sim::GroundFileStats st =
            sim::classifyGroundFile(in, out, o, std::size_t(1) << 20, {}, {}, [](std::size_t) {});
        CHECK(st.last_returns_only);
        const core::PointCloud written = io::readCloud(out);
        REQUIRE(written.points.size() == cloud.points.size());
        // The COPC writer orders the points by node: matched by position.
        std::vector<std::pair<std::pair<long, long>, bool>> got, want;
        std::size_t not_last = 0;
        for (std::size_t i = 0; i < cloud.points.size(); ++i) {
            const glm::vec3 a = glm::vec3(glm::dvec3(written.points[i].position) + written.origin - cloud.origin);
            got.push_back({{std::lround(a.x * 1000.0f), std::lround(a.y * 1000.0f)},
                           written.points[i].label == core::Role::Ground});
            want.push_back(
                {{std::lround(cloud.points[i].position.x * 1000.0f), std::lround(cloud.points[i].position.y * 1000.0f)},
                 expected[i] != 0});
            not_last += sim::notLastReturn(written.points[i]) && written.points[i].label != core::Role::Ground;
        }
        std::sort(got.begin(), got.end());
        std::sort(want.begin(), want.end());
        CHECK(got == want);
        CHECK(st.not_last_points > 0);
        CHECK(st.not_last_points <= not_last);
        fs::remove(out);
    }
    fs::remove_all(dir);
}

TEST_CASE("ground file: the generator's filters keep every return (low_outlier_m is 0 unless asked)") {
    CHECK(sim::SmrfOptions{}.low_outlier_m == 0.0);
    CHECK(sim::CsfOptions{}.low_outlier_m == 0.0);
    sim::GroundFileOptions o;
    o.smrf.low_outlier_m = -1;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("--low-outlier-m"), core::Error);
    o = sim::GroundFileOptions{};
    o.method = sim::GroundMethod::Ransac;
    CHECK_THROWS_WITH_AS(sim::validate(o), doctest::Contains("allowed smrf, csf"), core::Error);
}

TEST_CASE("ground file: the file written carries the labels the in-memory filter gives, every point kept") {
    const fs::path dir = fs::temp_directory_path() / ("ladarvr-ground-file-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path in = fs::path(test_support::isprsDir()) / "samp54.las", out = dir / "out.laz";
    const core::PointCloud cloud = io::readCloud(in);
    const sim::GroundFileOptions o;
    const std::vector<std::uint8_t> expected = sim::classifyGround(cloud.points, o);
    std::size_t progressed = 0;
    const sim::GroundFileStats st =
        sim::classifyGroundFile(in, out, o, std::size_t(1) << 20, {}, {}, [&](std::size_t n) { progressed += n; });
    CHECK(progressed == 2 * cloud.points.size());
    const core::PointCloud written = io::readCloud(out);
    REQUIRE(written.points.size() == cloud.points.size());
    std::size_t ground = 0, same = 0;
    for (std::size_t i = 0; i < written.points.size(); ++i) {
        const bool g = written.points[i].label == core::Role::Ground;
        ground += g;
        same += g == (expected[i] != 0);
        CHECK(glm::length(glm::dvec3(written.points[i].position) + written.origin -
                          glm::dvec3(cloud.points[i].position) - cloud.origin) < 0.001);
    }
    CHECK(same == written.points.size());
    CHECK(st.points == written.points.size());
    CHECK(st.ground_points == ground);
    CHECK(st.was_ground == 3983);  // the sample's bare-earth labels
    CHECK(written.fields.height_above_ground);
    // A raster bound too small for the cloud is refused naming the cell option.
    CHECK_THROWS_WITH_AS(sim::classifyGroundFile(in, dir / "small.laz", o, 100, {}, {}, [](std::size_t) {}),
                         doctest::Contains("--smrf-cell-m"), core::Error);
    CHECK(!fs::exists(dir / "small.laz"));
    fs::remove_all(dir);
}

TEST_CASE("ground file: the default's mean total error on two ISPRS samples stays under its floor") {
    // Type I + type II errors over all points, in percent, averaged over the samples as
    // the ISPRS filter test scores them (`./ladarvr bench ground-isprs` scores all 15).
    // The misclassified counts are pinned as this build gives them: a change to SMRF's
    // openings that leaves the mean about where it was (sparse openings that let a
    // left-out cell carry an opened height to the next radius move 1 and 15 points here)
    // must come with a new bench ground-isprs run.
    double mean_total = 0;
    const std::pair<const char*, std::size_t> samples[] = {{"samp24.las", 310}, {"samp54.las", 313}};
    for (const auto& [name, pinned] : samples) {
        const core::PointCloud cloud = io::readCloud(fs::path(test_support::isprsDir()) / name);
        const std::vector<std::uint8_t> ground = sim::classifyGround(cloud.points, sim::GroundFileOptions{});
        const std::size_t misclassified = wrong(cloud.points, ground);
        const double total = 100.0 * double(misclassified) / double(cloud.points.size());
        MESSAGE(std::string(name) << ": total error " << total << " %");
        CHECK(misclassified == pinned);
        mean_total += total / 2.0;
    }
    CHECK(mean_total <= 3.95);  // 3.89 % (samp24 4.14 %, samp54 3.64 %)
}

TEST_CASE("ground file: the default's mean total error on all 15 ISPRS samples stays under its floor") {
    // What `./ladarvr bench ground-isprs` measures, from the LAZ copies: one parameter set
    // for every sample, the mean of the per-sample total errors.
    const char* const samples[] = {"samp11", "samp12", "samp21", "samp22", "samp23", "samp24", "samp31", "samp41",
                                   "samp42", "samp51", "samp52", "samp53", "samp54", "samp61", "samp71"};
    double mean_total = 0, worst = 0;
    for (const char* name : samples) {
        const core::PointCloud cloud = io::readCloud(fs::path(test_support::isprsDir()) / (std::string(name) + ".laz"));
        REQUIRE(!cloud.points.empty());
        const std::vector<std::uint8_t> ground = sim::classifyGround(cloud.points, sim::GroundFileOptions{});
        const double total = 100.0 * double(wrong(cloud.points, ground)) / double(cloud.points.size());
        mean_total += total / 15.0;
        worst = std::max(worst, total);
    }
    MESSAGE("mean total error " << mean_total << " %, worst sample " << worst << " %");
    CHECK(mean_total <= 3.70);  // 3.67 %
    CHECK(worst <= 8.5);        // samp11 8.16 %
}

TEST_CASE("ground labeller: mark_noise gives class 7 beyond the low-outlier gap, and nothing else") {
    // One foreign record per case: its class after apply(), as the writer gets it.
    const auto labelled = [](const sim::GroundFileOptions& o, std::uint8_t cls, bool ground, float height_m,
                             sim::GroundFileStats& st) {
        const sim::GroundLabeller labeller(o, sizeof(core::ForeignPoint), 0.0f, false);
        core::CloudPoint p;
        core::ForeignPoint f;
        f.classification = cls;
        unsigned char record[sizeof f];
        std::memcpy(record, &f, sizeof f);
        labeller.apply(p, record, ground, height_m, st);
        std::memcpy(&f, record, sizeof f);
        return f.classification;
    };
    sim::GroundFileOptions o;
    o.mark_noise = true;
    o.smrf.low_outlier_m = 6.0;
    sim::GroundFileStats st;
    CHECK(labelled(o, 5, false, -7.0f, st) == 7);  // far below: noise, whatever its class
    CHECK(labelled(o, 2, false, -7.0f, st) == 7);
    CHECK(labelled(o, 5, false, -5.0f, st) == 5);  // within the gap: kept
    CHECK(labelled(o, 2, false, -5.0f, st) == 1);
    CHECK(labelled(o, 1, true, -7.0f, st) == 2);  // ground stays ground
    CHECK(st.noise_points == 2);
    o.smrf.low_outlier_m = 0.0;  // low outliers kept by the fit: none is noise
    CHECK(labelled(o, 1, false, -70.0f, st) == 1);
    o.smrf.low_outlier_m = 6.0;
    o.method = sim::GroundMethod::Csf;  // CSF's own gap
    o.csf.low_outlier_m = 10.0;
    CHECK(labelled(o, 1, false, -7.0f, st) == 1);
    CHECK(labelled(o, 1, false, -11.0f, st) == 7);
    o.mark_noise = false;
    CHECK(labelled(o, 1, false, -11.0f, st) == 1);
    CHECK(st.noise_points == 3);
}
