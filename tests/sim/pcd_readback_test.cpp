// tests/sim/pcd_readback_test.cpp: a generated file loads in PCL with the summary's count.
// The only test file that includes PCL.
#include "test_scenes.hpp"

#include <sim/generator.hpp>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <doctest/doctest.h>

#include <filesystem>
#include <unistd.h>

TEST_CASE("pcl::io::loadPCDFile reads the generated cloud with the summary's count and fields") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("ladarvr_pcd_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const engine::Scene scene = sim_test::townScene(160.0, 2.0);  // covers the footprint
    sim::GenerateOptions o;
    o.orbit.xres = 64;
    o.orbit.yres = 64;
    o.orbit.views = 10;
    for (const auto format : {engine::CloudFormat::PcdBinary, engine::CloudFormat::PcdAscii}) {
        const fs::path out = dir / "cloud.pcd";
        sim::GenerateStats st;
        sim::generateToFile(scene, o, out, format, &st);
        pcl::PointCloud<pcl::PointXYZRGBL> cloud;
        REQUIRE(pcl::io::loadPCDFile(out.string(), cloud) == 0);
        CHECK(cloud.size() == st.points);
        CHECK(st.points == 40960);
        std::size_t white = 0, ground = 0, target = 0;
        for (const auto& p : cloud) {
            white += p.r == 255 && p.g == 255 && p.b == 255;
            ground += p.label == 0;
            target += p.label == 2;
        }
        CHECK(white == st.ground_found);
        CHECK(ground == st.ground_truth);
        CHECK(target > 0);
        fs::remove(out);
    }
    fs::remove_all(dir);
}
