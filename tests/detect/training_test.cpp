// tests/detect/training_test.cpp: a model trained in the test on a tiny synthetic corpus
// (labelled clouds with a tank-sized box, trees and a house) separates the box from the
// trees on a scene it did not see; a scrap of the target is left out of the training
// segments; the corpus listing refuses malformed manifests.
#include <detect/boosted_detector.hpp>
#include <detect/segment_features.hpp>
#include <detect/training.hpp>

#include "labelled_scenes.hpp"
#include "test_files.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <random>

namespace {

std::shared_ptr<const detect::BoostedModel> trainTiny(detect::TrainReport& report) {
    detect::TrainOptions o;
    o.boost.rounds = 40;
    o.holdout_fraction = 0.25;
    std::vector<detect::TrainingItem> items;
    for (std::uint32_t seed = 1; seed <= 8; ++seed)
        items.push_back(
            detect::describeLabelledCloud(test_support::labelledScene(seed, 6), "scene " + std::to_string(seed), o));
    return std::make_shared<const detect::BoostedModel>(detect::trainDetector(items, o, {}, report));
}

std::size_t targetPoints(const core::PointCloud& c, const detect::Detection& d) {
    std::size_t n = 0;
    for (const std::uint32_t i : d.points) n += c.points[i].label == core::Role::Target;
    return n;
}

}  // namespace

TEST_CASE("a model trained on a tiny labelled corpus ranks the box first and the trees low") {
    detect::TrainReport report;
    const auto model = trainTiny(report);
    CHECK(report.items == 8);
    CHECK(report.heldout_items == 2);
    CHECK(report.positives == 8);  // one box per scene, each its own segment
    CHECK(report.calibrated_on_heldout);

    glm::dvec2 at;
    const core::PointCloud scene = test_support::labelledScene(99, 8, &at);
    detect::BoostedOptions bo;
    bo.min_probability = 0.0;
    const std::vector<detect::Detection> found = detect::BoostedDetector(bo, model).detect(scene);
    REQUIRE(found.size() >= 9);  // the box, the house, 8 trees (a tree's trunk and crown are one segment)
    CHECK(2 * targetPoints(scene, found[0]) > found[0].points.size());
    CHECK(found[0].candidate.score > 0.5);
    const glm::dvec3 centre = found[0].candidate.centre_world - scene.origin;
    CHECK(std::hypot(centre.x - at.x, centre.y - at.y) < 1.0);
    for (std::size_t k = 1; k < found.size(); ++k) {
        CHECK(targetPoints(scene, found[k]) == 0);
        CHECK(found[k].candidate.score < 0.5);
    }
}

TEST_CASE("training refuses clouds without labels and corpora without a target") {
    detect::TrainOptions o;
    core::PointCloud unlabelled = test_support::labelledScene(1, 2);
    unlabelled.fields.label = false;
    CHECK(test_support::errorOf([&] { detect::describeLabelledCloud(unlabelled, "x.pcd", o); }) ==
          "train: x.pcd: the cloud has no label field; allowed corpus clouds (labelled points)");
    core::PointCloud no_target = test_support::labelledScene(2, 3);
    for (auto& p : no_target.points)
        if (p.label == core::Role::Target) p.label = core::Role::Environment;
    const std::vector<detect::TrainingItem> items = {detect::describeLabelledCloud(no_target, "a", o)};
    detect::TrainReport report;
    CHECK(test_support::errorOf([&] {
              detect::trainDetector(items, o, {}, report);
          }).starts_with("train: no training segment is mostly target-labelled"));
}

TEST_CASE("training leaves out a scrap of the target: mostly target points, a small share of the target") {
    const detect::TrainOptions o;
    // A 1 x 0.6 x 1.2 m box on free ground (every object of the scene stands at least 1.7 m
    // away): about 140 points, some 6 % of the target's.
    auto withScrap = [](core::Role role) {
        core::PointCloud c = test_support::labelledScene(3, 2);
        std::mt19937 rng(7);
        test_support::addBoxSurface(c, rng, {7.0, 7.0}, {1.0, 0.6, 1.2}, 0.0, 0.2, role);
        return c;
    };
    auto positives = [](const detect::TrainingItem& item) {
        return std::count(item.labels.begin(), item.labels.end(), 1.0f);
    };
    const detect::TrainingItem as_environment =
        detect::describeLabelledCloud(withScrap(core::Role::Environment), "e", o);
    const detect::TrainingItem as_target = detect::describeLabelledCloud(withScrap(core::Role::Target), "t", o);
    CHECK(positives(as_environment) == 1);  // the target box; the scrap a negative
    CHECK(positives(as_target) == 1);       // the target box; the scrap neither
    CHECK(as_target.labels.size() + 1 == as_environment.labels.size());
    CHECK(as_target.rows.size() == as_target.labels.size() * detect::segmentFeatureNames().size());
}

TEST_CASE("the corpus listing reads the manifest's items and refuses malformed lines in one line") {
    test_support::TempDir dir("detect_listing");
    dir.write("manifest.jsonl", R"({"id": "0000", "files": {"scene.json": {}, "cloud.pcd": {}}})"
                                "\n"
                                R"({"id": "0001", "files": {"cloud.laz": {}}})"
                                "\n");
    const detect::CorpusListing l = detect::listCorpus(dir.path);
    REQUIRE(l.ids.size() == 2);
    CHECK(l.cloud(0) == dir.path / "items" / "0000" / "cloud.pcd");
    CHECK(l.cloud(1) == dir.path / "items" / "0001" / "cloud.laz");
    CHECK(l.manifest_sha256.size() == 64);

    dir.write("manifest.jsonl", R"({"id": "../x", "files": {"cloud.pcd": {}}})"
                                "\n");
    const std::string e = test_support::errorOf([&] { detect::listCorpus(dir.path); });
    CHECK(e.find("manifest.jsonl line 1: id '../x': allowed digits only") != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
    dir.write("manifest.jsonl", R"({"id": "0003", "files": {"scene.json": {}}})"
                                "\n");
    CHECK(test_support::errorOf([&] { detect::listCorpus(dir.path); }).find("names no cloud file") !=
          std::string::npos);
}

TEST_CASE("the corpus listing is as strict as the other JSON readers: no duplicate key, no NUL in a key") {
    test_support::TempDir dir("detect_listing_strict");
    dir.write("manifest.jsonl", R"({"id": "0000", "id": "0001", "files": {"cloud.pcd": {}}})"
                                "\n");
    std::string e = test_support::errorOf([&] { detect::listCorpus(dir.path); });
    CHECK(e.find("manifest.jsonl line 1: duplicate key 'id'") != std::string::npos);
    dir.write("manifest.jsonl", R"({"id": "0000", "files": {"cloud.pcd\u0000.txt": {}}})"
                                "\n");
    e = test_support::errorOf([&] { detect::listCorpus(dir.path); });
    CHECK(e.find("manifest.jsonl line 1: ") != std::string::npos);
    CHECK(e.find("NUL") != std::string::npos);
    dir.write("manifest.jsonl", std::string(R"({"id": "0000", "files": {"cloud.pcd": {}}, "pad": ")") +
                                    std::string(2 << 20, 'x') + "\"}\n");
    e = test_support::errorOf([&] { detect::listCorpus(dir.path); });
    CHECK(e.find("manifest.jsonl line 1: 2097") != std::string::npos);
    CHECK(e.find("bytes; allowed at most 1048576 bytes a line") != std::string::npos);
}

TEST_CASE("the corpus listing counts the manifest and the listing against the memory budget") {
    test_support::TempDir dir("detect_listing_budget");
    std::string text;
    for (int k = 0; k < 4000; ++k)
        text += R"({"id": ")" + std::to_string(100000 + k) +
                R"(", "files": {"cloud.pcd": {}}})"
                "\n";
    dir.write("manifest.jsonl", text);
    const detect::CorpusListing l = detect::listCorpus(dir.path, std::size_t(64) << 20);
    CHECK(l.ids.size() == 4000);
    // The vectors' fixed part: two strings an entry, whose ids and names fit inside them.
    CHECK(l.held_bytes == 4001 * 2 * sizeof(std::string));
    // The text fits, the fixed part does not.
    std::string e = test_support::errorOf([&] { detect::listCorpus(dir.path, text.size() + 1000); });
    CHECK(e.find("manifest.jsonl: its 4001 lines and their listing pass --memory-mb 0 MiB; raise --memory-mb") !=
          std::string::npos);
    // The fixed part fits, the paths' heap does not: refused part way, naming the line.
    std::string long_names;
    for (int k = 0; k < 4000; ++k)
        long_names += R"({"id": "0000000000)" + std::to_string(100000 + k) +
                      R"(", "files": {"cloud.pcd": {}}})"
                      "\n";
    dir.write("manifest.jsonl", long_names);
    const std::size_t fixed = long_names.size() + 4001 * 2 * sizeof(std::string);
    e = test_support::errorOf([&] { detect::listCorpus(dir.path, fixed + 2000 * 33); });
    CHECK(e.find("manifest.jsonl: its text and its listing up to line ") != std::string::npos);
    // An id of 16 digits outgrows the inline buffer: 33 bytes of heap each, so 2,000 fit.
    CHECK(e.find("up to line 2001 pass") != std::string::npos);
    // The text alone is over.
    dir.write("manifest.jsonl", text);
    e = test_support::errorOf([&] { detect::listCorpus(dir.path, text.size() - 1); });
    CHECK(e.find("manifest.jsonl: " + std::to_string(text.size()) + " bytes, more than --memory-mb 0 MiB") !=
          std::string::npos);
}
