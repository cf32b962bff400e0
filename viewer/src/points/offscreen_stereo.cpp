// viewer/src/points/offscreen_stereo.cpp: see viewer/offscreen_stereo.hpp. The eye images stand
// where an OpenXR swapchain's images would: the renderer draws each eye into its own
// offscreen target and resolves it (eye-dome lighting, indicator) into the image.
#include <viewer/offscreen_stereo.hpp>

#include "points/point_renderer.hpp"

#include <viewer/cloud_feed.hpp>
#include <viewer/cloud_feed_source.hpp>

#include <core/error.hpp>
#include <render/gl.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace viewer {

void validate(const StereoOptions& o) {
    auto fail = [](const std::string& what) { throw core::Error("view: offscreen " + what); };
    if (o.eye_width_px < 16 || o.eye_height_px < 16 || o.eye_width_px > 8192 || o.eye_height_px > 8192)
        fail("eye size " + std::to_string(o.eye_width_px) + "x" + std::to_string(o.eye_height_px) +
             ": allowed 16..8192 pixels each");
    if (!std::isfinite(o.ipd_m) || o.ipd_m < 0.0 || o.ipd_m > 1.0)
        fail("ipd_m = " + std::to_string(o.ipd_m) + ": allowed 0..1");
    const bool fov_ok = o.angle_left_rad < o.angle_right_rad && o.angle_down_rad < o.angle_up_rad &&
                        std::abs(o.angle_left_rad) < 1.55 && std::abs(o.angle_right_rad) < 1.55 &&
                        std::abs(o.angle_up_rad) < 1.55 && std::abs(o.angle_down_rad) < 1.55;
    if (!fov_ok) fail("field of view: need left < right, down < up, each angle within +-1.55 rad");
}

struct OffscreenStereo::Impl {
    StereoOptions options;
    // Every cloud uploaded, as the point sources the renderer follows (kept: the renderer
    // knows their nodes).
    std::vector<std::unique_ptr<CloudFeed>> feeds;
    std::vector<std::unique_ptr<CloudFeedSource>> sources;
    PointRenderer renderer;
    PointSource* followed = nullptr;  // follow()'s source, if any
    std::array<std::size_t, 2> drawn{};
    std::array<EyeTarget, 2> targets;
    std::array<GLuint, 2> images{}, fbos{};

    ~Impl() {
        for (auto& t : targets) t.destroy();
        glDeleteFramebuffers(2, fbos.data());
        glDeleteTextures(2, images.data());
    }

    std::array<EyeDraw, 2> eyeDraws(const RigPose& head) const {
        std::array<EyeDraw, 2> draws;
        for (int i = 0; i < 2; ++i) {
            RigPose eye = head;
            eye.position = head.apply(glm::dvec3((i == 0 ? -0.5 : 0.5) * options.ipd_m, 0.0, 0.0));
            draws[i].view = viewFromPose(eye);
            draws[i].projection =
                projectionFromFov(options.angle_left_rad, options.angle_right_rad, options.angle_up_rad,
                                  options.angle_down_rad, draws[i].near_m, draws[i].far_m);
        }
        return draws;
    }
};

OffscreenStereo::OffscreenStereo(const StereoOptions& options) {
    validate(options);
    impl_ = std::make_unique<Impl>();  // compiles the programs (throws on a shader failure);
                                       // what is allocated after is freed by ~Impl on a throw
    impl_->options = options;
    glCreateTextures(GL_TEXTURE_2D, 2, impl_->images.data());
    glCreateFramebuffers(2, impl_->fbos.data());
    for (int i = 0; i < 2; ++i) {
        glTextureStorage2D(impl_->images[i], 1, GL_RGBA8, options.eye_width_px, options.eye_height_px);
        glNamedFramebufferTexture(impl_->fbos[i], GL_COLOR_ATTACHMENT0, impl_->images[i], 0);
        if (!impl_->targets[i].ensure(options.eye_width_px, options.eye_height_px))
            throw core::Error("view: offscreen eye target " + std::to_string(options.eye_width_px) + "x" +
                              std::to_string(options.eye_height_px) + " could not be allocated");
    }
}

OffscreenStereo::~OffscreenStereo() = default;

void OffscreenStereo::upload(const core::PointCloud& cloud) {
    impl_->feeds.push_back(std::make_unique<CloudFeed>());
    impl_->feeds.back()->feedCloud(cloud, 1u << 20);
    impl_->sources.push_back(std::make_unique<CloudFeedSource>(*impl_->feeds.back()));
    impl_->sources.back()->poll();
    impl_->renderer.stream(*impl_->sources.back(), cloud.points.size());
}

void OffscreenStereo::follow(PointSource& source, std::size_t gpu_bytes) {
    impl_->followed = &source;
    impl_->renderer.setGpuBytes(gpu_bytes);
}

OffscreenStereo::StreamStep OffscreenStereo::stream(std::size_t upload_points) {
    StreamStep step;
    PointSource* source = impl_->followed;
    if (!source) return step;
    using Clock = std::chrono::steady_clock;
    const auto ms = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration<double, std::milli>(b - a).count();
    };
    const Clock::time_point t0 = Clock::now();
    if (const std::optional<SourceView>& view = impl_->renderer.lastView()) source->select(*view);
    const Clock::time_point t1 = Clock::now();
    step.added_nodes = source->poll();
    const Clock::time_point t2 = Clock::now();
    step.uploaded_points = impl_->renderer.stream(*source, upload_points);
    const Clock::time_point t3 = Clock::now();
    step.select_ms = ms(t0, t1);
    step.poll_ms = ms(t1, t2);
    step.upload_ms = ms(t2, t3);
    return step;
}

std::size_t OffscreenStereo::pendingPoints() const { return impl_->renderer.pendingPoints(); }
std::size_t OffscreenStereo::gpuBytes() const { return impl_->renderer.arena().bytes; }
std::size_t OffscreenStereo::gpuBytesPeak() const { return impl_->renderer.arena().bytes_peak; }
std::size_t OffscreenStereo::gpuNodesRefused() const { return impl_->renderer.arena().nodes_refused; }

std::array<std::size_t, 2> OffscreenStereo::lastDrawnPerEye() const { return impl_->drawn; }

const std::optional<SourceView>& OffscreenStereo::lastView() const { return impl_->renderer.lastView(); }

std::size_t OffscreenStereo::uploadedPoints() const { return impl_->renderer.uploadedPoints(); }
std::size_t OffscreenStereo::cellCount() const { return impl_->renderer.cellCount(); }
const core::Bounds& OffscreenStereo::bounds() const { return impl_->renderer.bounds(); }

glm::dmat4 OffscreenStereo::eyeView(const RigPose& head, int eye) const {
    return impl_->eyeDraws(head)[eye == 0 ? 0 : 1].view;
}

glm::dmat4 OffscreenStereo::projection() const { return impl_->eyeDraws(RigPose{})[0].projection; }

void OffscreenStereo::plan(const RigPose& head, std::size_t point_budget, bool cull) {
    const std::array<EyeDraw, 2> draws = impl_->eyeDraws(head);
    impl_->renderer.planFrame(draws, point_budget, cull);
}

void OffscreenStereo::setFocus(LodFocus focus) { impl_->renderer.setFocus(std::move(focus)); }

std::size_t OffscreenStereo::draw(const RigPose& head, const ViewStyle& style, ViewMode mode) {
    const std::array<EyeDraw, 2> draws = impl_->eyeDraws(head);
    for (int i = 0; i < 2; ++i)
        impl_->drawn[i] = impl_->renderer
                              .drawEye(impl_->targets[i], draws[i], style, mode, impl_->fbos[i], 0, 0,
                                       impl_->options.eye_width_px, impl_->options.eye_height_px)
                              .points_drawn;
    return impl_->drawn[0] + impl_->drawn[1];
}

void OffscreenStereo::setPassTiming(bool on) { impl_->renderer.setPassTiming(on); }

OffscreenStereo::PassTimes OffscreenStereo::takePassTimes() {
    const PointRenderer::PassTimes t = impl_->renderer.takePassTimes();
    return {t.raster_ms, t.colour_ms, t.resolve_ms, t.eyes};
}

bool OffscreenStereo::subgroupAvailable() const { return impl_->renderer.subgroupAvailable(); }
void OffscreenStereo::setSubgroupReduction(bool on) { impl_->renderer.setSubgroupReduction(on); }

std::size_t OffscreenStereo::coveredPixels() const {
    const EyeTarget& target = impl_->targets[1];
    impl_->renderer.depthInto(target);  // the compute rasteriser's depth; GL_POINTS left it there
    std::vector<float> depth(std::size_t(target.width) * std::size_t(target.height));
    glGetTextureImage(target.depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(depth.size() * sizeof(float)),
                      depth.data());
    render::logGl("OffscreenStereo::coveredPixels", __FILE__, __LINE__);
    return std::size_t(std::count_if(depth.begin(), depth.end(), [](float d) { return d < 1.0f; }));
}

std::vector<std::uint8_t> OffscreenStereo::readEye(int eye) const {
    const int w = impl_->options.eye_width_px, h = impl_->options.eye_height_px;
    std::vector<std::uint8_t> rgba(std::size_t(w) * std::size_t(h) * 4);
    glFinish();
    glGetTextureImage(impl_->images[eye == 0 ? 0 : 1], 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
    return rgba;
}

}  // namespace viewer
