// tests/sim/sensor_ideal_test.cpp: the sensor seam. With every model off the generator's
// cloud is, byte for byte, the cloud of the paper's ideal sensor: one ray per pixel centre
// from the orbit's pose, its first hit placed at origin + t * direction. That cloud is
// rebuilt here through the RayCaster's public interface, independently of sim::Sensor.
#include <scene_builders.hpp>

#include <sim/generator.hpp>
#include <sim/sensor.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <cstring>
#include <limits>
#include <vector>

namespace {

// The ideal cloud of `g`'s options (white, so no RANSAC), traced with single rays.
std::vector<core::CloudPoint> idealCloud(const sim::Generator& g) {
    std::vector<core::CloudPoint> out;
    std::vector<sim::Ray> rays;
    std::vector<sim::Hit> hits;
    for (int v = 0; v < g.options().orbit.views; ++v) {
        g.viewRays(v, rays);
        hits.resize(rays.size());
        g.caster().intersect(rays, hits);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!hits[i].hit()) continue;
            core::CloudPoint p;
            p.position = glm::vec3(glm::dvec3(rays[i].origin) + double(hits[i].t) * glm::dvec3(rays[i].direction));
            p.range_m = hits[i].t;
            p.view = std::uint16_t(v);
            p.label = hits[i].role;
            p.rgb = core::kWhite;
            out.push_back(p);
        }
    }
    return out;
}

bool sameBytes(const std::vector<core::CloudPoint>& a, const std::vector<core::CloudPoint>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(core::CloudPoint)) == 0;
}

}  // namespace

TEST_CASE("sensor: every model off gives the ideal sensor's cloud byte for byte, packets or not") {
    const core::Scene scene = test_support::townScene(120.0, 1.0);
    sim::GenerateOptions o;
    o.orbit.xres = 67;  // rows that do not split into whole packets
    o.orbit.yres = 40;
    o.orbit.views = 9;
    o.white = true;
    CHECK(sim::isIdeal(o.sensor));
    for (const bool packets : {true, false}) {
        CAPTURE(packets);
        o.packet_rays = packets;
        sim::Generator g(scene, o);
        const core::PointCloud cloud = g.run();
        const std::vector<core::CloudPoint> expected = idealCloud(g);
        CHECK(expected.size() > 10000);
        CHECK(sameBytes(cloud.points, expected));
        // The ideal cloud carries the four fields it always had, and nothing more.
        CHECK_FALSE(cloud.fields.intensity);
        CHECK_FALSE(cloud.fields.returns);
        CHECK_FALSE(cloud.fields.incidence);
        CHECK_FALSE(cloud.fields.scan_angle);
    }
    // The "ideal" preset is the default.
    const sim::SensorOptions ideal = sim::sensorPreset("ideal");
    CHECK(sim::isIdeal(ideal));
}

TEST_CASE("sensor: any model on leaves the ideal path, and the presets are valid real sensors") {
    sim::SensorOptions o;
    o.range_noise_m = 0.01;
    CHECK_FALSE(sim::isIdeal(o));
    o = {};
    o.returns = sim::ReturnMode::Last;
    CHECK_FALSE(sim::isIdeal(o));
    for (std::string_view name : sim::sensorPresetNames()) {
        CAPTURE(name);
        const sim::SensorOptions p = sim::sensorPreset(name);
        CHECK_NOTHROW(sim::validate(p));
        CHECK(sim::isIdeal(p) == (name == "ideal"));
    }
    const sim::SensorOptions vux = sim::sensorPreset("riegl-vux1uav");
    CHECK(vux.beam_divergence_mrad == 0.5);
    CHECK(vux.range_noise_m == 0.01);
    const sim::SensorOptions avia = sim::sensorPreset("livox-avia");
    CHECK(avia.beam_divergence_mrad == 0.89);
    CHECK(avia.range_noise_m == 0.02);
    CHECK(avia.max_returns == 3);
    CHECK_THROWS_WITH_AS(sim::sensorPreset("velodyne"),
                         "sensor: --sensor 'velodyne' is not one of ideal, riegl-vux1uav, livox-avia", core::Error);
}

TEST_CASE("sensor: bad values name the option and the allowed range") {
    sim::SensorOptions o;
    o.range_noise_m = -0.1;
    CHECK_THROWS_WITH_AS(sim::validate(o), "sensor: range_noise_m (--range-noise-m) = -0.1: allowed [0, 100] metres",
                         core::Error);
    o = {};
    o.footprint_quality = 9;
    CHECK_THROWS_WITH_AS(sim::validate(o), "sensor: footprint_quality (--footprint-quality) = 9: allowed [1, 5]",
                         core::Error);
    o = {};
    o.max_returns = 0;
    CHECK_THROWS_WITH_AS(sim::validate(o), "sensor: max_returns (--max-returns) = 0: allowed [1, 15]", core::Error);
    o = {};
    o.beam_divergence_mrad = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(sim::validate(o), core::Error);
    CHECK_THROWS_WITH_AS(sim::parseReturnMode("second", "sensor: --returns"),
                         "sensor: --returns: 'second' is not one of first, last, strongest, all", core::Error);
    CHECK(sim::parseReturnMode("strongest", "x") == sim::ReturnMode::Strongest);
    // The generator validates its sensor before any work.
    sim::GenerateOptions g;
    g.sensor.attitude_noise_deg = 20.0;
    CHECK_THROWS_WITH_AS(sim::validate(g),
                         "sensor: attitude_noise_deg (--attitude-noise-deg) = 20: allowed [0, 10] degrees",
                         core::Error);
}
