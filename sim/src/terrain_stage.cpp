// sim/src/terrain_stage.cpp: see terrain_stage.hpp.
#include "terrain_stage.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace sim {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

TerrainStage::TerrainStage(const CloudGroundFilter* filter, const SmrfOptions& check_options, bool white, bool check) {
    if (white) return;
    if (filter) {
        fit_ = filter->startCloud();
        whitens_ = true;
    } else if (check) {
        fit_ = startSmrf(check_options);
    }
}

void TerrainStage::add(std::span<const core::CloudPoint> points) {
    if (!fit_ || failed_) return;
    const auto t0 = Clock::now();
    if (!whitens_) {  // the check: every kCheckStride-th point of the cloud
        sample_.clear();
        const std::size_t first = (kCheckStride - added_ % kCheckStride) % kCheckStride;
        for (std::size_t i = first; i < points.size(); i += kCheckStride) sample_.push_back(points[i]);
        added_ += points.size();
        points = sample_;
    }
    try {
        fit_->add(points);
    } catch (const core::Error&) {
        if (whitens_) throw;
        failed_ = true;  // only a check: a cloud too wide for its raster goes unchecked
    }
    add_seconds_ += secondsSince(t0);
}

void TerrainStage::fit() {
    if (!fit_ || failed_) return;
    const auto t0 = Clock::now();
    try {
        fit_->fit();
    } catch (const core::Error&) {
        if (whitens_) throw;
        failed_ = true;
    }
    seconds_ += secondsSince(t0);
}

void TerrainStage::classify(std::span<core::CloudPoint> points, Workers& pool) {
    if (!fit_ || failed_) return;
    const auto t0 = Clock::now();
    constexpr std::size_t kChunk = 1u << 16;
    const std::size_t tasks = (points.size() + kChunk - 1) / kChunk;
    std::vector<std::array<std::uint64_t, 4>> counts(tasks, {0, 0, 0, 0});
    const TerrainFit& fit = *fit_;
    const bool whitens = whitens_;
    const std::size_t stride = whitens ? 1 : kCheckStride;
    const std::size_t first = (stride - classified_ % stride) % stride;  // of the sample, in `points`
    classified_ += points.size();
    pool.run(tasks, [&](std::size_t task) {
        auto& c = counts[task];
        const std::size_t end = std::min(points.size(), (task + 1) * kChunk);
        std::size_t i = task * kChunk;
        i += (first + stride - i % stride) % stride;
        for (; i < end; i += stride) {
            core::CloudPoint& p = points[i];
            float height_m = 0;
            const bool ground = fit.classify(p, height_m);
            if (whitens) {
                p.height_above_ground_m = height_m;
                if (ground) {
                    p.rgb = core::kWhite;
                    c[0] += 1;
                    c[1] += p.label == core::Role::Ground;
                }
            }
            // RANSAC's check: the points on the fitted terrain that RANSAC left coloured. A
            // whitening filter: the points within kNearTerrain_m of its own terrain that it
            // left coloured (a ground thicker than its tolerance).
            const bool near = whitens ? std::abs(height_m) <= kNearTerrain_m : ground;
            if (near) {
                c[2] += 1;
                c[3] += p.rgb != core::kWhite;
            }
        }
    });
    for (const auto& c : counts) {
        found_ += c[0];
        true_positive_ += c[1];
        terrain_ += c[2];
        terrain_coloured_ += c[3];
    }
    seconds_ += secondsSince(t0);
}

void TerrainStage::finish(GenerateStats& st) {
    if (!fit_) return;
    st.seconds.fuse = std::max(0.0, st.seconds.fuse - add_seconds_);
    if (whitens_) {
        st.ground_found = found_;
        st.ground_true_positive = true_positive_;
        st.ground_precision.reset();
        st.ground_recall.reset();
        if (st.ground_found > 0) st.ground_precision = double(st.ground_true_positive) / double(st.ground_found);
        if (st.ground_truth > 0) st.ground_recall = double(st.ground_true_positive) / double(st.ground_truth);
        st.seconds.ground += seconds_ + add_seconds_;
    } else {
        st.seconds.ground_check += seconds_ + add_seconds_;
    }
    if (failed_) return;
    st.terrain_points = terrain_;
    st.terrain_points_coloured = terrain_coloured_;
    st.terrain = std::make_shared<const TerrainGrid>(fit_->surface());
}

}  // namespace sim
