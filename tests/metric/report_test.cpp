// Outputs of the metric: views.csv columns, summary.json fields, PNGs that decode.
#include <png_decode.hpp>
#include <scene_builders.hpp>

#include <metric/clouds.hpp>
#include <metric/report.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST_CASE("report: views.csv, summary.json and I1..I4 PNGs exist, parse and agree") {
    const core::Scene scene = test_support::boxBehindWall(2.0f, 6.0f, 0.5f);
    metric::Evaluator evaluator(metric::generateClouds(scene), &scene);
    metric::MetricOptions o;
    o.orbit.radius_m = 20.0;
    o.orbit.altitude_m = 3.0;
    o.orbit.views = 3;
    o.width = 96;
    o.height = 64;
    o.picture_view = 1;
    const metric::MetricResult r = evaluator.run(o);
    const fs::path dir = fs::temp_directory_path() / ("ladarvr_metric_report_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const auto written = metric::writeReport(r, dir / "out");
    CHECK(written.size() == 6);

    // CSV: the exact header, one row per view, world coordinates.
    std::istringstream csv(readFile(dir / "out" / "views.csv"));
    std::string line;
    std::getline(csv, line);
    CHECK(line ==
          "view,eye_x,eye_y,eye_z,look_x,look_y,look_z,up_x,up_y,up_z,vfov_deg,width,height,"
          "i1,i2,i3,i4,metric,visible,exact");
    int rows = 0;
    while (std::getline(csv, line)) {
        std::vector<std::string> cells;
        std::stringstream s(line);
        std::string cell;
        while (std::getline(s, cell, ',')) cells.push_back(cell);
        REQUIRE(cells.size() == 20);
        CHECK(std::stoi(cells[0]) == rows);
        const auto& v = r.views[std::size_t(rows)];
        CHECK(std::stod(cells[1]) == doctest::Approx(scene.origin.x + v.pose.eye.x).epsilon(1e-9));
        CHECK(std::stod(cells[3]) == doctest::Approx(scene.origin.z + 3.0).epsilon(1e-9));
        CHECK(std::stod(cells[4]) == doctest::Approx(scene.origin.x).epsilon(1e-9));  // cube centre
        CHECK(std::stoi(cells[11]) == 96);
        CHECK(std::stoi(cells[12]) == 64);
        CHECK(std::stoll(cells[13]) == v.i1);
        CHECK(std::stoll(cells[16]) == v.i4);
        CHECK(std::stod(cells[17]) == doctest::Approx(double(v.i4) / double(v.i1)).epsilon(1e-5));
        CHECK(!cells[19].empty());
        ++rows;
    }
    CHECK(rows == 3);

    const auto summary = nlohmann::json::parse(readFile(dir / "out" / "summary.json"));
    for (const char* key :
         {"views", "views_used", "metric_mean", "metric_min", "metric_max", "visible_mean", "exact_mean", "seconds"})
        CHECK_MESSAGE(summary.contains(key), key);
    CHECK(summary["views"] == 3);
    CHECK(summary["views_used"] == r.views_used);
    CHECK(summary["metric_mean"].get<double>() == doctest::Approx(r.metric_mean));
    CHECK(summary["metric_min"].get<double>() <= summary["metric_max"].get<double>());

    // PNGs: I1's white pixels (full frame) hold at least the counted |I1| of that view.
    for (const char* name : {"i1", "i2", "i3", "i4"}) {
        const auto png = test_support::decodePng(readFile(dir / "out" / ("view_1_" + std::string(name) + ".png")));
        CHECK(png.width == 96);
        CHECK(png.height == 64);
        CHECK(png.channels == 1);
        std::int64_t lit = 0;
        for (auto p : png.pixels) lit += p == 255;
        if (std::string(name) == "i1") CHECK(lit == r.views[1].i1);
        if (std::string(name) == "i3") CHECK(lit >= r.views[1].i1 / 2);
    }
    // No temporary files left behind.
    for (const auto& entry : fs::directory_iterator(dir / "out"))
        CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("report: an unwritable destination is a clear output error") {
    metric::MetricResult r;
    CHECK_THROWS_WITH_AS(metric::writeReport(r, "/proc/ladarvr-no-such-dir/x"), doctest::Contains("output: "),
                         core::Error);
}
