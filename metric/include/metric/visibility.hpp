// metric/visibility.hpp: how hard the target is to see in a point cloud (paper §IV-B).
//
// Three white clouds from the generator: P1 the target alone, P2 the environment without
// ground, P3 the target and the environment without ground. For each view of an orbit
// (render/orbit_camera.hpp, the viewer's automatic mode) the binary images I1, I2, I3 of
// P1, P2, P3 are rendered offscreen (EGL surfaceless, GL 4.5 core, square splats) and
//   metric  = |I4| / |I1| with I4 = I2 xor I3       (the paper's definition)
//   visible = |I3 and not I2| / |I1|                (target pixels only; docs/metric.md)
//   depth_visible = |I1 and (a P3 point nearer than every P2 point)| / |I1|
//                                                   (occlusion-aware, compute rasterizer only)
// The exact reference casts a ray through every pixel centre of the same camera against
// the meshes (sim::RayCaster): the fraction of target pixels (hit the target in the
// target-only scene) whose first hit in target + environment (no ground) is the target.
// The final figures are means over the views whose |I1| > 0.
#pragma once
#include <core/point_cloud.hpp>
#include <core/scene.hpp>
#include <render/orbit_camera.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace metric {

/// The three clouds of §IV-B. They may carry different origins (files from elsewhere);
/// the evaluator brings them into one local frame in double precision.
struct MetricClouds {
    core::PointCloud p1;  // target only
    core::PointCloud p2;  // environment without ground
    core::PointCloud p3;  // target + environment without ground
};

/// How the square splats are drawn (same pixels either way, see docs/metric.md).
enum class Rasterizer {
    Compute,  // a compute shader ORs each point's bit into an integer mask (fast on llvmpipe)
    Raster,   // GL_POINTS with gl_PointSize, as the viewer draws (render::PointSplatRenderer)
};

/// Options of one evaluation; defaults chosen from `ladarvr bench metric` (docs/metric.md).
struct MetricOptions {
    render::OrbitCameraOptions orbit;         // radius, altitude, vfov (30 deg), views (100)
    std::optional<glm::dvec3> look_at_world;  // orbit centre and look-at, world metres;
                                              // default: the centre of the target's bounds
    int width = 512;                          // image size, pixels (16..8192)
    int height = 512;
    double splat_px = 2.0;  // square splat side, pixels [1, 64]
    bool skip = true;       // render/count only the target's screen
                            // rectangle; skip views whose frustum misses it
    bool exact = true;      // compute the exact reference (needs a scene)
    int picture_view = -1;  // view whose I1..I4 are kept (full frame); -1 none
    Rasterizer rasterizer = Rasterizer::Compute;
    double depth_margin_m = 0.5;  // depth-aware variant: a P3 point counts as
                                  // target when nearer than every P2 point of
                                  // its pixel by more than this [0, 100] m
    /// When not empty, the views are these cameras (world frame, e.g. an operator's head
    /// path, metric/trace.hpp) instead of the orbit's; orbit.vfov_deg, near_m and far_m
    /// still apply. At most kMaxPoses.
    std::vector<render::CameraPose> poses_world;
};
inline constexpr std::size_t kMaxPoses = 1000000;

/// Throws core::Error("metric: --<option> = <value>: allowed <range>") for bad options
/// (the orbit's fields through render::validate). `views` is options.orbit.views.
void validate(const MetricOptions& options);

/// |I4| / |I1| (paper §IV-B); NaN when i1 == 0 (the view is reported and left out).
double ratio(std::int64_t numerator, std::int64_t i1);

/// Per-view result. Poses are in the local frame of MetricResult::origin.
struct ViewResult {
    int view = 0;
    render::CameraPose pose;
    render::PixelRect rect;  // pixels rendered and counted
    std::int64_t i1 = 0, i2 = 0, i3 = 0, i4 = 0;
    std::int64_t visible_px = 0;         // |I3 and not I2|
    std::int64_t depth_visible_px = -1;  // -1 with the raster rasterizer
    double metric = 0.0;                 // NaN when i1 == 0
    double visible = 0.0;                // NaN when i1 == 0
    double depth_visible = 0.0;          // NaN when i1 == 0 or not computed
    std::int64_t exact_target_px = 0;    // rays through pixel centres hitting the target
    std::int64_t exact_visible_px = 0;   // ... whose first hit with the environment is it
    double exact = 0.0;                  // NaN when absent or exact_target_px == 0
    bool used = false;                   // i1 > 0: counted in the means
    bool frustum_skipped = false;        // skip: target bounds outside the view
    double seconds_render = 0.0;         // this view's splats + counting (+ picture)
    double seconds_exact = 0.0;          // this view's exact ray casting
};

/// Full-frame binary images of the picture view, rows bottom-up (GL order), 0 or 255.
struct MetricPictures {
    int view = -1;
    int width = 0, height = 0;
    std::vector<std::uint8_t> i1, i2, i3, i4;
};

struct MetricResult {
    glm::dvec3 origin{0.0};   // world = origin + local
    glm::dvec3 look_at{0.0};  // local frame
    MetricOptions options;
    std::vector<ViewResult> views;
    int views_used = 0;
    double metric_mean = 0.0, metric_min = 0.0, metric_max = 0.0;  // NaN if no view used
    double visible_mean = 0.0;
    double depth_visible_mean = 0.0;  // NaN with the raster rasterizer
    double exact_mean = 0.0;          // NaN when absent; mean over views used with exact
    bool has_exact = false;
    std::optional<MetricPictures> pictures;
    double seconds_render = 0.0;   // splat rendering + GPU counting, all views
    double seconds_exact = 0.0;    // ray casting, all views
    double seconds = 0.0;          // the whole run()
    std::size_t points_drawn = 0;  // over all views and clouds
};

/// Holds a headless GL context with the three clouds uploaded and, when a scene is given,
/// the two Embree scenes of the exact reference, so that many option sets can be
/// evaluated (the benchmark). Create, run and destroy on one thread.
class Evaluator {
  public:
    /// Throws core::Error("metric: P1 is empty ...") if P1 has no point, ("egl: ...") if
    /// no headless GL context can be made. `scene` (may be null) is only used during
    /// construction; P2/P3 may be empty (nothing hides the target).
    Evaluator(const MetricClouds& clouds, const core::Scene* scene);
    ~Evaluator();
    Evaluator(const Evaluator&) = delete;
    Evaluator& operator=(const Evaluator&) = delete;

    /// Evaluates every view of options.orbit (or options.poses_world). Throws core::Error
    /// for invalid options.
    MetricResult run(const MetricOptions& options);

    /// Whether the exact reference is available (a scene with a target was given).
    bool hasExact() const;
    glm::dvec3 origin() const;

    struct Impl;

  private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace metric
