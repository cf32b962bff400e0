// tests/viewer/points/point_budget_test.cpp: the default point budget by GPU class (GL strings
// of real drivers) and the adaptive budget as a pure function of frame times: lowered at
// once over 90 % of the frame budget, raised only after frames in a row under 70 %, held
// in between, never under its floor nor over its ceiling, the same times giving the
// same budgets.
#include <viewer/point_budget.hpp>

#include <doctest/doctest.h>

#include <vector>

using namespace viewer;

TEST_CASE("the GPU class from GL_RENDERER / GL_VENDOR and its default budget") {
    CHECK(classifyGpu("llvmpipe (LLVM 19.1.7, 256 bits)", "Mesa") == GpuClass::Software);
    CHECK(classifyGpu("softpipe", "Mesa") == GpuClass::Software);
    CHECK(classifyGpu("NVIDIA H100 80GB HBM3/PCIe/SSE2", "NVIDIA Corporation") == GpuClass::Discrete);
    CHECK(classifyGpu("NVIDIA GeForce RTX 4090/PCIe/SSE2", "NVIDIA Corporation") == GpuClass::Discrete);
    CHECK(classifyGpu("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 17.0.6, DRM 3.54)", "AMD") == GpuClass::Discrete);
    CHECK(classifyGpu("AMD Radeon Graphics (radeonsi, renoir, LLVM 15.0.7, DRM 3.49)", "AMD") == GpuClass::Integrated);
    CHECK(classifyGpu("Mesa Intel(R) UHD Graphics 620 (KBL GT2)", "Intel") == GpuClass::Integrated);
    CHECK(classifyGpu("Something New", "Nobody") == GpuClass::Unknown);
    // A software rasterizer keeps the budget that holds the paper's 1.6 M point cloud whole.
    CHECK(defaultPointBudget(GpuClass::Software) == 3000000);
    CHECK(defaultPointBudget(GpuClass::Unknown) == 3000000);
    CHECK(defaultPointBudget(GpuClass::Discrete) > defaultPointBudget(GpuClass::Software));
    CHECK(defaultPointBudget(GpuClass::Integrated) < defaultPointBudget(GpuClass::Software));
    CHECK(std::string(gpuClassName(GpuClass::Discrete)) == "discrete");
    // The compute rasterizer by default where it was measured faster: discrete GPUs only.
    CHECK(computeRasterizerByDefault(GpuClass::Discrete));
    CHECK_FALSE(computeRasterizerByDefault(GpuClass::Software));
    CHECK_FALSE(computeRasterizerByDefault(GpuClass::Integrated));
    CHECK_FALSE(computeRasterizerByDefault(GpuClass::Unknown));
}

TEST_CASE("adaptive budget: late frames lower it at once, then it settles") {
    AdaptiveBudget b(100000, 1000000);
    CHECK(b.budget() == 1000000);
    // 80 % of an 11.1 ms frame: between the two thresholds, held.
    for (int i = 0; i < 10; ++i) CHECK(b.update(8.9, 11.1) == 1000000);
    // Over 90 %: lowered by kDrop on the first late frame.
    CHECK(b.update(10.5, 11.1) == 800000);
    // The next kSettle frames were drawn with the old budget: not judged.
    CHECK(b.update(20.0, 11.1) == 800000);
    CHECK(b.update(20.0, 11.1) == 800000);
    CHECK(b.update(20.0, 11.1) == 640000);
    // Never under the floor however late.
    for (int i = 0; i < 100; ++i) b.update(50.0, 11.1);
    CHECK(b.budget() == 100000);
}

TEST_CASE("adaptive budget: early frames raise it slowly, up to the ceiling") {
    AdaptiveBudget b(100000, 1000000);
    for (int i = 0; i < 3; ++i) b.update(10.5, 11.1);  // down to 800000 (then settling)
    CHECK(b.budget() == 800000);
    // Under 70 %: raised only after kRaiseAfter such frames in a row.
    for (int i = 0; i < AdaptiveBudget::kRaiseAfter - 1; ++i) CHECK(b.update(3.0, 11.1) == 800000);
    CHECK(b.update(3.0, 11.1) == 880000);
    // One frame between the thresholds breaks the run.
    for (int i = 0; i < AdaptiveBudget::kSettle; ++i) b.update(3.0, 11.1);
    for (int i = 0; i < AdaptiveBudget::kRaiseAfter - 1; ++i) b.update(3.0, 11.1);
    CHECK(b.update(8.9, 11.1) == 880000);
    CHECK(b.update(3.0, 11.1) == 880000);
    // Never over the ceiling however early.
    for (int i = 0; i < 200; ++i) b.update(1.0, 11.1);
    CHECK(b.budget() == 1000000);
    // No frame budget (or a bad time): nothing changes.
    CHECK(b.update(50.0, 0.0) == 1000000);
    CHECK(b.update(-1.0, 11.1) == 1000000);
}

TEST_CASE("adaptive budget: the same frame times give the same budgets") {
    const std::vector<double> times = {5, 12, 12, 12, 3, 3, 3, 3, 3, 3, 9, 11, 11, 2, 2, 2, 2, 2, 2, 2, 2};
    AdaptiveBudget a(200000, 3000000), b(200000, 3000000);
    for (double t : times) CHECK(a.update(t, 11.1) == b.update(t, 11.1));
    CHECK(adaptiveFloor(3000000) == 375000);
    CHECK(adaptiveFloor(400000) == 100000);
    CHECK(adaptiveFloor(50000) == 50000);
}

TEST_CASE("budget measure: each rasterizer in turn, the faster per point chosen, its budget from the frame budget") {
    using viewer::BudgetMeasure;
    using viewer::Rasterizer;
    BudgetMeasure m(Rasterizer::Points, true);
    CHECK(m.rasterizer() == Rasterizer::Points);
    m.add(0, 5.0);  // nothing drawn: not counted
    for (int i = 0; i < BudgetMeasure::kSettle + BudgetMeasure::kFrames; ++i) m.add(1000000, 10.0);  // 10 ms / M
    CHECK_FALSE(m.done());
    CHECK(m.rasterizer() == Rasterizer::Compute);
    for (int i = 0; i < BudgetMeasure::kSettle; ++i) m.add(1000000, 100.0);  // settling: not judged
    for (int i = 0; i < BudgetMeasure::kFrames; ++i) m.add(2000000, 5.0);    // 2.5 ms / M
    REQUIRE(m.done());
    const BudgetMeasure::Choice c = m.choice(10.0);
    CHECK(c.rasterizer == Rasterizer::Compute);
    CHECK(c.ms_per_million[0] == doctest::Approx(10.0));
    CHECK(c.ms_per_million[1] == doctest::Approx(2.5));
    // 70 % of 10 ms at 2.5 ms per million points, both eyes: 1.4 M per eye.
    CHECK(c.point_budget == 1400000);
    // A slow GPU gets the least budget, a fast one the most.
    CHECK(m.choice(0.001).point_budget == BudgetMeasure::kLeastBudget);
    CHECK(m.choice(1e6).point_budget == BudgetMeasure::kMostBudget);
    // One rasterizer only (the user chose it): measured alone.
    BudgetMeasure one(Rasterizer::Points, false);
    for (int i = 0; i < BudgetMeasure::kSettle + BudgetMeasure::kFrames; ++i) one.add(500000, 7.0);
    REQUIRE(one.done());
    CHECK(one.choice(10.0).rasterizer == Rasterizer::Points);
    CHECK(one.choice(10.0).ms_per_million[1] < 0.0);
}
