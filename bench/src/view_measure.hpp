// bench/src/view_measure.hpp: the measurements of `ladarvr bench view`, one row per
// configuration: the viewer's real frame loop (desktop mirror, OpenXR) and its offscreen
// stereo drawing (viewer::OffscreenStereo) against an in-run baseline.
#pragma once
#include <core/point_cloud.hpp>
#include <viewer/viewer.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace bench {

/// One measured configuration of `ladarvr bench view`.
struct ViewBenchResult {
    std::string path;  // "mirror", "xr", "stereo-egl" or "skip-egl"
    std::size_t points = 0;
    int width = 0, height = 0;     // per eye (xr, stereo-egl) or the window (mirror)
    double cpu_ms_median = 0.0;    // CPU time to record and submit the frame's draws
    double gpu_ms_median = 0.0;    // GL timer query around the frame's draws
    double frame_ms_median = 0.0;  // wall time of a whole frame (loop period / until glFinish)
    int frames = 0;                // measured frames (after warm-up)
    /// stereo-egl only: the same eyes drawn by render::PointSplatRenderer (the metric's plain
    /// 2 px splats: no eye-dome lighting, no colour modes), the in-run baseline; 0 if not run.
    double baseline_gpu_ms_median = 0.0;
    std::string gl;                // GL vendor / renderer / version
    std::string note;              // why a path was skipped, or what it stands for
    std::size_t points_drawn = 0;  // per frame, both eyes (skip-egl rows)
};

struct ViewBenchOptions {
    int warmup_frames = 3;  // after every point is on the GPU
    int frames = 10;
    bool mirror = true;  // the desktop window (needs a display)
    bool xr = true;      // the OpenXR path (needs a runtime with an HMD)
    bool egl = true;     // offscreen stereo through EGL (no display, any GPU)
    /// Offscreen stereo (EGL) of the orbit view and of a view turned away from the cloud,
    /// each with nothing skipped, frustum culling only, and culling + `point_budget` (LOD),
    /// interleaved frame by frame.
    bool skip = false;
    /// The OpenXR path again with the operator's tools at work (the pointer aimed at the
    /// cloud's centre, a designation, the panel in the headset; then also the cutting
    /// volume), against a run with none of them (no panel in the headset), run after run.
    bool tools = false;
    std::size_t point_budget = 3000000;
    int eye_width = 1440, eye_height = 1600;  // stereo-egl eye size (Index / Vive Pro class)
    /// The offscreen stereo rows (egl, skip) once per rasterizer, in this order.
    std::vector<viewer::Rasterizer> rasterizers = {viewer::Rasterizer::Points};
};

/// Measures the viewer drawing `cloud` (entirely uploaded before measuring, eye-dome
/// lighting on): the real frame loop in the desktop mirror path and the OpenXR path, and
/// the same per-eye drawing in an offscreen EGL stereo loop; medians over `frames` frames
/// after warm-up. A path that cannot run here is returned with `note` saying why.
/// Throws core::Error("bench view: ...") for frames or eye sizes out of range.
std::vector<ViewBenchResult> measureViewer(const core::PointCloud& cloud, const ViewBenchOptions& options);

}  // namespace bench
