// tests/corpus/spec_test.cpp: a bad SPEC is one line naming the key and what is allowed,
// before any work; a good one is read as written.
#include <corpus/random.hpp>
#include <corpus/spec.hpp>

#include <sim/generator.hpp>
#include <sim/sensor.hpp>

#include <doctest/doctest.h>

#include "test_files.hpp"
#include <test_paths.hpp>

#include <string>
#include <vector>

using test_support::errorOf;

namespace {

const std::string kScene = std::string(test_support::corpusDataDir()) + "/scene.json";

std::string specError(const std::string& body) {
    test_support::TempDir dir("corpus_spec");
    const auto file = dir.write("spec.json", body);
    return errorOf([&] { corpus::loadSpec(file); });
}

std::string withVary(const std::string& vary) {
    return R"({"scene": ")" + kScene + R"(", "count": 3, "seed": 1, "vary": {)" + vary + "}}";
}

void checkOneLine(const std::string& message, const std::string& key, const std::string& allowed) {
    INFO(message);
    CHECK(message.rfind("corpus: ", 0) == 0);
    CHECK(message.find('\n') == std::string::npos);
    CHECK(message.find(key) != std::string::npos);
    CHECK(message.find(allowed) != std::string::npos);
}

}  // namespace

TEST_CASE("spec: a good SPEC is read as written") {
    test_support::TempDir dir("corpus_spec_good");
    const std::string text = withVary(R"("altitude_m": {"min": 200, "max": 400}, "resolution": [16, 32], "views": 5,
        "target_files": [")" + std::string(test_support::assetsDir()) +
                                      R"(/common/tank.obj", {"file": ")" + std::string(test_support::assetsDir()) +
                                      R"(/common/tower.obj", "up": "z", "scale": 0.5}])");
    const corpus::Spec s = corpus::parseSpec(text, dir.path / "spec.json");
    CHECK(s.count == 3);
    CHECK(s.seed == 1);
    CHECK(s.numbers.at("altitude_m").kind == corpus::NumberVary::Kind::Uniform);
    CHECK(s.numbers.at("altitude_m").min == 200);
    CHECK(s.numbers.at("resolution").choices.size() == 2);
    CHECK(s.numbers.at("views").kind == corpus::NumberVary::Kind::Fixed);
    CHECK(s.target_files.size() == 2);
    CHECK(s.target_files[1].scale == 0.5);
    CHECK(s.sha256.size() == 64);
    CHECK(s.cloudName() == "cloud.pcd");
    CHECK_FALSE(s.metric.enabled);
    const corpus::Spec ply = corpus::parseSpec(R"({"scene": ")" + kScene + R"(", "count": 1, "format": "ply",
        "metric": {"views": 8, "width": 64, "height": 32}})",
                                               dir.path / "spec.json");
    CHECK(ply.cloudName() == "cloud.ply");
    CHECK(ply.metric.enabled);
    CHECK(ply.metric.views == 8);
    CHECK(ply.metric.height == 32);
    const corpus::Spec laz =
        corpus::parseSpec(R"({"scene": ")" + kScene + R"(", "count": 1, "format": "laz"})", dir.path / "spec.json");
    CHECK(laz.cloudName() == "cloud.laz");
    CHECK(errorOf([&] {
              corpus::parseSpec(R"({"scene": ")" + kScene + R"(", "count": 1, "format": "e57"})", "s.json");
          }).find("format 'e57' is not one of pcd, pcd-ascii, ply, ply-ascii, las, laz, copc") != std::string::npos);
}

TEST_CASE("spec: sensor_preset takes the presets' names or their places, and sets the generator's sensor") {
    test_support::TempDir dir("corpus_spec_sensor");
    const corpus::Spec s =
        corpus::parseSpec(withVary(R"("sensor_preset": ["ideal", "livox-avia", 1])"), dir.path / "spec.json");
    const corpus::NumberVary& n = s.numbers.at("sensor_preset");
    REQUIRE(n.kind == corpus::NumberVary::Kind::Choice);
    CHECK(n.choices == std::vector<double>{0, 2, 1});
    sim::GenerateOptions o;
    corpus::applyToOptions(o, "sensor_preset", 2);
    const sim::SensorOptions avia = sim::sensorPreset("livox-avia");
    CHECK(o.sensor.range_noise_m == avia.range_noise_m);
    CHECK(o.sensor.attitude_noise_deg == avia.attitude_noise_deg);
    CHECK_FALSE(sim::isIdeal(o.sensor));
    corpus::applyToOptions(o, "sensor_preset", 0);
    CHECK(sim::isIdeal(o.sensor));
    checkOneLine(specError(withVary(R"("sensor_preset": ["lidar-x"])")), "vary.sensor_preset[0]",
                 "allowed ideal, riegl-vux1uav, livox-avia");
    checkOneLine(specError(withVary(R"("sensor_preset": 3)")), "vary.sensor_preset", "allowed integers in [0, 2]");
}

TEST_CASE("spec: unknown keys, empty ranges, min > max, count < 1 and missing files are one line each") {
    checkOneLine(specError(R"({"scene": ")" + kScene + R"(", "count": 3, "sed": 1})"), "sed",
                 "allowed scene, count, seed, vary");
    checkOneLine(specError(withVary(R"("altitude": {"min": 1, "max": 2})")), "vary.altitude", "allowed target_yaw_deg");
    checkOneLine(specError(withVary(R"("altitude_m": {"min": 400, "max": 200})")), "vary.altitude_m",
                 "min 400 > max 200");
    checkOneLine(specError(withVary(R"("altitude_m": {"min": 400})")), "vary.altitude_m", "empty range");
    checkOneLine(specError(withVary(R"("resolution": [])")), "vary.resolution", "empty list");
    checkOneLine(specError(withVary(R"("resolution": [16.5])")), "vary.resolution[0]", "allowed integers");
    checkOneLine(specError(withVary(R"("environment_keep_fraction": {"min": 0.5, "max": 1.5})")),
                 "vary.environment_keep_fraction.max", "allowed numbers in [0, 1]");
    checkOneLine(specError(withVary(R"("altitude_m": {"min": 1, "max": 2, "step": 1})")), "vary.altitude_m",
                 "allowed min, max");
    checkOneLine(specError(withVary(R"("target_files": ["no_such_tank.obj"])")), "vary.target_files[0]",
                 "does not exist");
    checkOneLine(specError(R"({"scene": ")" + kScene + R"(", "count": 0})"), "count", "allowed an integer in [1, ");
    checkOneLine(specError(R"({"scene": ")" + kScene + R"(", "count": -2})"), "count", "allowed an integer in [1, ");
    checkOneLine(specError(R"({"scene": "missing_scene.json", "count": 2})"), "scene", "does not exist");
    checkOneLine(specError(R"({"count": 2})"), "scene", "missing");
    checkOneLine(specError(R"({"scene": ")" + kScene + R"("})"), "count", "missing");
    checkOneLine(specError(R"({"scene": ")" + kScene + R"(", "count": 2, "metric": {"views": 0}})"), "metric.views",
                 "allowed an integer in [1, 65535]");
    // The generator's limits at the ranges' corners: alpha 60 + fov 70/2 is past grazing.
    checkOneLine(specError(withVary(R"("alpha_deg": {"min": 30, "max": 60}, "fov_deg": {"min": 4, "max": 70})")),
                 "at its highest", "orbit:");
    checkOneLine(specError("[1, 2]"), "corpus: ", "allowed a JSON object");
    // Strict JSON: the second of two equal keys would otherwise win silently.
    checkOneLine(specError(R"({"scene": ")" + kScene + R"(", "count": 2, "count": 5})"), "duplicate key 'count'",
                 "allowed: each key once per object");
    checkOneLine(specError(R"({"scene": ")" + kScene + R"(", "count": )"), "spec.json", "JSON syntax error");
}

TEST_CASE("random: SplitMix64 known answer, streams depend on (seed, item, key) only") {
    corpus::SplitMix64 r(0);
    CHECK(r.next() == 0xe220a8397b1dcdafull);  // the reference SplitMix64's first output for seed 0
    CHECK(corpus::itemSeed(7, 3) == corpus::itemSeed(7, 3));
    CHECK(corpus::itemSeed(7, 3) != corpus::itemSeed(7, 4));
    CHECK(corpus::itemSeed(7, 3) != corpus::itemSeed(8, 3));
    corpus::SplitMix64 a = corpus::keyStream(corpus::itemSeed(7, 3), "altitude_m");
    corpus::SplitMix64 b = corpus::keyStream(corpus::itemSeed(7, 3), "altitude_m");
    corpus::SplitMix64 c = corpus::keyStream(corpus::itemSeed(7, 3), "alpha_deg");
    const std::uint64_t first = a.next();
    CHECK(first == b.next());
    CHECK(first != c.next());
    corpus::SplitMix64 u(42);
    for (int i = 0; i < 1000; ++i) {
        const double x = u.unit();
        CHECK((x >= 0.0 && x < 1.0));
        CHECK(u.below(3) < 3);
    }
}
