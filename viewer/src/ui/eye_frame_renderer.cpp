// viewer/src/ui/eye_frame_renderer.cpp: the headset's eyes, the desktop view, overlays and the panel quad.
#include "ui/eye_frame_renderer.hpp"

#include "ui/panel_quad.hpp"

#include <io/png.hpp>
#include <render/orbit_camera.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <span>
#include <vector>

namespace viewer {

namespace {

using Clock = std::chrono::steady_clock;

/// Where an eye's image lands in the mirror window (letterboxed, aspect kept).
struct Rect {
    int x = 0, y = 0, w = 0, h = 0;
};
Rect fitRect(int area_x, int area_w, int area_h, int img_w, int img_h) {
    const double s = std::min(double(area_w) / img_w, double(area_h) / img_h);
    Rect r;
    r.w = std::max(1, int(img_w * s));
    r.h = std::max(1, int(img_h * s));
    r.x = area_x + (area_w - r.w) / 2;
    r.y = (area_h - r.h) / 2;
    return r;
}

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

RigPose compose(const RigPose& a, const RigPose& b) {
    return {a.rotation * b.rotation, a.rotation * b.position + a.position};
}

glm::dmat4 scaledView(const RigPose& eye, double scale) {
    return glm::scale(glm::dmat4(1.0), glm::dvec3(scale)) * viewFromPose(eye);
}

EyeFrameRenderer::EyeFrameRenderer(const ViewerOptions& options) : options_(options) {
    if (options_.gpu_timing) glCreateQueries(GL_TIME_ELAPSED, 1, &timer_query_);
    glCreateFramebuffers(2, swapchain_fbo_.data());
}

EyeFrameRenderer::~EyeFrameRenderer() {
    for (auto& t : eye_targets_) t.destroy();
    desktop_target_.destroy();
    panel_target_.destroy();
    if (swapchain_fbo_[0]) glDeleteFramebuffers(2, swapchain_fbo_.data());
    if (timer_query_) glDeleteQueries(1, &timer_query_);
}

void EyeFrameRenderer::drawEye(const EyeTarget& target, PointRenderer& points, const FrameView& view,
                               const EyeDraw& draw, GLuint fbo, int x, int y, int w, int h, FrameResult& out) {
    if (view.blank) {  // nothing of the cloud before the trial starts
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(x, y, w, h);
        glClearColor(0.02f, 0.02f, 0.03f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        return;
    }
    const std::size_t drawn =
        points.drawEye(target, draw, *view.style, view.mode, fbo, x, y, w, h, view.cut).points_drawn;
    out.points_drawn += drawn;
    out.points_drawn_per_eye = std::max(out.points_drawn_per_eye, drawn);
    overlay_.draw(*view.overlay, draw.view, draw.projection, fbo, x, y, w, h, 8.0f);
    if (view.headset && view.overlay->vignette) {
        const VignetteStyle& v = *view.overlay->vignette;
        overlay_.drawVignette(fbo, x, y, w, h, v.aperture, v.feather, v.strength);
    }
}

void EyeFrameRenderer::drawPanelQuad(const RigPose& eye_tracking, const glm::dmat4& projection, GLuint fbo, int w,
                                     int h) {
    const std::array<glm::dvec3, 4> corners_t =
        panelCorners(headsetPanelQuad(panel_target_.width, panel_target_.height));
    std::array<glm::dvec3, 4> corners_eye;
    for (int k = 0; k < 4; ++k)
        corners_eye[k] = glm::transpose(eye_tracking.rotation) * (corners_t[k] - eye_tracking.position);
    overlay_.drawPanelQuad(panel_target_.colour, corners_eye, projection, fbo, 0, 0, w, h);
}

void EyeFrameRenderer::mirror(int eye, int w, int h, int fb_w, int fb_h) {
    const MirrorEyes m = options_.mirror;
    const bool show =
        m == MirrorEyes::Both || (m == MirrorEyes::Left && eye == 0) || (m == MirrorEyes::Right && eye == 1);
    if (!show) return;
    const bool both = m == MirrorEyes::Both;
    const int area_w = both ? fb_w / 2 : fb_w;
    const Rect r = fitRect(both ? eye * area_w : 0, area_w, fb_h, w, h);
    glBlitNamedFramebuffer(swapchain_fbo_[eye], 0, 0, 0, w, h, r.x, r.y, r.x + r.w, r.y + r.h, GL_COLOR_BUFFER_BIT,
                           GL_LINEAR);
}

void EyeFrameRenderer::beginXr(XrStereoSession& xr) {
    begun_valid_ = true;
    begun_failed_ = !xr.beginFrame(begun_);
    if (begun_failed_ || !begun_.should_render || !begun_.views_valid) return;
    const XrEye& l = begun_.eyes[0];
    const XrEye& r = begun_.eyes[1];
    last_head_ = {glm::mat3_cast(l.orientation), 0.5 * (l.position + r.position)};
}

bool EyeFrameRenderer::renderXr(XrStereoSession& xr, PointRenderer& points, const FrameView& view, int fb_w, int fb_h,
                                FrameResult& out) {
    out = FrameResult{};
    XrFrame& frame = out.xr_frame;
    if (!begun_valid_) beginXr(xr);
    begun_valid_ = false;
    if (begun_failed_) return false;
    frame = begun_;
    frame.input_time_ns = xr.inputTime_ns();
    const int w = xr.eyeWidth(), h = xr.eyeHeight();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    const Clock::time_point t0 = Clock::now();
    if (frame.should_render && frame.views_valid) {
        if (timer_query_) glBeginQuery(GL_TIME_ELAPSED, timer_query_);
        for (int i = 0; i < 2; ++i)
            out.eyes_tracking[i] = {glm::mat3_cast(frame.eyes[i].orientation), frame.eyes[i].position};
        std::array<EyeDraw, 2> draws;
        for (int i = 0; i < 2; ++i) {
            out.eyes_local[i] = compose(view.rig, view.zoom->apply(out.eyes_tracking[i]));
            EyeDraw& draw = draws[i];
            draw.near_m = options_.modes.orbit.near_m;
            draw.far_m = options_.modes.orbit.far_m;
            draw.view = scaledView(out.eyes_local[i], view.zoom->scale());
            const XrEye& e = frame.eyes[i];
            draw.projection =
                projectionFromFov(e.angle_left, e.angle_right, e.angle_up, e.angle_down, draw.near_m, draw.far_m);
        }
        points.planFrame(draws, options_.point_budget, options_.cull);  // union of both eyes
        // The eye targets' depth (the points only: the overlay, vignette and panel quad
        // have none) goes to the compositor as drawn; a ready screen has no depth.
        const bool depth = xr.depthAvailable() && !view.blank;
        for (int i = 0; i < 2; ++i) {
            if (!eye_targets_[i].ensure(w, h)) return false;
            const unsigned texture = xr.acquireEye(i);
            if (texture == 0) return false;
            glNamedFramebufferTexture(swapchain_fbo_[i], GL_COLOR_ATTACHMENT0, texture, 0);
            drawEye(eye_targets_[i], points, view, draws[i], swapchain_fbo_[i], 0, 0, w, h, out);
            if (show_panel && panel_target_.colour != 0)
                drawPanelQuad(out.eyes_tracking[i], draws[i].projection, swapchain_fbo_[i], w, h);
            mirror(i, w, h, fb_w, fb_h);
            glNamedFramebufferTexture(swapchain_fbo_[i], GL_COLOR_ATTACHMENT0, 0, 0);
            if (!xr.releaseEye(i)) return false;
            if (depth) {
                points.depthInto(eye_targets_[i]);
                const unsigned depth_texture = xr.acquireEyeDepth(i);
                if (depth_texture == 0) return false;
                glCopyImageSubData(eye_targets_[i].depth, GL_TEXTURE_2D, 0, 0, 0, 0, depth_texture, GL_TEXTURE_2D, 0, 0,
                                   0, 0, w, h, 1);
                const bool copied = render::logGl("eye depth into the depth swapchain", __FILE__, __LINE__);
                if (!xr.releaseEyeDepth(i) || !copied) return false;
            }
        }
        out.cpu_ms = msSince(t0);
        endGpuTimer();
        out.rendered = true;
        if (depth)
            out.depth_range = XrDepthRange{float(options_.modes.orbit.near_m), float(options_.modes.orbit.far_m)};
    }
    return xr.endFrame(frame, out.rendered, out.depth_range);
}

void EyeFrameRenderer::renderDesktop(PointRenderer& points, const FrameView& view, int fb_w, int fb_h,
                                     FrameResult& out) {
    out = FrameResult{};
    if (fb_w <= 0 || fb_h <= 0) return;  // minimised
    const Clock::time_point t0 = Clock::now();
    RigPose eye = compose(view.rig, view.zoom->apply(view.head_tracking));
    double scale = view.zoom->scale();
    if (view.replay) {  // the recorded head, in the cloud's local frame
        eye = {glm::mat3_cast(view.replay->head_orientation), view.replay->head_world - view.origin};
        scale = view.replay->scale;
    }
    EyeDraw draw;
    draw.near_m = options_.modes.orbit.near_m;
    draw.far_m = options_.modes.orbit.far_m;
    draw.view = scaledView(eye, scale);
    draw.projection =
        render::projectionMatrix(options_.modes.orbit.vfov_deg, double(fb_w) / fb_h, draw.near_m, draw.far_m);
    if (!desktop_target_.ensure(fb_w, fb_h)) return;
    if (timer_query_) glBeginQuery(GL_TIME_ELAPSED, timer_query_);
    points.planFrame(std::span<const EyeDraw>(&draw, 1), options_.point_budget, options_.cull);
    drawEye(desktop_target_, points, view, draw, 0, 0, 0, fb_w, fb_h, out);
    out.cpu_ms = msSince(t0);
    endGpuTimer();
    out.eyes_tracking = {view.head_tracking, view.head_tracking};
    out.eyes_local = {eye, eye};
    out.rendered = true;
}

void EyeFrameRenderer::endGpuTimer() {
    if (!timer_query_) return;
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer_query_, GL_QUERY_RESULT, &ns);  // waits: benchmarks only
    last_gpu_ms_ = double(ns) * 1e-6;
}

bool writeScreenshot(const std::filesystem::path& path, int fb_w, int fb_h) {
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(fb_w) * fb_h * 3);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, fb_w, fb_h, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
    if (!render::logGl("glReadPixels (screenshot)", __FILE__, __LINE__)) return false;
    try {
        io::writePng(path, pixels, fb_w, fb_h, 3, io::PngRows::BottomUp);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ladarvr: view: --screenshot: %s\n", e.what());
        return false;
    }
    return true;
}

}  // namespace viewer
