// tests/detect/boosted_model_test.cpp: the model file: written and read back the same,
// and every damaged or mismatching file refused in one line naming the file and what is
// wrong, before XGBoost sees its bytes.
#include <detect/boosted_model.hpp>
#include <detect/segment_features.hpp>
#include <detect/training.hpp>

#include "labelled_scenes.hpp"
#include "test_files.hpp"
#include <test_paths.hpp>

#include <doctest/doctest.h>

#include <cstring>

namespace {

detect::BoostedModel smallModel() {
    detect::TrainOptions o;
    o.boost.rounds = 5;
    o.holdout_fraction = 0.0;
    std::vector<detect::TrainingItem> items;
    for (std::uint32_t seed = 1; seed <= 2; ++seed)
        items.push_back(detect::describeLabelledCloud(test_support::labelledScene(seed, 3), "s", o));
    detect::TrainReport report;
    return detect::trainDetector(items, o, {std::string(64, 'a')}, report);
}

std::string refusal(const std::filesystem::path& file) {
    return test_support::errorOf([&] { detect::BoostedModel::read(file); });
}

// Replaces the first occurrence of `from` in the header by `to` and fixes the header length.
std::string editHeader(std::string bytes, const std::string& from, const std::string& to) {
    std::uint32_t hl = 0;
    std::memcpy(&hl, bytes.data() + 8, 4);
    std::string header = bytes.substr(12, hl);
    const auto at = header.find(from);
    REQUIRE(at != std::string::npos);
    header.replace(at, from.size(), to);
    const std::uint32_t nl = std::uint32_t(header.size());
    std::string out = bytes.substr(0, 8);
    out.append(reinterpret_cast<const char*>(&nl), 4);
    return out + header + bytes.substr(12 + hl);
}

}  // namespace

TEST_CASE("a model file reads back with its record and the same margins") {
    test_support::TempDir dir("detect_model");
    const detect::BoostedModel m = smallModel();
    m.write(dir.path / "m.ldm");
    const detect::BoostedModel r = detect::BoostedModel::read(dir.path / "m.ldm");
    CHECK(r.info().library == "xgboost");
    CHECK(r.info().library_version == detect::xgboostVersion());
    CHECK(r.info().features == detect::segmentFeatureNames());
    CHECK(r.info().corpus_manifests_sha256 == std::vector<std::string>{std::string(64, 'a')});
    CHECK(r.info().target_size_m == glm::dvec3(7.0, 3.5, 2.5));
    CHECK(r.info().platt_a == m.info().platt_a);
    CHECK(r.info().segments.split_height_m == m.info().segments.split_height_m);
    CHECK(r.info().feature_set == detect::FeatureSet::kV2);
    CHECK(r.info().segments.level_cell_m == 8.0);
    CHECK(r.serialize() == m.serialize());
    const std::vector<float> rows(detect::segmentFeatureNames().size() * 2, 1.0f);
    CHECK(r.margins(rows, 1) == m.margins(rows, 1));
    CHECK(dir.entries() == 1);  // no temporary left
}

TEST_CASE("a model file from before the split height reads as splitting nothing") {
    test_support::TempDir dir("detect_model_old");
    const std::string good = smallModel().serialize();
    const std::string old = editHeader(good, "\"split_height_m\"", "\"split_height_x\"");
    REQUIRE(old != good);
    { std::ofstream(dir.path / "old.ldm", std::ios::binary) << old; }
    CHECK(detect::BoostedModel::read(dir.path / "old.ldm").info().segments.split_height_m == 0.0);
}

TEST_CASE("a model file from before the terrain levelling reads as levelling nothing") {
    test_support::TempDir dir("detect_model_level");
    const std::string good = smallModel().serialize();
    const std::string old = editHeader(good, "\"level_cell_m\"", "\"level_cell_x\"");
    REQUIRE(old != good);
    { std::ofstream(dir.path / "old.ldm", std::ios::binary) << old; }
    CHECK(detect::BoostedModel::read(dir.path / "old.ldm").info().segments.level_cell_m == 0.0);
}

TEST_CASE("the shipped model reads as the second feature set, levelled in 8 m squares") {
    const detect::BoostedModel m =
        detect::BoostedModel::read(std::filesystem::path(test_support::assetsDir()) / "detect" / "model.ldm");
    CHECK(m.info().feature_set == detect::FeatureSet::kV2);
    CHECK(m.info().features == detect::segmentFeatureNames(detect::FeatureSet::kV2));
    CHECK(m.info().segments.level_cell_m == 8.0);
}

TEST_CASE("a bad or mismatching model file is refused in one line naming the file and the fault") {
    test_support::TempDir dir("detect_model_bad");
    const std::string good = smallModel().serialize();
    struct Case {
        const char* name;
        std::string bytes;
        const char* fault;
    };
    std::string flipped = good;
    flipped[flipped.size() - 10] ^= 0x55;
    std::string renamed = editHeader(good, "\"log_points\"", "\"log_count\"");
    // The first two features swapped: the same count, another order.
    std::string swapped =
        editHeader(editHeader(editHeader(good, "\"log_points\"", "\"x\""), "\"length_m\"", "\"log_points\""), "\"x\"",
                   "\"length_m\"");
    std::string dropped = editHeader(good, "\"points_per_m2_rel\"", "");
    dropped = editHeader(dropped, "\"log_points_rel\",", "\"log_points_rel\"");
    // A header length over the 1 MiB cap (the file is smaller still).
    std::string huge = good;
    const std::uint32_t over = (1u << 20) + 1;
    std::memcpy(huge.data() + 8, &over, 4);
    const Case cases[] = {
        {"empty.ldm", "", "no LDVRDET1 magic"},
        {"text.ldm", "{\"not\": \"a model\"}\n", "no LDVRDET1 magic"},
        {"cut.ldm", good.substr(0, good.size() - 1), "does not match the"},
        {"long.ldm", good + "x", "does not match the"},
        {"header_cut.ldm", good.substr(0, 40), "header length"},
        {"flipped.ldm", flipped, "do not match their SHA-256"},
        {"features.ldm", renamed, ": features[0] is 'log_count', this build's is 'log_points'; retrain"},
        {"order.ldm", swapped, ": features[0] is 'length_m', this build's is 'log_points'; retrain"},
        {"fewer.ldm", dropped, ": its 51 features differ from this build's 31 or 52; retrain"},
        {"header_huge.ldm", huge, "header length 1048577: allowed 2 .. 1048576 (1 MiB)"},
        {"library.ldm", editHeader(good, "\"xgboost\"", "\"lightgbm\""), "library 'lightgbm': allowed xgboost"},
        {"newer.ldm", editHeader(good, "\"" + detect::xgboostVersion() + "\"", "\"99.0.0\""),
         "trained with XGBoost 99.0.0"},
        {"format.ldm", editHeader(good, "\"format\": 1", "\"format\": 2"), "this build reads format 1"},
        {"size.ldm", editHeader(good, "\"target_size_m\": [", "\"target_size_m\": [-1,"), "target_size_m must hold"},
    };
    for (const Case& c : cases) {
        CAPTURE(std::string(c.name));
        const auto path = dir.path / c.name;
        { std::ofstream(path, std::ios::binary) << c.bytes; }
        const std::string e = refusal(path);
        CHECK(e.starts_with("detect: --model " + path.string() + ": "));
        CAPTURE(e);
        CHECK(e.find(c.fault) != std::string::npos);
        CHECK(e.find('\n') == std::string::npos);
    }
}
