// sim/src/fuse.hpp: the generator's fusion of paper §III-B and §III-C step 1-3: every
// view's rays cast in batches of views (and bands of rows), each view's hits compacted in
// pixel order, whitened by its per-view ground filter and handed on in view order.
// Internal to sim: the generator builds one FusePipeline per run; the casting itself is
// the caller's (FuseSetup::cast_block), so the pipeline runs without Embree in tests.
#pragma once
#include "memory_plan.hpp"
#include "parallel.hpp"

#include <core/point_cloud.hpp>
#include <platform/progress.hpp>
#include <sim/generator.hpp>
#include <sim/ground.hpp>
#include <sim/orbit.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace sim {

/// A band of rows being traced: pixel i (row-major in the view) has its sensor-frame
/// direction in dirs[i - first] and its slots_per_pixel return slots from
/// slots[(i - first) * slots_per_pixel].
struct FuseBand {
    const glm::dvec3* dirs;
    core::CloudPoint* slots;
    std::size_t first;
};

/// How a worker may pack a view's points for the emit callback: the bytes a point takes,
/// and the packing (called on several threads at once).
struct FusePacking {
    std::size_t bytes_per_point = 0;
    std::function<void(std::span<const core::CloudPoint>, unsigned char*)> pack;
};

/// Gets a view's fused points and, where FusePacking let the workers pack them, their
/// records (else none).
using FuseEmit = std::function<void(std::span<const core::CloudPoint>, std::span<const unsigned char>)>;

/// What the fusion reads from the run. `cast_block(view, begin, end, band)` fills the
/// slots of pixels [begin, end) (row-major) of `view`, a slot without a return holding
/// range_m = kNoReturn; it is called on several threads at once.
struct FuseSetup {
    OrbitOptions orbit;                             // xres, yres, views, and the pinhole of pixelDirection
    MemoryPlan plan;                                // views per batch, rows per band, threads, the buffers' bytes
    std::uint64_t budget_bytes = 0;                 // GenerateOptions::memory_budget_bytes
    bool white = false;                             // every point white, no ground filter
    bool progress = false;                          // a platform::Progress bar over the views
    std::uint64_t seed = 1;                         // view v's filter is seeded with seed ^ v
    const ViewGroundFilter* view_filter = nullptr;  // whitens each view; null: none
    std::size_t slots_per_pixel = 1;                // return slots per pixel
    std::size_t rays_per_pixel = 1;                 // rays a traced pixel casts (a beam's sub-rays)
    std::span<const std::uint64_t> traced_count;    // per view, the pixels traced
    std::function<void(int, std::size_t, std::size_t, const FuseBand&)> cast_block;
};

/// Runs every view and hands the fused points, in (view, row, column) order, to `emit`.
/// Points of PG (or all points with --white) carry rgb = kWhite, the others 0.
/// `emit_bytes`: what the points handed on take beside the plan (the fused cloud when it
/// stays in memory); where the budget leaves room for a second batch of hits, a batch is
/// whitened and handed on while the next one is traced. Counts rays, points, misses, the
/// ground found against the labels, the z range and the stage seconds into `st`.
class FusePipeline {
  public:
    /// Plans the pipeline and holds its buffers; `setup`, `pool`, `st`, `packing` and
    /// `emit` must outlive it.
    FusePipeline(const FuseSetup& setup, Workers& pool, GenerateStats& st, std::uint64_t emit_bytes,
                 const FusePacking* packing, const FuseEmit& emit);
    /// Casts, whitens and hands on every view; call once. Rethrows what cast_block, the
    /// filter or `emit` throw, after the thread handing a batch on has stopped.
    void run();

  private:
    // What fusing counts of a view's points: its z range and its ground, true and found.
    struct Tally {
        float z_min = std::numeric_limits<float>::infinity(), z_max = -std::numeric_limits<float>::infinity();
        std::uint64_t truth = 0, found = 0, true_positive = 0;
    };
    // A batch's hits from compaction until they are handed on: two while pipelined.
    struct Batch {
        std::size_t first = 0, count = 0;
        std::vector<std::vector<core::CloudPoint>> points;
        std::vector<std::size_t> missed;  // pixels without a return
        std::vector<GroundStats> ground;
        std::vector<Tally> tally;                        // per view, counted by the worker that whitened it
        std::vector<double> tally_s;                     // per view, the seconds that took
        std::vector<std::vector<unsigned char>> packed;  // per view, its records (FusePacking)
    };

    Tally tallyOf(std::span<const core::CloudPoint> pts) const;
    void fuse(const std::vector<core::CloudPoint>& pts, std::size_t missed, const Tally& t,
              std::span<const unsigned char> packed);
    double whiten(Batch& batch, std::size_t k);
    double tallyShare(const Batch& batch) const;
    void whitenAll(Batch& batch);
    void handOn(Batch& batch);
    void castBand(std::size_t first, std::size_t count, std::size_t row0, std::size_t rows, Batch* waiting);
    void startBatch(Batch& batch, std::size_t first, std::size_t count);
    void compactBand(Batch& batch, std::size_t rows);
    void finish();

    const FuseSetup& setup_;
    Workers& pool_;
    GenerateStats& st_;
    const FusePacking* packing_;
    const FuseEmit& emit_;
    std::size_t xres_, yres_, views_, batch_views_, band_rows_, band_pixels_;
    bool emit_per_band_ = false;    // white and tiled: a band's hits handed on as it is cast
    bool pipelined_ = false;        // a batch whitened and handed on while the next is cast
    bool whitens_ = false;          // a per-view filter runs
    bool pack_on_workers_ = false;  // the worker that whitens a view packs it too
    std::vector<glm::dvec3> dirs_;  // sensor frame, unit, rows [dirs_row_, + band_rows_)
    std::size_t dirs_row_;
    std::vector<core::CloudPoint> slots_;  // per view of a batch, a band's return slots
    std::array<Batch, 2> batches_;
    std::vector<double> whiten_s_;  // per view of the waiting batch, the seconds its whitening took
    std::optional<platform::Progress> progress_;
    float z_min_ = std::numeric_limits<float>::infinity(), z_max_ = -std::numeric_limits<float>::infinity();
    double ground_s_ = 0.0;   // whitening, on the workers
    double handed_s_ = 0.0;   // handing on, by whichever thread does it
    double tallied_s_ = 0.0;  // the whitened views' tallies, on the workers
};

}  // namespace sim
