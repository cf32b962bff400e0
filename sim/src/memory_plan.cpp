// sim/src/memory_plan.cpp: see memory_plan.hpp. Byte counts are upper bounds of what the
// generator's buffers hold (vector capacities reserved up front, not grown).
#include "memory_plan.hpp"

#include <sim/memory_budget.hpp>

#include <core/error.hpp>
#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <sys/statvfs.h>

namespace sim {
namespace {

constexpr std::uint64_t kPointBytes = sizeof(core::CloudPoint);
constexpr std::uint64_t kDirBytes = sizeof(glm::dvec3);
// RANSAC of one view, per hit it may see: the positions handed to findGround (12), its
// band indices with vector growth (8), PCL's cloud (16), PC's indices (4), inlier lists
// (8), flags (2), rounded up for PCL's own bookkeeping.
constexpr std::uint64_t kRansacBytesPerHit = 64;
constexpr std::uint64_t kThreadBytes = 128u
                                       << 10;  // a worker's stack and allocator arena in use (measured below 100 KiB)
constexpr std::uint64_t kWriterBytes = (8u << 20) + (64u << 10);  // io::CloudWriter's buffer
constexpr std::uint64_t kMinColourChunk = 4096;
constexpr std::uint64_t kMaxColourChunk = 1u << 20;

std::string mebibytes(std::uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20); }

// Largest n in [1, hi] with fits(n), given fits is monotone (true, then false); 0 if none.
template <class Fits>
std::uint64_t largest(std::uint64_t hi, const Fits& fits) {
    if (hi == 0 || !fits(1)) return 0;
    std::uint64_t lo = 1;
    while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo + 1) / 2;
        if (fits(mid))
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

}  // namespace

std::size_t memoryBudgetBytes(double memory_mb, std::string_view command) {
    if (!(std::isfinite(memory_mb) && memory_mb >= 1.0 && memory_mb <= 1048576.0))
        throw core::Error(std::string(command) + ": --memory-mb = " + core::shownNumber(memory_mb) +
                          ": allowed [1, 1048576]");
    return std::size_t(memory_mb * 1048576.0);
}

void refuseOverBudget(std::string_view command, std::uint64_t budget_bytes, std::uint64_t need_bytes,
                      const std::string& why, const std::string& advice) {
    if (need_bytes <= budget_bytes) return;
    char budget_mb[32];
    std::snprintf(budget_mb, sizeof budget_mb, "%.6g", double(budget_bytes) / 1048576.0);
    throw core::Error(std::string(command) + ": --memory-mb " + budget_mb + " is too small: this run needs at least " +
                      mebibytes(need_bytes) + " MiB (" + why + "); " + advice);
}

std::uint64_t planBytes(const MemoryNeeds& n, std::size_t batch_views, std::size_t band_rows, int threads) {
    const std::uint64_t band_pixels = std::uint64_t(band_rows) * n.xres;
    const bool tiled = band_rows < n.yres;
    // A tiled white view hands its hits on band by band; otherwise a view's hits wait whole.
    const std::uint64_t view_hits =
        n.white && tiled ? std::min(n.view_hits, band_pixels * n.slots_per_pixel) : n.view_hits;
    const std::uint64_t ransac = n.white ? 0
                                         : std::uint64_t(std::min<std::size_t>(std::size_t(threads), batch_views)) *
                                               n.view_hits * kRansacBytesPerHit;
    return n.fixed_bytes + kWriterBytes + band_pixels * kDirBytes +
           std::uint64_t(batch_views) * (band_pixels * n.slots_per_pixel + view_hits) * kPointBytes + ransac +
           std::uint64_t(threads) * (kThreadBytes + n.thread_scratch_bytes);
}

MemoryPlan planMemory(const MemoryNeeds& n) {
    MemoryPlan p;
    const std::uint64_t budget = n.budget_bytes;
    const auto fits = [&](std::size_t batch, std::size_t rows, int threads) {
        return planBytes(n, batch, rows, threads) + kMinColourChunk * kPointBytes <= budget;
    };
    const std::size_t yres = std::size_t(n.yres);
    p.threads = std::max(1, n.threads);
    p.band_rows = yres;
    // 1. Fewer views per batch.
    p.batch_views = std::size_t(largest(std::max<std::size_t>(1, n.batch_views),
                                        [&](std::uint64_t b) { return fits(std::size_t(b), yres, p.threads); }));
    if (p.batch_views == 0) {
        p.batch_views = 1;
        // 2. Bands of rows.
        p.band_rows = std::size_t(largest(yres, [&](std::uint64_t r) { return fits(1, std::size_t(r), p.threads); }));
        if (p.band_rows == 0) {
            // 3. Fewer threads, then bands as wide as those threads leave room for.
            p.threads = int(largest(std::uint64_t(p.threads), [&](std::uint64_t t) { return fits(1, 1, int(t)); }));
            if (p.threads == 0) {
                const std::uint64_t need = planBytes(n, 1, 1, 1) + kMinColourChunk * kPointBytes;
                std::string why =
                    n.white ? "one row of " + std::to_string(n.xres) + " pixels on one thread"
                            : "one view's up to " + std::to_string(n.view_hits) + " hits, whitened together by RANSAC";
                refuseOverBudget(
                    "generate", budget, std::max(need, budget + 1), why,
                    "raise --memory-mb" + (n.white ? std::string() : ", lower --xres/--yres, or use --white"));
            }
            p.band_rows =
                std::size_t(largest(yres, [&](std::uint64_t r) { return fits(1, std::size_t(r), p.threads); }));
        }
    }
    p.fuse_bytes = planBytes(n, p.batch_views, p.band_rows, p.threads);
    p.view_hits =
        n.white && p.band_rows < yres ? std::min(n.view_hits, std::uint64_t(p.band_rows) * n.xres) : n.view_hits;
    // Spooled runs read the cloud back in chunks once the fusion's buffers are freed; the
    // workers stay.
    const std::uint64_t kept = n.fixed_bytes + kWriterBytes + std::uint64_t(p.threads) * kThreadBytes;
    const std::uint64_t chunk_room = (budget - std::min(budget, kept)) / kPointBytes;
    p.colour_chunk = std::size_t(std::clamp(chunk_room, kMinColourChunk, kMaxColourChunk));
    p.kept_bytes = kept;
    p.writer_bytes = kWriterBytes;
    return p;
}

void checkFreeSpace(const std::filesystem::path& dir, std::uint64_t need_bytes, const char* what) {
    struct statvfs fs{};
    const std::filesystem::path where = dir.empty() ? std::filesystem::path(".") : dir;
    if (::statvfs(where.c_str(), &fs) != 0)
        throw core::Error("output: " + where.string() + ": cannot read the free space: " + std::strerror(errno));
    const std::uint64_t free_bytes = std::uint64_t(fs.f_bavail) * std::uint64_t(fs.f_frsize);
    if (free_bytes < need_bytes)
        throw core::Error("output: " + where.string() + ": " + mebibytes(free_bytes) + " MiB free, but " + what +
                          " may need " + mebibytes(need_bytes) + " MiB; free space or write elsewhere");
}

}  // namespace sim
