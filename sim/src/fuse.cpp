// sim/src/fuse.cpp: the generator's fusion (paper §III-B: NoV views fused; §III-C steps
// 1-3: each view's ground whitened on its own, seeded per view). Views are cast in
// batches; for a batch, the rays of every (view, block of pixels) task are traced in
// parallel into per-pixel slots, each view's hits are compacted in pixel order, whitened
// and handed on in view order. Where the budget holds a second batch, a batch is
// whitened among the next batch's casting tasks and handed on by a thread of its own
// while the batch after is cast (docs/generator.md).
#include "fuse.hpp"

#include <algorithm>
#include <chrono>
#include <future>

namespace sim {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr std::size_t kBlockRays = 4096;  // rays per task: one slot range per task

}  // namespace

FusePipeline::FusePipeline(const FuseSetup& setup, Workers& pool, GenerateStats& st, std::uint64_t emit_bytes,
                           const FusePacking* packing, const FuseEmit& emit)
    : setup_(setup),
      pool_(pool),
      st_(st),
      packing_(packing),
      emit_(emit),
      xres_(std::size_t(setup.orbit.xres)),
      yres_(std::size_t(setup.orbit.yres)),
      views_(std::size_t(setup.orbit.views)),
      batch_views_(setup.plan.batch_views),
      band_rows_(setup.plan.band_rows),
      band_pixels_(setup.plan.band_rows * std::size_t(setup.orbit.xres)),
      dirs_row_(std::size_t(setup.orbit.yres)) {
    const MemoryPlan& plan = setup.plan;
    // A tiled view is alone in its batch (the plan tiles only then); white, it needs no
    // RANSAC, so its hits are handed on band by band instead of waiting for the whole view.
    emit_per_band_ = setup.white && band_rows_ < yres_;
    // Pipelined when the budget holds a second batch of hits and there is a second core:
    // a batch is whitened by the workers among the next batch's casting tasks, then handed
    // on (packed and spooled when streamed) by a thread of its own while the batch after
    // is cast. Otherwise each batch is whitened, then handed on, before the next is cast.
    const std::uint64_t second_batch = std::uint64_t(batch_views_) * plan.view_hits * sizeof(core::CloudPoint);
    pipelined_ =
        !emit_per_band_ && plan.threads >= 2 && plan.fuse_bytes + emit_bytes + second_batch <= setup.budget_bytes;
    st_.pipelined = pipelined_;
    dirs_.resize(band_pixels_);
    slots_.resize(batch_views_ * band_pixels_ * setup.slots_per_pixel);
    for (std::size_t b = 0; b < (pipelined_ ? 2u : 1u); ++b) {
        Batch& batch = batches_[b];
        batch.points.resize(batch_views_);
        for (auto& v : batch.points) v.reserve(std::size_t(plan.view_hits));
        batch.missed.resize(batch_views_);
        batch.ground.resize(batch_views_);
        batch.tally.resize(batch_views_);
        batch.tally_s.resize(batch_views_);
        batch.packed.resize(batch_views_);
    }
    if (setup.progress) progress_.emplace("generate", views_);
    whitens_ = !setup.white && setup.view_filter;
    // Pipelined, where the budget also holds both batches' records, the worker that
    // whitens a view packs it too, and the handing thread only appends the records.
    const std::uint64_t packed_bytes = packing && packing->bytes_per_point > 0
                                           ? 2 * std::uint64_t(batch_views_) * plan.view_hits * packing->bytes_per_point
                                           : 0;
    pack_on_workers_ = pipelined_ && whitens_ && packed_bytes > 0 &&
                       plan.fuse_bytes + emit_bytes + second_batch + packed_bytes <= setup.budget_bytes;
    st_.packed_on_workers = pack_on_workers_;
    whiten_s_.resize(batch_views_);
}

void FusePipeline::run() {
    // Pipelined: the batch compacted last (`waiting`), whitened by the workers among the
    // next batch's casting tasks, then handed on by a thread of its own (`handing`,
    // declared last, so that leaving early waits for it before what it uses goes) while
    // the batch after is cast.
    Batch* waiting = nullptr;
    std::future<void> handing;
    std::size_t cur = 0;
    for (std::size_t first = 0; first < views_; first += batch_views_) {
        Batch& batch = batches_[cur];
        const std::size_t count = std::min(batch_views_, views_ - first);
        for (std::size_t row0 = 0; row0 < yres_; row0 += band_rows_) {
            const std::size_t rows = std::min(band_rows_, yres_ - row0);
            castBand(first, count, row0, rows, waiting);
            const auto t0 = Clock::now();
            if (row0 == 0) {
                // The batch this one's buffers held before (two batches ago) must be handed on.
                if (handing.valid()) handing.get();
                startBatch(batch, first, count);
            }
            compactBand(batch, rows);
            st_.seconds.fuse += secondsSince(t0);
        }
        for (std::size_t k = 0; k < count; ++k) {
            st_.rays_traced += setup_.traced_count[first + k];
            st_.sub_rays_traced += setup_.traced_count[first + k] * setup_.rays_per_pixel;
        }
        if (emit_per_band_) {
            if (progress_) progress_->advance(count);
            continue;
        }
        if (!pipelined_) {
            whitenAll(batch);
            handOn(batch);
            continue;
        }
        if (waiting) handing = std::async(std::launch::async, [this, b = waiting] { handOn(*b); });
        waiting = &batch;
        cur ^= 1;
    }
    if (waiting) {
        whitenAll(*waiting);
        if (handing.valid()) handing.get();
        handOn(*waiting);
    }
    finish();
}

// The tally of `pts`, once their ground is found.
FusePipeline::Tally FusePipeline::tallyOf(std::span<const core::CloudPoint> pts) const {
    Tally t;
    for (const auto& p : pts) {
        t.z_min = std::min(t.z_min, p.position.z);
        t.z_max = std::max(t.z_max, p.position.z);
        const bool truth = p.label == core::Role::Ground;
        const bool found = !setup_.white && p.rgb == core::kWhite;
        t.truth += truth;
        t.found += found;
        t.true_positive += truth && found;
    }
    return t;
}

// Counts `pts` (their tally, and `missed` pixels without a return) into the stats and
// hands them on.
void FusePipeline::fuse(const std::vector<core::CloudPoint>& pts, std::size_t missed, const Tally& t,
                        std::span<const unsigned char> packed) {
    st_.misses += missed;
    st_.points += pts.size();
    z_min_ = std::min(z_min_, t.z_min);
    z_max_ = std::max(z_max_, t.z_max);
    st_.ground_truth += t.truth;
    st_.ground_found += t.found;
    st_.ground_true_positive += t.true_positive;
    emit_(pts, packed);
}

// Whitens view k of a batch (RANSAC on its points, PG turned white), tallies it and,
// where the workers pack, packs it; returns the seconds the whitening took (the tally's
// and the packing's are in batch.tally_s).
double FusePipeline::whiten(Batch& batch, std::size_t k) {
    const auto t0 = Clock::now();
    auto& pts = batch.points[k];
    if (pts.size() < 3) {  // the band cannot hold 3 points: no RANSAC, no copy
        batch.ground[k] = GroundStats{};
        batch.ground[k].band_points = pts.size();
    } else {
        std::vector<glm::vec3> positions(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) positions[i] = pts[i].position;
        const std::uint64_t view = batch.first + k;
        const auto is_ground = setup_.view_filter->classifyView(positions, setup_.seed ^ view, &batch.ground[k]);
        for (std::size_t i = 0; i < pts.size(); ++i)
            if (is_ground[i]) pts[i].rgb = core::kWhite;
    }
    const auto t1 = Clock::now();
    batch.tally[k] = tallyOf(pts);
    if (pack_on_workers_) {
        batch.packed[k].resize(pts.size() * packing_->bytes_per_point);
        packing_->pack(pts, batch.packed[k].data());
    }
    batch.tally_s[k] = secondsSince(t1);
    return std::chrono::duration<double>(t1 - t0).count();
}

// The share of a batch's tallies in the workers' time: fusing, not whitening.
double FusePipeline::tallyShare(const Batch& batch) const {
    double sum = 0.0;
    for (std::size_t k = 0; k < batch.count; ++k) sum += batch.tally_s[k];
    return sum / double(setup_.plan.threads);
}

// Whitens a whole batch on the workers.
void FusePipeline::whitenAll(Batch& batch) {
    if (!whitens_) return;
    const auto t0 = Clock::now();
    pool_.run(batch.count, [&](std::size_t k) { whiten(batch, k); });
    const double tally_s = tallyShare(batch);
    ground_s_ += std::max(0.0, secondsSince(t0) - tally_s);
    tallied_s_ += tally_s;
}

// Hands a whitened batch on in view order.
void FusePipeline::handOn(Batch& batch) {
    const auto t0 = Clock::now();
    for (std::size_t k = 0; k < batch.count; ++k) {
        if (whitens_) {
            st_.planes_accepted += batch.ground[k].planes_accepted;
            st_.planes_rejected += batch.ground[k].planes_rejected;
            st_.views_without_ransac += batch.ground[k].band_points < 3;
        }
        fuse(batch.points[k], batch.missed[k], whitens_ ? batch.tally[k] : tallyOf(batch.points[k]),
             pack_on_workers_ ? std::span<const unsigned char>(batch.packed[k]) : std::span<const unsigned char>());
    }
    handed_s_ += secondsSince(t0);
    if (progress_) progress_->advance(batch.count);
}

// Casts rows [row0, row0 + rows) of views [first, first + count) into the slots. Tasks
// are the blocks of kBlockRays pixels of the whole view cut to this band (bands start on
// rows), so a tiled view makes the very same ray calls; with the first band go the
// waiting batch's views to whiten, first.
void FusePipeline::castBand(std::size_t first, std::size_t count, std::size_t row0, std::size_t rows, Batch* waiting) {
    const std::size_t p0 = row0 * xres_, p1 = p0 + rows * xres_;
    const auto t0 = Clock::now();
    if (dirs_row_ != row0) {
        for (std::size_t py = row0; py < row0 + rows; ++py)
            for (std::size_t px = 0; px < xres_; ++px)
                dirs_[(py - row0) * xres_ + px] = pixelDirection(setup_.orbit, double(px), double(py));
        dirs_row_ = row0;
    }
    const std::size_t block0 = p0 / kBlockRays, blocks = (p1 + kBlockRays - 1) / kBlockRays - block0;
    const std::size_t whiten_tasks = row0 == 0 && waiting && whitens_ ? waiting->count : 0;
    const std::size_t slots_per_view = band_pixels_ * setup_.slots_per_pixel;
    pool_.run(whiten_tasks + count * blocks, [&](std::size_t task) {
        if (task < whiten_tasks) {
            whiten_s_[task] = whiten(*waiting, task);
            return;
        }
        task -= whiten_tasks;
        const std::size_t k = task / blocks, block = block0 + task % blocks;
        const FuseBand band{dirs_.data(), slots_.data() + k * slots_per_view, p0};
        setup_.cast_block(int(first + k), std::max(p0, block * kBlockRays), std::min(p1, (block + 1) * kBlockRays),
                          band);
    });
    // The whitening's share of the run: its tasks' time over the workers (the tallies in
    // them are fusing's).
    double share_s = 0.0;
    for (std::size_t k = 0; k < whiten_tasks; ++k) share_s += whiten_s_[k];
    share_s /= double(setup_.plan.threads);
    const double tally_s = whiten_tasks > 0 ? tallyShare(*waiting) : 0.0;
    ground_s_ += share_s;
    tallied_s_ += tally_s;
    st_.seconds.cast += std::max(0.0, secondsSince(t0) - share_s - tally_s);
}

// Views [first, first + count) take the batch's buffers, emptied.
void FusePipeline::startBatch(Batch& batch, std::size_t first, std::size_t count) {
    batch.first = first;
    batch.count = count;
    for (std::size_t k = 0; k < count; ++k) {
        batch.points[k].clear();
        batch.missed[k] = 0;
    }
}

// Appends each view's returns in the band's slots to its points, in pixel order, and
// counts its pixels without any; white and tiled, hands the band's points on at once.
void FusePipeline::compactBand(Batch& batch, std::size_t rows) {
    pool_.run(batch.count, [&](std::size_t k) {
        auto& out = batch.points[k];
        const std::size_t n = setup_.slots_per_pixel;
        const core::CloudPoint* s = slots_.data() + k * band_pixels_ * n;
        for (std::size_t i = 0; i < rows * xres_; ++i) {
            bool missed = true;
            for (std::size_t r = i * n; r < (i + 1) * n; ++r)
                if (s[r].range_m != kNoReturn) {
                    missed = false;
                    out.push_back(s[r]);
                    if (setup_.white) out.back().rgb = core::kWhite;
                }
            batch.missed[k] += missed;
        }
    });
    if (emit_per_band_) {
        fuse(batch.points[0], batch.missed[0], tallyOf(batch.points[0]), {});
        batch.points[0].clear();
        batch.missed[0] = 0;
    }
}

// The stage seconds, the rays, the z range and the ground's precision and recall.
void FusePipeline::finish() {
    st_.seconds.ground += ground_s_;
    st_.seconds.fuse += handed_s_ + tallied_s_;
    if (progress_) progress_->finish();
    st_.rays = std::uint64_t(xres_ * yres_) * views_;
    if (st_.points > 0) {
        st_.z_min = z_min_;
        st_.z_max = z_max_;
    }
    if (!setup_.white) {
        if (st_.ground_found > 0) st_.ground_precision = double(st_.ground_true_positive) / double(st_.ground_found);
        if (st_.ground_truth > 0) st_.ground_recall = double(st_.ground_true_positive) / double(st_.ground_truth);
    }
}

}  // namespace sim
