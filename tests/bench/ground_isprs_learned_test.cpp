// tests/bench/ground_isprs_learned_test.cpp: the learned refinement of SMRF as `bench
// ground-isprs` scores it, on two small ISPRS samples of two sites (samp24 and samp54, each
// classified by trees learned on the other): two runs give the same margins (the trees
// learn on two threads with a fixed seed), and each sample's confusion counts are pinned,
// so that a change to the features, the trees' parameters or XGBoost is seen before the
// figures of docs/ground-isprs.md and BENCHMARKS.md silently stop being this build's.
#include <test_paths.hpp>
#include "ground_isprs_learned.hpp"

#include <core/point_cloud.hpp>
#include <core/roles.hpp>
#include <io/cloud_io.hpp>
#include <sim/ground_file.hpp>

#include <doctest/doctest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace {

// A sample of tests/data/isprs with its reference labels and features, as the bench reads it.
bench::LearnedSample load(const std::string& name) {
    const core::PointCloud cloud = io::readCloud(std::string(test_support::isprsDir()) + "/" + name + ".laz");
    std::vector<std::uint8_t> truth;
    for (const core::CloudPoint& p : cloud.points) truth.push_back(p.label == core::Role::Ground ? 1 : 0);
    return bench::describeSample(name, cloud.points, truth, sim::surveySmrfOptions());
}

// Reference x found, ground / object.
struct Confusion {
    std::size_t gg = 0, go = 0, og = 0, oo = 0;
    bool operator==(const Confusion&) const = default;
};

Confusion confusion(const std::vector<std::uint8_t>& found, const std::vector<std::uint8_t>& truth) {
    Confusion c;
    for (std::size_t i = 0; i < truth.size(); ++i) {
        if (truth[i])
            ++(found[i] ? c.gg : c.go);
        else
            ++(found[i] ? c.og : c.oo);
    }
    return c;
}

}  // namespace

TEST_CASE("ground-isprs learned: two sites' samples, each refined by trees learned on the other, pinned") {
    const std::vector<bench::LearnedSample> samples = {load("samp24"), load("samp54")};
    REQUIRE(samples[0].site == 2);
    REQUIRE(samples[1].site == 5);
    const std::vector<std::vector<float>> margins = bench::leaveOneSiteOut(samples, bench::TreeParams{});
    REQUIRE(margins.size() == 2);
    CHECK(bench::leaveOneSiteOut(samples, bench::TreeParams{}) == margins);
    // Reference x found (ground / object), as this build gives them; they follow the
    // features, which move with any change to the terrains they read (one as small as the
    // hole filling's last sweeps: tests/sim/ground_learned_test.cpp).
    const Confusion smrf[] = {{5289, 145, 165, 1893}, {3934, 49, 264, 4361}};
    const Confusion refined[] = {{5100, 334, 109, 1949}, {3957, 26, 525, 4100}};
    for (std::size_t k = 0; k < 2; ++k) {
        CAPTURE(samples[k].name);
        CHECK(confusion(samples[k].smrf, samples[k].truth) == smrf[k]);
        CHECK(confusion(bench::refinedLabels(samples[k], margins[k], bench::kRefineConfidence), samples[k].truth) ==
              refined[k]);
    }
}
