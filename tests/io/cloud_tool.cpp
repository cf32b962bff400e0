// cloud_tool: io's cloud writer and reader for tests in other languages
// (las_interop_test.py compares what laspy and Open3D read with what we read).
//   cloud_tool write <out> <ox> <oy> <oz>   a synthetic cloud with every field, at that origin
//   cloud_tool dump <in>                    one line per point, world coordinates in metres
#include <core/error.hpp>
#include <io/cloud_io.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

core::PointCloud synthetic(const glm::dvec3& origin) {
    core::PointCloud c;
    c.origin = origin;
    c.fields.intensity = c.fields.returns = c.fields.incidence = c.fields.scan_angle = true;
    c.fields.height_above_ground = true;
    for (int i = 0; i < 1000; ++i) {
        core::CloudPoint p;
        p.position = {float(i % 40) * 0.25f - 5.0f, float(i / 40) * 0.5f, float(i % 7) * 0.125f};
        p.rgb = core::packRgb(std::uint8_t(i), std::uint8_t(i * 3), std::uint8_t(255 - i % 256));
        p.range_m = 300.0f + float(i) * 0.25f;
        p.incidence_deg = float(i % 80) * 0.5f;
        p.scan_angle_deg = float(i % 21 - 10) * 0.3f;
        p.height_above_ground_m = float(i % 9) * 0.25f;
        p.intensity = std::uint16_t(i * 61);
        p.view = std::uint16_t(i % 11);
        p.label = core::Role(i % 3);
        p.return_number = std::uint8_t(1 + i % 2);
        p.returns = 2;
        c.points.push_back(p);
    }
    return c;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::string cmd = argc > 1 ? argv[1] : "";
        if (cmd == "write" && argc == 6) {
            const std::filesystem::path out = argv[2];
            const glm::dvec3 origin{std::strtod(argv[3], nullptr), std::strtod(argv[4], nullptr),
                                    std::strtod(argv[5], nullptr)};
            io::writeCloud(out, synthetic(origin), io::formatForPath(out));
            return 0;
        }
        if (cmd == "dump" && argc == 3) {
            const core::PointCloud c = io::readCloud(argv[2]);
            std::printf("count %zu\n", c.points.size());
            for (const core::CloudPoint& p : c.points) {
                const glm::dvec3 w = c.origin + glm::dvec3(p.position);
                std::printf("%.6f %.6f %.6f %u %d %u %.9g %u %u %u %.9g %.9g %.9g\n", w.x, w.y, w.z, p.rgb,
                            int(p.label), unsigned(p.view), double(p.range_m), unsigned(p.intensity),
                            unsigned(p.return_number), unsigned(p.returns), double(p.incidence_deg),
                            double(p.scan_angle_deg), double(p.height_above_ground_m));
            }
            return 0;
        }
        std::fprintf(stderr, "usage: cloud_tool write <out> <ox> <oy> <oz> | dump <in>\n");
        return 2;
    } catch (const core::Error& e) {
        std::fprintf(stderr, "cloud_tool: %s\n", e.what());
        return 1;
    }
}
