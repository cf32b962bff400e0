// tests/sim/memory_plan_test.cpp: --memory-mb bounds a generate run (sim/src/memory_plan.hpp
// and the generator's batches, tiles and threads): tiled runs are bit-identical to
// untiled ones, and runs that cannot fit are refused naming the option. The CLI's peak RSS
// within the budget is measured in generate_cli_test.cpp.
#include <test_files.hpp>
#include "memory_plan.hpp"
#include <scene_builders.hpp>

#include <sim/generator.hpp>

#include <core/error.hpp>
#include <io/cloud_io.hpp>

#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <sys/mount.h>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kMiB = 1u << 20;

sim::MemoryNeeds needs(std::uint64_t xres, std::uint64_t yres, std::uint64_t views, bool white, int threads,
                       std::uint64_t budget) {
    sim::MemoryNeeds n;
    n.xres = xres;
    n.yres = yres;
    n.views = views;
    n.view_hits = xres * yres;
    n.white = white;
    n.threads = threads;
    n.batch_views = std::size_t(std::min<std::uint64_t>(views, 2 * std::uint64_t(threads)));
    n.budget_bytes = budget;
    return n;
}

bool identical(const core::PointCloud& a, const core::PointCloud& b) {
    return a.origin == b.origin && a.points.size() == b.points.size() &&
           std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(core::CloudPoint)) == 0;
}

}  // namespace

TEST_CASE("memory plan: a roomy budget keeps the wanted batch, untiled, every thread") {
    const auto n = needs(128, 128, 100, false, 4, 512 * kMiB);
    const sim::MemoryPlan p = sim::planMemory(n);
    CHECK(p.batch_views == 8);
    CHECK(p.band_rows == 128);
    CHECK(p.threads == 4);
    CHECK(p.fuse_bytes == sim::planBytes(n, 8, 128, 4));
    CHECK(p.fuse_bytes <= n.budget_bytes);
}

TEST_CASE("memory plan: fewer views per batch, then row bands, then fewer threads, always within the budget") {
    // 512 x 512 views with RANSAC: ~34 MiB a view untiled, 512 threads wanted.
    auto n = needs(512, 512, 2048, false, 512, 0);
    n.batch_views = 1024;
    for (const std::uint64_t mib : {4096u, 512u, 128u, 40u, 36u}) {
        n.budget_bytes = mib * kMiB;
        const sim::MemoryPlan p = sim::planMemory(n);
        CAPTURE(mib);
        CHECK(p.fuse_bytes <= n.budget_bytes);
        CHECK(p.batch_views >= 1);
        CHECK(p.band_rows >= 1);
        CHECK(p.threads >= 1);
        if (mib == 4096) CHECK(p.batch_views > 8);
        if (mib == 128) {
            CHECK(p.batch_views < 8);
            CHECK(p.band_rows == 512);
        }
        if (mib <= 40) {
            CHECK(p.batch_views == 1);
            CHECK((p.band_rows < 512 || p.threads < 512));
        }
    }
    // --threads 1024 against a small budget: clamped, not refused.
    auto t = needs(64, 64, 10, true, 1024, 12 * kMiB);
    const sim::MemoryPlan p = sim::planMemory(t);
    CHECK(p.threads < 1024);
    CHECK(p.threads >= 1);
    CHECK(p.fuse_bytes <= t.budget_bytes);
}

TEST_CASE("memory plan: a run that cannot fit is refused in one line naming --memory-mb") {
    // 65536 x 65536 with RANSAC: one view's hits alone are hundreds of GiB.
    const auto huge = needs(65536, 65536, 1, false, 2, 512 * kMiB);
    CHECK_THROWS_WITH_AS(sim::planMemory(huge), doctest::Contains("generate: --memory-mb 512 is too small"),
                         core::Error);
    try {
        sim::planMemory(huge);
    } catch (const core::Error& e) {
        const std::string m = e.what();
        CHECK(m.find('\n') == std::string::npos);
        CHECK(m.find("needs at least 4259") != std::string::npos);  // ~416 GiB
        CHECK(m.find("--white") != std::string::npos);
    }
    // White, the same view is traced in bands and fits.
    const sim::MemoryPlan white = sim::planMemory(needs(65536, 65536, 1, true, 2, 512 * kMiB));
    CHECK(white.band_rows < 65536);
    CHECK(white.band_rows > 10);
    CHECK(white.fuse_bytes <= 512 * kMiB);
    // Even white, 1 MiB cannot hold the writer's buffer.
    CHECK_THROWS_WITH_AS(sim::planMemory(needs(64, 64, 1, true, 1, kMiB)),
                         doctest::Contains("--memory-mb 1 is too small"), core::Error);
}

TEST_CASE("generator: tiled views give the same cloud bit for bit, white and whitened") {
    const core::Scene scene = test_support::townScene(120.0, 1.0);
    for (const bool white : {true, false}) {
        sim::GenerateOptions o;
        o.orbit.xres = 256;
        o.orbit.yres = 192;
        o.orbit.views = 3;
        o.threads = 2;
        o.white = white;
        sim::GenerateStats roomy, tight;
        const core::PointCloud a = sim::generateCloud(scene, o, &roomy);
        o.memory_budget_bytes = (white ? 10 : 14) * kMiB;
        const core::PointCloud b = sim::generateCloud(scene, o, &tight);
        CAPTURE(white);
        CHECK(roomy.band_rows == 192);
        CHECK(tight.band_rows < 192);
        CHECK(tight.band_rows > 1);
        CHECK(tight.batch_views == 1);
        CHECK(tight.memory_planned_bytes <= o.memory_budget_bytes);
        REQUIRE(a.points.size() > 10000);
        CHECK(identical(a, b));
        CHECK(tight.points == roomy.points);
        CHECK(tight.misses == roomy.misses);
        CHECK(tight.ground_found == roomy.ground_found);
    }
}

TEST_CASE("generator: a tiled, spooled file is byte-identical to the roomy in-memory one") {
    const core::Scene scene = test_support::townScene(120.0, 1.0);
    test_support::TempDir dir("memory_plan");
    sim::GenerateOptions o;
    o.orbit.xres = 256;
    o.orbit.yres = 192;
    o.orbit.views = 3;
    o.threads = 2;
    sim::GenerateStats roomy, tight;
    sim::generateToFile(scene, o, dir.path / "roomy.pcd", io::CloudFormat::PcdBinary, &roomy);
    o.memory_budget_bytes = 14 * kMiB;
    sim::generateToFile(scene, o, dir.path / "tight.pcd", io::CloudFormat::PcdBinary, &tight);
    CHECK_FALSE(roomy.streamed);
    CHECK(tight.streamed);
    CHECK(tight.band_rows < 192);
    CHECK(test_support::slurp(dir.path / "roomy.pcd") == test_support::slurp(dir.path / "tight.pcd"));
    CHECK(dir.entries() == 2);  // no spool or temporary file left
}

TEST_CASE("generator: a budget too small is refused before any work, naming --memory-mb") {
    const core::Scene scene = test_support::townScene(40.0, 2.0);
    test_support::TempDir dir("memory_refuse");
    sim::GenerateOptions o;
    o.orbit.xres = o.orbit.yres = 512;
    o.skip_rays = false;  // every pixel may hit: one view's RANSAC needs ~23 MB
    o.memory_budget_bytes = 20 * kMiB;
    CHECK_THROWS_WITH_AS(sim::generateToFile(scene, o, dir.path / "x.pcd", io::CloudFormat::PcdBinary),
                         doctest::Contains("--memory-mb 20 is too small"), core::Error);
    CHECK(dir.entries() == 0);
}

TEST_CASE("free space: a spool larger than the disk's free space stops with one line") {
    test_support::TempDir dir("free_space");
    CHECK_NOTHROW(sim::checkFreeSpace(dir.path, 1, "the spool file"));
    CHECK_THROWS_WITH_AS(sim::checkFreeSpace(dir.path, std::uint64_t(1) << 62, "the spool file"),
                         doctest::Contains("MiB free, but the spool file may need 4398046511104 MiB"), core::Error);
    CHECK_THROWS_WITH_AS(sim::checkFreeSpace(dir.path / "missing", 1, "the spool file"),
                         doctest::Contains("cannot read the free space"), core::Error);
}

TEST_CASE("a streamed run on a nearly full disk stops before writing, with one line and no file left") {
    if (::geteuid() != 0) {
        MESSAGE("skipped: mounting a small tmpfs needs root");
        return;
    }
    test_support::TempDir dir("disk_full");
    if (::mount("tmpfs", dir.path.c_str(), "tmpfs", 0, "size=1m") != 0) {
        MESSAGE("skipped: cannot mount a tmpfs here (" << std::strerror(errno) << ")");
        return;
    }
    const core::Scene scene = test_support::townScene(120.0, 1.0);
    sim::GenerateOptions o;
    o.orbit.xres = 256;
    o.orbit.yres = 192;
    o.orbit.views = 3;
    o.threads = 2;
    o.memory_budget_bytes = 14 * kMiB;  // streams ~3.4 MB (23 bytes a point), more than the 1 MiB free
    // Binary PCD: the points go into the output itself; ASCII PCD: through the spool
    // (22 bytes a point).
    CHECK_THROWS_WITH_AS(sim::generateToFile(scene, o, dir.path / "c.pcd", io::CloudFormat::PcdBinary),
                         doctest::Contains("MiB free, but the output may need 4 MiB"), core::Error);
    CHECK_THROWS_WITH_AS(sim::generateToFile(scene, o, dir.path / "c.pcd", io::CloudFormat::PcdAscii),
                         doctest::Contains("MiB free, but the spool file of the fused cloud may need 4 MiB"),
                         core::Error);
    CHECK(dir.entries() == 0);
    CHECK(::umount(dir.path.c_str()) == 0);
}
