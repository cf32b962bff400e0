// metric/src/visibility.cpp: the visibility metric of paper §IV-B on the GPU, and its
// exact mesh reference on Embree (see metric/visibility.hpp).
//
// Per view (paper §IV-B steps 1-3): the three white clouds are splatted into binary
// images (gpu_images.cpp: by default a compute shader ORs one bit per cloud into an
// integer mask; no depth, the images are binary), then a compute shader counts |I1|, |I2|,
// |I3|, |I2 xor I3| and |I3 and not I2| with shared-memory atomics; only a few integers
// come back. Skips ("skip what a scene doesn't need"): only the target's screen rectangle
// (plus a guard band of half a splat) is drawn and counted, views whose frustum misses
// the target's bounds are not drawn, and point cells outside the rectangle's frustum are
// culled.
#include <metric/visibility.hpp>

#include "gpu_images.hpp"

#include <core/error.hpp>
#include <core/frames.hpp>
#include <render/egl_context.hpp>
#include <render/gl.hpp>
#include <sim/raycaster.hpp>

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace metric {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kCellM = 8.0;  // culling cells: small enough that the target's frustum keeps few

[[noreturn]] void invalid(const std::string& option, double value, const char* allowed) {
    std::ostringstream s;
    s << "metric: --" << option << " = " << value << ": allowed " << allowed;
    throw core::Error(s.str());
}

double seconds(std::chrono::steady_clock::time_point since) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

core::PointCloud toFrame(const core::PointCloud& cloud, const glm::dvec3& origin) {
    core::PointCloud out = cloud;
    out.origin = origin;
    const glm::dvec3 shift = cloud.origin - origin;
    if (shift != glm::dvec3(0.0))
        for (auto& p : out.points) p.position = glm::vec3(glm::dvec3(p.position) + shift);
    return out;
}

}  // namespace

void validate(const MetricOptions& o) {
    // Named after the CLI options (cmd_metric.cpp maps them one to one).
    const auto& c = o.orbit;
    if (c.views < 1 || c.views > 65535) invalid("views", c.views, "1..65535");
    // The eye is a float position relative to the scene's origin: beyond
    // core::kMaxLocalCoordinate_m the camera steps by metres and the target leaves the frame.
    constexpr double kMax_m = core::kMaxLocalCoordinate_m;
    if (!std::isfinite(c.radius_m) || c.radius_m <= 0.0 || c.radius_m > kMax_m)
        invalid("radius-m", c.radius_m, "(0, 1e7] metres");
    if (!std::isfinite(c.altitude_m) || std::abs(c.altitude_m) > kMax_m)
        invalid("altitude-m", c.altitude_m, "[-1e7, 1e7] metres");
    if (!std::isfinite(c.vfov_deg) || c.vfov_deg <= 0.0 || c.vfov_deg > 170.0)
        invalid("vfov-deg", c.vfov_deg, "(0, 170] degrees");
    if (o.width < 16 || o.width > 8192) invalid("width", o.width, "16..8192 pixels");
    if (o.height < 16 || o.height > 8192) invalid("height", o.height, "16..8192 pixels");
    if (!std::isfinite(o.splat_px) || o.splat_px < 1.0 || o.splat_px > 64.0)
        invalid("splat-px", o.splat_px, "[1, 64] pixels");
    const int views = o.poses_world.empty() ? c.views : static_cast<int>(std::min(o.poses_world.size(), kMaxPoses));
    if (o.picture_view < -1 || o.picture_view >= views)
        invalid("picture-view", o.picture_view, "-1 (none) or 0..views-1");
    if (o.poses_world.size() > kMaxPoses)
        throw core::Error("metric: " + std::to_string(o.poses_world.size()) + " camera poses; allowed at most " +
                          std::to_string(kMaxPoses));
    for (const render::CameraPose& p : o.poses_world) {
        const glm::dvec3 axis = p.look_at - p.eye;
        const bool finite = std::isfinite(p.eye.x) && std::isfinite(p.eye.y) && std::isfinite(p.eye.z) &&
                            std::isfinite(p.look_at.x) && std::isfinite(p.look_at.y) && std::isfinite(p.look_at.z) &&
                            std::isfinite(p.up.x) && std::isfinite(p.up.y) && std::isfinite(p.up.z);
        if (!finite || glm::length(axis) <= 0.0 || std::abs(glm::length(p.up) - 1.0) > 1e-6 ||
            std::abs(glm::dot(glm::normalize(axis), p.up)) > 1e-6)
            throw core::Error(
                "metric: a camera pose is not finite or its up is not a unit vector orthogonal to "
                "its view axis");
    }
    if (o.look_at_world &&
        !(std::isfinite(o.look_at_world->x) && std::isfinite(o.look_at_world->y) && std::isfinite(o.look_at_world->z)))
        throw core::Error("metric: --look-at: not finite; allowed x,y,z in world metres");
    if (o.look_at_world && !(std::abs(o.look_at_world->x) <= core::kMaxWorldCoordinate_m &&
                             std::abs(o.look_at_world->y) <= core::kMaxWorldCoordinate_m &&
                             std::abs(o.look_at_world->z) <= core::kMaxWorldCoordinate_m))
        throw core::Error("metric: --look-at: out of range; allowed x,y,z within 1e9 world metres");
    if (!std::isfinite(o.depth_margin_m) || o.depth_margin_m < 0.0 || o.depth_margin_m > 100.0)
        invalid("depth-margin-m", o.depth_margin_m, "[0, 100] metres");
    render::validate(c);  // near/far/start, which the CLI does not expose
}

double ratio(std::int64_t numerator, std::int64_t i1) {
    if (i1 <= 0) return kNaN;
    return static_cast<double>(numerator) / static_cast<double>(i1);
}

struct Evaluator::Impl {
    render::EglContext context;
    glm::dvec3 origin{0.0};
    core::Bounds p1_bounds;      // local frame
    core::Bounds target_bounds;  // meshes' (exact reference); empty without scene
    std::unique_ptr<detail::GpuImages> images;
    std::unique_ptr<sim::RayCaster> target_only, target_and_environment;

    /// Exact reference for one view over the pixels of `rect` (outside it no ray can hit the
    /// target): {target pixels, visible target pixels}.
    std::pair<std::int64_t, std::int64_t> exact(const render::CameraPose& pose, double vfov_deg, int width, int height,
                                                const render::PixelRect& rect) const {
        if (rect.empty()) return {0, 0};
        const std::int64_t n = rect.area();
        // Batches of pixels on oneTBB's workers; integer counts per batch, summed in batch
        // order afterwards, so the totals do not depend on the scheduling.
        constexpr std::int64_t kBatch = 4096;
        const std::size_t batches = static_cast<std::size_t>((n + kBatch - 1) / kBatch);
        std::vector<std::pair<std::int64_t, std::int64_t>> counts(batches, {0, 0});
        tbb::parallel_for(std::size_t{0}, batches, [&](std::size_t batch) {
            std::vector<sim::Ray> rays;
            std::vector<sim::Hit> hits;
            std::int64_t target = 0, visible = 0;
            const std::int64_t b = static_cast<std::int64_t>(batch) * kBatch;
            const std::int64_t e = std::min(n, b + kBatch);
            rays.resize(static_cast<std::size_t>(e - b));
            hits.assign(rays.size(), sim::Hit{});
            for (std::int64_t i = b; i < e; ++i) {
                const int px = rect.x0 + static_cast<int>(i % rect.width());
                const int py = rect.y0 + static_cast<int>(i / rect.width());
                sim::Ray& ray = rays[static_cast<std::size_t>(i - b)];
                ray.origin = glm::vec3(pose.eye);
                ray.direction = glm::vec3(render::pixelCentreDirection(pose, vfov_deg, width, height, px, py));
                ray.t_far = 1e30f;
            }
            // First hit among target + environment: the target there is visible.
            target_and_environment->intersect(rays, hits);
            std::vector<sim::Ray> again;
            for (std::size_t i = 0; i < rays.size(); ++i) {
                if (hits[i].hit() && hits[i].role == core::Role::Target) {
                    ++target;
                    ++visible;
                } else {
                    again.push_back(rays[i]);
                }
            }
            // The others are target pixels if the target alone would be hit.
            std::vector<sim::Hit> again_hits(again.size());
            target_only->intersect(again, again_hits);
            for (const sim::Hit& h : again_hits)
                if (h.hit()) ++target;
            counts[batch] = {target, visible};
        });
        std::pair<std::int64_t, std::int64_t> total{0, 0};
        for (const auto& [target, visible] : counts) {
            total.first += target;
            total.second += visible;
        }
        return total;
    }
};

Evaluator::Evaluator(const MetricClouds& clouds, const core::Scene* scene) {
    if (clouds.p1.points.empty())
        throw core::Error(
            "metric: P1 (the target-only cloud) is empty: the target is never sensed, so "
            "|I1| = 0 in every view; check the scene's target mesh or --p1");
    impl_ = std::make_unique<Impl>();
    Impl& impl = *impl_;
    impl.origin = scene ? scene->origin : clouds.p1.origin;
    const core::PointCloud p1 = toFrame(clouds.p1, impl.origin);
    impl.p1_bounds = p1.bounds();
    impl.images = std::make_unique<detail::GpuImages>(p1, toFrame(clouds.p2, impl.origin),
                                                      toFrame(clouds.p3, impl.origin), kCellM);
    if (scene && scene->hasRole(core::Role::Target)) {
        impl.target_bounds = scene->bounds(core::RoleMask::of({core::Role::Target}));
        impl.target_only = std::make_unique<sim::RayCaster>(*scene, core::RoleMask::of({core::Role::Target}));
        impl.target_and_environment =
            std::make_unique<sim::RayCaster>(*scene, core::RoleMask::of({core::Role::Target, core::Role::Environment}));
    }
}

Evaluator::~Evaluator() = default;

bool Evaluator::hasExact() const { return impl_->target_only != nullptr; }
glm::dvec3 Evaluator::origin() const { return impl_->origin; }

MetricResult Evaluator::run(const MetricOptions& options) {
    validate(options);
    const auto start = std::chrono::steady_clock::now();
    Impl& impl = *impl_;
    impl.context.makeCurrent();
    MetricResult result;
    result.origin = impl.origin;
    result.options = options;
    result.has_exact = options.exact && hasExact();
    if (options.look_at_world)
        result.look_at = *options.look_at_world - impl.origin;
    else
        result.look_at = impl.target_bounds.empty() ? impl.p1_bounds.centre() : impl.target_bounds.centre();

    const int w = options.width, h = options.height;
    const auto& orbit = options.orbit;
    const glm::dmat4 projection =
        render::projectionMatrix(orbit.vfov_deg, static_cast<double>(w) / h, orbit.near_m, orbit.far_m);
    // Splats reach splat/2 pixels past their centre; the guard band lets points just
    // outside the counted rectangle still paint into it.
    const int guard_px = static_cast<int>(std::ceil(options.splat_px / 2.0)) + 1;

    double metric_sum = 0.0, visible_sum = 0.0, depth_sum = 0.0, exact_sum = 0.0;
    int exact_used = 0;
    result.metric_min = kNaN;
    result.metric_max = kNaN;
    const bool given = !options.poses_world.empty();
    const int views = given ? static_cast<int>(options.poses_world.size()) : orbit.views;
    for (int k = 0; k < views; ++k) {
        ViewResult v;
        v.view = k;
        if (given) {
            const render::CameraPose& p = options.poses_world[static_cast<std::size_t>(k)];
            v.pose = {p.eye - impl.origin, p.look_at - impl.origin, p.up};
        } else {
            v.pose = render::orbitView(orbit, result.look_at, k);
        }
        const glm::dmat4 view = render::viewMatrix(v.pose);
        const glm::dmat4 view_projection = projection * view;

        const auto render_start = std::chrono::steady_clock::now();
        render::PixelRect counted{0, 0, w, h};
        if (options.skip) counted = render::projectBounds(view_projection, impl.p1_bounds, w, h, guard_px);
        if (counted.empty()) {
            v.frustum_skipped = true;
            v.rect = counted;
        } else {
            v.rect = counted;
            render::PixelRect drawn = counted;
            if (options.skip) {
                drawn.x0 = std::max(0, counted.x0 - guard_px);
                drawn.y0 = std::max(0, counted.y0 - guard_px);
                drawn.x1 = std::min(w, counted.x1 + guard_px);
                drawn.y1 = std::min(h, counted.y1 + guard_px);
            }
            const detail::ImageCounts c = impl.images->renderAndCount(
                view, projection, w, h, drawn, counted, options.splat_px, options.depth_margin_m, options.rasterizer,
                options.skip, &result.points_drawn);
            v.i1 = c.i1;
            v.i2 = c.i2;
            v.i3 = c.i3;
            v.i4 = c.i4;
            v.visible_px = c.visible;
            v.depth_visible_px = c.depth_visible;
        }
        if (k == options.picture_view) {
            const render::PixelRect whole{0, 0, w, h};
            impl.images->renderAndCount(view, projection, w, h, whole, whole, options.splat_px, options.depth_margin_m,
                                        options.rasterizer, false, nullptr);
            result.pictures = impl.images->readPictures(k, w, h, options.rasterizer);
        }
        v.seconds_render = seconds(render_start);
        result.seconds_render += v.seconds_render;

        v.metric = ratio(v.i4, v.i1);
        v.visible = ratio(v.visible_px, v.i1);
        v.depth_visible = v.depth_visible_px >= 0 ? ratio(v.depth_visible_px, v.i1) : kNaN;
        v.used = v.i1 > 0;
        v.exact = kNaN;
        if (result.has_exact) {
            const auto exact_start = std::chrono::steady_clock::now();
            const render::PixelRect rays = render::projectBounds(view_projection, impl.target_bounds, w, h, 1.0);
            const auto [target, visible] = impl.exact(v.pose, orbit.vfov_deg, w, h, rays);
            v.exact_target_px = target;
            v.exact_visible_px = visible;
            v.exact = ratio(visible, target);
            v.seconds_exact = seconds(exact_start);
            result.seconds_exact += v.seconds_exact;
        }
        if (v.used) {
            ++result.views_used;
            metric_sum += v.metric;
            visible_sum += v.visible;
            depth_sum += v.depth_visible;  // NaN propagates with the raster rasterizer
            if (std::isnan(result.metric_min) || v.metric < result.metric_min) result.metric_min = v.metric;
            if (std::isnan(result.metric_max) || v.metric > result.metric_max) result.metric_max = v.metric;
            if (!std::isnan(v.exact)) {
                exact_sum += v.exact;
                ++exact_used;
            }
        }
        result.views.push_back(v);
    }
    result.metric_mean = result.views_used ? metric_sum / result.views_used : kNaN;
    result.visible_mean = result.views_used ? visible_sum / result.views_used : kNaN;
    result.depth_visible_mean = result.views_used ? depth_sum / result.views_used : kNaN;
    result.exact_mean = exact_used ? exact_sum / exact_used : kNaN;
    result.seconds = seconds(start);
    return result;
}

}  // namespace metric
