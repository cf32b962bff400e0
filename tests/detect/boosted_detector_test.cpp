// tests/detect/boosted_detector_test.cpp: the trained detector gives the same candidates
// whatever its thread count, and the shipped model (assets/detect/) loads and ranks the
// demo scene's tank first.
#include <test_paths.hpp>
#include <detect/boosted_detector.hpp>
#include <detect/training.hpp>

#include <io/scene_file.hpp>
#include <sim/generator.hpp>

#include "labelled_scenes.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <memory>

namespace {

std::size_t targetPoints(const core::PointCloud& c, const detect::Detection& d) {
    std::size_t n = 0;
    for (const std::uint32_t i : d.points) n += c.points[i].label == core::Role::Target;
    return n;
}

}  // namespace

TEST_CASE("the trained detector's candidates do not depend on the thread count") {
    detect::TrainOptions o;
    o.boost.rounds = 20;
    std::vector<detect::TrainingItem> items;
    for (std::uint32_t seed = 1; seed <= 4; ++seed)
        items.push_back(detect::describeLabelledCloud(test_support::labelledScene(seed, 5), "s", o));
    detect::TrainReport report;
    const auto model = std::make_shared<const detect::BoostedModel>(detect::trainDetector(items, o, {}, report));
    const core::PointCloud scene = test_support::labelledScene(42, 12);
    detect::BoostedOptions bo;
    bo.min_probability = 0.0;
    bo.threads = 1;
    const auto one = detect::BoostedDetector(bo, model).detect(scene);
    bo.threads = 3;
    const auto three = detect::BoostedDetector(bo, model).detect(scene);
    REQUIRE(one.size() == three.size());
    REQUIRE(one.size() >= 10);
    for (std::size_t k = 0; k < one.size(); ++k) {
        CHECK(one[k].candidate.id == three[k].candidate.id);
        CHECK(one[k].candidate.score == three[k].candidate.score);
        CHECK(one[k].candidate.centre_world == three[k].candidate.centre_world);
        CHECK(one[k].points == three[k].points);
    }
}

TEST_CASE("the shipped model loads and ranks the demo scene's tank first") {
    const std::filesystem::path assets = test_support::assetsDir();
    detect::BoostedOptions bo;
    bo.model = assets / "detect" / "model.ldm";
    bo.threads = 2;
    const detect::BoostedDetector detector(bo);
    CHECK(detector.model().info().library == "xgboost");
    CHECK(detector.model().info().corpus_manifests_sha256.size() == 18);  // assets/detect/shipped_*.json
    const core::Scene scene = io::loadScene(assets / "demo" / "scene.json");
    const core::PointCloud cloud = sim::generateCloud(scene, sim::GenerateOptions{});
    const std::vector<detect::Detection> found = detector.detect(cloud);
    REQUIRE(!found.empty());
    CHECK(2 * targetPoints(cloud, found[0]) > found[0].points.size());
    CHECK(found[0].candidate.score > 0.5);
}
