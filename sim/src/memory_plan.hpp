// sim/src/memory_plan.hpp: how a generate run fits GenerateOptions::memory_budget_bytes
// (--memory-mb): views per batch, rows per band, threads; and the free-space check
// before spooling.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>

namespace sim {

/// What a run must hold, from its options and the ray-cast bounds.
struct MemoryNeeds {
    std::uint64_t xres = 1, yres = 1, views = 1;
    std::uint64_t view_hits = 0;             // most hits one view can give (its traced pixels)
    std::uint64_t fixed_bytes = 0;           // per-run tables (poses, traced pixel spans)
    bool white = false;                      // no RANSAC: a tiled view's hits leave band by band
    std::uint64_t slots_per_pixel = 1;       // return slots per pixel (several returns per pulse)
    std::uint64_t thread_scratch_bytes = 0;  // the sensor's per-thread ray buffers
    int threads = 1;                         // requested, resolved (> 0)
    std::size_t batch_views = 1;             // views per batch wanted for speed (<= views)
    std::uint64_t budget_bytes = 0;
};

/// The buffers of one run. Every field is > 0.
struct MemoryPlan {
    std::size_t batch_views = 1;  // views traced, whitened and fused together
    std::size_t band_rows = 1;    // rows of a view traced per pass (yres: untiled)
    int threads = 1;
    std::uint64_t view_hits = 0;     // capacity of one view's hit buffer
    std::uint64_t fuse_bytes = 0;    // everything held while fusing, fixed tables and writer included
    std::size_t colour_chunk = 1;    // points per colour/write chunk read back from a spool
    std::uint64_t kept_bytes = 0;    // held once the fusion is done: tables, writer, workers
    std::uint64_t writer_bytes = 0;  // the cloud writer's share of kept_bytes (at least)
};

/// Plans within needs.budget_bytes: the wanted batch first, then fewer views per batch,
/// then bands of rows (bit-identical output), then fewer threads. Throws
/// core::Error("generate: --memory-mb ...: ...") naming the least that would fit when
/// even one row band of one view on one thread does not.
MemoryPlan planMemory(const MemoryNeeds& needs);

/// The buffers of a plan, in bytes (what planMemory compares with the budget).
std::uint64_t planBytes(const MemoryNeeds& needs, std::size_t batch_views, std::size_t band_rows, int threads);

/// Throws core::Error("output: <dir>: ...") when the filesystem of `dir` has fewer than
/// need_bytes free for an unprivileged writer, saying what needs them (`what`).
void checkFreeSpace(const std::filesystem::path& dir, std::uint64_t need_bytes, const char* what);

}  // namespace sim
