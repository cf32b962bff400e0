// tests/sim/fuse_test.cpp: the generator's fusion (sim/src/fuse.hpp) without Embree: a
// made-up caster fills the slots of two tiny views, and the points handed on must come in
// (view, row, column) order, misses left out, whitened where the view filter says, and
// the same whatever the batches, bands, threads and pipelining.
#include "fuse.hpp"

#include <doctest/doctest.h>

#include <atomic>
#include <tuple>
#include <vector>

namespace {

constexpr int kXres = 3, kYres = 2, kViews = 2;

// Pixel i of view v returns at z = 10 v + i, except pixel 4 of view 1, which misses;
// even pixels are ground-labelled.
bool misses(int view, std::size_t pixel) { return view == 1 && pixel == 4; }

// Whitens the points below z = 12 (one flag per point), counting them as one plane.
class BelowTwelve : public sim::ViewGroundFilter {
  public:
    sim::GroundMethod method() const override { return sim::GroundMethod::Ransac; }
    std::vector<std::uint8_t> classifyView(std::span<const glm::vec3> points, std::uint64_t,
                                           sim::GroundStats* stats) const override {
        std::vector<std::uint8_t> ground;
        for (const glm::vec3& p : points) ground.push_back(p.z < 12.0f);
        stats->band_points = points.size();
        stats->planes_accepted = 1;
        return ground;
    }
};

struct Fused {
    std::vector<core::CloudPoint> points;
    std::vector<std::size_t> calls;  // points per emit call
    sim::GenerateStats st;
    int wrong_directions = 0;
};

Fused fuse(std::size_t batch_views, std::size_t band_rows, int threads, bool white,
           const sim::ViewGroundFilter* filter) {
    sim::FuseSetup setup;
    setup.orbit.xres = kXres;
    setup.orbit.yres = kYres;
    setup.orbit.views = kViews;
    setup.plan.batch_views = batch_views;
    setup.plan.band_rows = band_rows;
    setup.plan.threads = threads;
    setup.plan.view_hits = kXres * kYres;
    setup.budget_bytes = std::uint64_t(1) << 30;  // room to pipeline when threads >= 2
    setup.white = white;
    setup.view_filter = filter;
    const std::vector<std::uint64_t> traced{6, 5};
    setup.traced_count = traced;
    std::atomic<int> wrong{0};
    setup.cast_block = [&](int view, std::size_t begin, std::size_t end, const sim::FuseBand& band) {
        for (std::size_t i = begin; i < end; ++i) {
            const glm::dvec3 want = sim::pixelDirection(setup.orbit, double(i % kXres), double(i / kXres));
            if (band.dirs[i - band.first] != want) ++wrong;
            core::CloudPoint& p = band.slots[i - band.first];
            p = core::CloudPoint{};
            p.position = glm::vec3(float(view), float(i), float(10 * view + int(i)));
            p.range_m = misses(view, i) ? sim::kNoReturn : 1.0f;
            p.view = std::uint16_t(view);
            p.rgb = 0;  // not yet coloured, as the sensor leaves a return
            p.label = i % 2 == 0 ? core::Role::Ground : core::Role::Target;
        }
    };
    Fused f;
    const sim::FuseEmit emit = [&](std::span<const core::CloudPoint> pts, std::span<const unsigned char>) {
        f.points.insert(f.points.end(), pts.begin(), pts.end());
        f.calls.push_back(pts.size());
    };
    sim::Workers pool(threads);
    sim::FusePipeline(setup, pool, f.st, 0, nullptr, emit).run();
    f.wrong_directions = wrong.load();
    return f;
}

// The points every plan must hand on: (view, pixel) in order, but the miss.
void checkOrder(const Fused& f) {
    REQUIRE(f.points.size() == 11);
    std::size_t n = 0;
    for (int v = 0; v < kViews; ++v)
        for (std::size_t i = 0; i < std::size_t(kXres * kYres); ++i) {
            if (misses(v, i)) continue;
            CAPTURE(v);
            CAPTURE(i);
            CHECK(f.points[n].position.z == float(10 * v + int(i)));
            CHECK(f.points[n].view == v);
            ++n;
        }
    CHECK(f.wrong_directions == 0);
    CHECK(f.st.points == 11);
    CHECK(f.st.misses == 1);
    CHECK(f.st.rays == 12);
    CHECK(f.st.rays_traced == 11);
    CHECK(f.st.z_min == 0.0f);
    CHECK(f.st.z_max == 15.0f);
    CHECK(f.st.ground_truth == 5);  // pixels 0, 2, 4 of view 0; 0, 2 of view 1
}

}  // namespace

TEST_CASE("fusion hands each view's returns on in view and pixel order, misses left out") {
    for (const auto& [batch, band, threads] :
         {std::tuple<std::size_t, std::size_t, int>{1, 2, 1}, {2, 2, 1}, {2, 2, 2}, {1, 2, 2}, {1, 1, 1}, {1, 1, 2}}) {
        CAPTURE(batch);
        CAPTURE(band);
        CAPTURE(threads);
        const Fused f = fuse(batch, band, threads, false, nullptr);
        checkOrder(f);
        CHECK(f.calls == std::vector<std::size_t>{6, 5});  // one call per view
        CHECK(f.st.pipelined == (threads >= 2));
        for (const core::CloudPoint& p : f.points) CHECK(p.rgb == 0);
        CHECK(f.st.ground_found == 0);
        CHECK(f.st.ground_recall == 0.0);
    }
}

TEST_CASE("fusion whitens each view with its filter and counts the ground found against the labels") {
    const BelowTwelve filter;
    for (const int threads : {1, 2}) {
        CAPTURE(threads);
        const Fused f = fuse(1, 2, threads, false, &filter);
        checkOrder(f);
        for (const core::CloudPoint& p : f.points) CHECK((p.rgb == core::kWhite) == (p.position.z < 12.0f));
        // White: view 0's six and view 1's pixels 0 and 1; of them 0, 2, 4 of view 0 and 0 of view 1 are ground.
        CHECK(f.st.ground_found == 8);
        CHECK(f.st.ground_true_positive == 4);
        CHECK(f.st.planes_accepted == 2);
        REQUIRE(f.st.ground_precision.has_value());
        CHECK(*f.st.ground_precision == doctest::Approx(0.5));
        REQUIRE(f.st.ground_recall.has_value());
        CHECK(*f.st.ground_recall == doctest::Approx(4.0 / 5.0));
    }
}

TEST_CASE("white fusion of a tiled view hands each band on as it is cast") {
    const Fused f = fuse(1, 1, 2, true, nullptr);
    checkOrder(f);
    CHECK(f.calls == std::vector<std::size_t>{3, 3, 3, 2});  // a row at a time
    CHECK_FALSE(f.st.pipelined);
    for (const core::CloudPoint& p : f.points) CHECK(p.rgb == core::kWhite);
    CHECK(f.st.ground_found == 0);
    CHECK_FALSE(f.st.ground_precision.has_value());
}
