// Outputs of the metric: views.csv columns, summary.json fields, PNGs that decode.
#include <scene_builders.hpp>

#include <metric/clouds.hpp>
#include <metric/report.hpp>

#include <engine/error.hpp>

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

std::uint32_t be32(const std::string& s, std::size_t at) {
    return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}

std::uint32_t crc(const std::string& s, std::size_t begin, std::size_t end) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (std::size_t i = begin; i < end; ++i) {
        c ^= std::uint8_t(s[i]);
        for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    return c ^ 0xFFFFFFFFu;
}

/// Independent decoder for the stored-block greyscale PNGs: checks signature, CRCs,
/// zlib header and Adler-32; returns rows top-down.
std::vector<std::uint8_t> decodePng(const std::string& png, int& width, int& height) {
    REQUIRE(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
    std::size_t at = 8;
    std::string idat;
    bool ended = false;
    while (at + 12 <= png.size()) {
        const std::uint32_t length = be32(png, at);
        const std::string type = png.substr(at + 4, 4);
        REQUIRE(crc(png, at + 4, at + 8 + length) == be32(png, at + 8 + length));
        if (type == "IHDR") {
            width = int(be32(png, at + 8));
            height = int(be32(png, at + 12));
            REQUIRE(png[at + 16] == 8);
            REQUIRE(png[at + 17] == 0);
        } else if (type == "IDAT") {
            idat += png.substr(at + 8, length);
        } else if (type == "IEND") {
            ended = true;
        }
        at += 12 + length;
    }
    REQUIRE(ended);
    REQUIRE(std::uint8_t(idat[0]) == 0x78);
    std::string raw;
    std::size_t p = 2;
    for (;;) {
        const bool last = idat[p] & 1;
        REQUIRE((idat[p] & 6) == 0);  // stored
        const std::size_t n = std::uint8_t(idat[p + 1]) | (std::size_t(std::uint8_t(idat[p + 2])) << 8);
        raw += idat.substr(p + 5, n);
        p += 5 + n;
        if (last) break;
    }
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : raw) {
        a = (a + c) % 65521u;
        b = (b + a) % 65521u;
    }
    REQUIRE(be32(idat, p) == ((b << 16) | a));
    REQUIRE(raw.size() == std::size_t(width + 1) * height);
    std::vector<std::uint8_t> pixels;
    for (int y = 0; y < height; ++y) {
        REQUIRE(raw[std::size_t(y) * (width + 1)] == 0);
        for (int x = 0; x < width; ++x) pixels.push_back(std::uint8_t(raw[std::size_t(y) * (width + 1) + 1 + x]));
    }
    return pixels;
}

}  // namespace

TEST_CASE("png encoder: a known 3x2 image round-trips through an independent decoder, upright") {
    // Bottom-up input: bottom row 0,255,0 ; top row 255,0,10.
    const std::vector<std::uint8_t> bottom_up = {0, 255, 0, 255, 0, 10};
    int w = 0, h = 0;
    const auto pixels = decodePng(metric::encodePngGray(3, 2, bottom_up), w, h);
    CHECK(w == 3);
    CHECK(h == 2);
    CHECK(pixels == std::vector<std::uint8_t>{255, 0, 10, 0, 255, 0});
    // More than one stored block (> 65535 bytes of scanlines).
    std::vector<std::uint8_t> big(300 * 300);
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = std::uint8_t(i * 7);
    const auto back = decodePng(metric::encodePngGray(300, 300, big), w, h);
    CHECK(back[0] == big[299 * 300]);
    CHECK(back[back.size() - 1] == big[299]);
    CHECK_THROWS_AS(metric::encodePngGray(3, 3, bottom_up), engine::Error);
}

TEST_CASE("report: views.csv, summary.json and I1..I4 PNGs exist, parse and agree") {
    const engine::Scene scene = test_support::boxBehindWall(2.0f, 6.0f, 0.5f);
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
    CHECK(line == "view,eye_x,eye_y,eye_z,look_x,look_y,look_z,up_x,up_y,up_z,vfov_deg,width,height,"
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
    for (const char* key : {"views", "views_used", "metric_mean", "metric_min", "metric_max", "visible_mean",
                            "exact_mean", "seconds"})
        CHECK_MESSAGE(summary.contains(key), key);
    CHECK(summary["views"] == 3);
    CHECK(summary["views_used"] == r.views_used);
    CHECK(summary["metric_mean"].get<double>() == doctest::Approx(r.metric_mean));
    CHECK(summary["metric_min"].get<double>() <= summary["metric_max"].get<double>());

    // PNGs: I1's white pixels (full frame) hold at least the counted |I1| of that view.
    for (const char* name : {"i1", "i2", "i3", "i4"}) {
        int w = 0, h = 0;
        const auto pixels = decodePng(readFile(dir / "out" / ("view_1_" + std::string(name) + ".png")), w, h);
        CHECK(w == 96);
        CHECK(h == 64);
        std::int64_t lit = 0;
        for (auto p : pixels) lit += p == 255;
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
                         engine::Error);
}
