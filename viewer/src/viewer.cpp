// viewer/src/viewer.cpp: the frame loop of `ladarvr view` and of a study's trials (paper
// §IV-A): desktop mirror window, optional OpenXR session, modes, zoom, the operator's
// tools, ImGui panel, script, screenshot and run log.
//
// Input comes from three places merged into one OperatorInput per frame: the OpenXR
// actions (xr_actions.cpp), the desktop (desktop_input.cpp) and a --script; the tools
// (tools/) read only that. Setup throws engine::Error; once the loop runs nothing
// throws: OpenXR failures drop to the desktop mode with the cloud kept, GL errors are
// logged.
#include <render/gl.hpp>   // glad first
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <render/gl.hpp>   // glad first
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <viewer/viewer.hpp>
#include <viewer/world_zoom.hpp>

#include "desktop_input.hpp"
#include "overlay_renderer.hpp"
#include "panel.hpp"
#include "point_renderer.hpp"
#include "run_log.hpp"
#include "stop_signal.hpp"
#include "tools/candidates_tool.hpp"
#include "tools/pointer_tool.hpp"
#include "xr_session.hpp"

#include <engine/error.hpp>
#include <engine/png.hpp>
#include <engine/safe_file.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <thread>

namespace viewer {

namespace {

using Clock = std::chrono::steady_clock;

std::string g_glfw_error;
void glfwError(int code, const char* description) {
    g_glfw_error = std::string(description ? description : "?") + " (" + std::to_string(code) + ")";
}

nlohmann::json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
nlohmann::json quat(const glm::dquat& q) { return {q.w, q.x, q.y, q.z}; }

RigPose compose(const RigPose& a, const RigPose& b) {
    return {a.rotation * b.rotation, a.rotation * b.position + a.position};
}

/// World-to-eye view of an eye at `eye` (local frame) with the zoom's scale applied after
/// the rigid part, in double.
glm::dmat4 scaledView(const RigPose& eye, double scale) {
    return glm::scale(glm::dmat4(1.0), glm::dvec3(scale)) * viewFromPose(eye);
}

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

/// A trial in flight (a plain `view` run is one trial without a ready screen or observer).
struct TrialState {
    int index = -1;                 // -1: a plain view run
    TrialSetup setup;
    std::unique_ptr<CloudFeed> own_feed;
    bool ready_screen = false;      // waiting for the operator to start
    bool running = false;           // between the ready screen and the decision
    Clock::time_point started{};
    TrialOutcome outcome;
    std::optional<glm::dvec3> designated_local;
    bool candidates_placed = false;
};

class ViewerApp {
public:
    /// `record_frames`: keep per-frame records in the log (for --log-json and benchmarks;
    /// an interactive session would otherwise grow it for nothing).
    ViewerApp(const ViewerOptions& options, bool record_frames)
        : options_(options), style_(options.style), modes_(options.modes, glm::dvec3(0.0)),
          pointer_(options.pick), record_frames_(record_frames), cut_enabled_(options.cut_enabled),
          cut_radius_m_(options.cut_radius_m),
          snap_turn_(options.snap_turn), vignette_(options.vignette), headset_panel_(options.headset_panel) {}
    ~ViewerApp();
    /// A plain run over `feed` (source and observer null), or the trials of `source`.
    int run(CloudFeed* feed, TrialSource* source, TrialObserver* observer);
    std::string logJson() const { return log_.json().dump(); }

private:
    void setup();
    void fallBackToDesktop(const std::string& reason);
    bool renderXrFrame(bool& rendered);
    void renderDesktop(int fb_w, int fb_h);
    void drawEyeAndOverlay(const EyeTarget& target, const EyeDraw& draw, GLuint fbo, int x, int y, int w, int h,
                           std::size_t& drawn);
    void drawPanel(double frame_ms, int fb_w, int fb_h);
    void endGpuTimer();
    void toggleMode(const std::string& source);
    RigPose headTracking() const;
    RigPose headLocal() const { return compose(modes_.rig(), zoom_.apply(headTracking())); }
    void logFrame(bool xr, const std::array<RigPose, 2>& eyes_t, const std::array<RigPose, 2>& eyes_local,
                  const XrFrame* xr_frame, double cpu_ms);
    void frameCounted();
    bool screenshot(int fb_w, int fb_h);

    // Trials.
    void beginTrial(int index);
    void endTrial(Decision decision);
    double trialTime() const;
    bool readyToStart() const;
    void applyInput(const OperatorInput& in, double dt);
    std::optional<LocalRay> pointerRay(const OperatorInput& in) const;
    void streamAndIndex();

    ViewerOptions options_;
    CloudFeed* feed_ = nullptr;
    TrialSource* source_ = nullptr;
    TrialObserver* observer_ = nullptr;
    TrialState trial_;
    int trials_total_ = 1;
    ViewStyle style_;
    ModeController modes_;
    WorldZoom zoom_;
    PointerTool pointer_;
    CandidatesTool candidates_;
    RunLog log_;
    DesktopInput input_;
    GLFWwindow* window_ = nullptr;
    bool imgui_ = false;
    std::unique_ptr<PointRenderer> renderer_;
    std::unique_ptr<OverlayRenderer> overlay_;
    OverlayList overlay_list_;
    std::unique_ptr<XrStereoSession> xr_;
    std::array<EyeTarget, 2> eye_targets_;
    EyeTarget desktop_target_;
    std::array<GLuint, 2> swapchain_fbo_{};
    XrEye last_eye_[2];
    RigPose last_head_;
    long frames_ = 0;            // counted frames (XR: submitted with both eyes)
    long frames_submitted_ = 0;
    long first_points_frame_ = -1;
    std::size_t points_drawn_ = 0;
    std::string fallback_;
    long desktop_since_frame_ = -1;   // frames_ when the viewer dropped to desktop mode
    long loaded_since_frame_ = -1;    // frames_ when the whole cloud was first on the GPU
    bool quitting_ = false;      // frames after the exit request are not counted
    GLuint timer_query_ = 0;     // GL_TIME_ELAPSED around the frame's draws (--gpu-timing)
    double last_gpu_ms_ = -1.0;
    double frame_ms_ = 0.0;      // wall time since the previous loop iteration
    bool record_frames_ = true;
    Clock::time_point start_ = Clock::now();
    bool centre_final_ = false;
    // The pick index, built on a worker thread once the whole cloud has arrived.
    std::vector<engine::CloudPoint> index_points_;
    std::future<std::shared_ptr<const PickIndex>> index_future_;
    std::shared_ptr<const PickIndex> index_;
    // Tools' state.
    std::optional<glm::dvec3> aim_world_;    // a script's aim: the pointer follows the head to it
    int pointer_hand_ = 1;                   // the hand whose ray is the pointer (last designate)
    bool cut_enabled_ = false;
    double cut_radius_m_ = 15.0;
    bool highlight_candidates_ = false;
    bool snap_turn_ = true, vignette_ = true;
    double last_snap_s_ = -1e9;
    double vignette_strength_ = 0.0;   // eases to 1 while moving in free mode, back to 0 at rest
    // Replay of a trace: the sample shown this frame, and when the replay started.
    std::optional<TraceSample> replay_sample_;
    std::optional<Clock::time_point> replay_start_;
    std::size_t replay_next_ = 0;
    bool replay_done_ = false;
    bool reset_zoom_button_ = false;
    EyeTarget panel_target_;             // the ImGui windows rendered for the headset's quad
    bool headset_panel_ = true;
    nlohmann::json decisions_ = nlohmann::json::array();   // the run log's record of actions
};

ViewerApp::~ViewerApp() {
    xr_.reset();
    if (window_) {
        glfwMakeContextCurrent(window_);
        renderer_.reset();
        overlay_.reset();
        for (auto& t : eye_targets_) t.destroy();
        desktop_target_.destroy();
        panel_target_.destroy();
        if (swapchain_fbo_[0]) glDeleteFramebuffers(2, swapchain_fbo_.data());
        if (timer_query_) glDeleteQueries(1, &timer_query_);
        if (imgui_) {
            ImGui_ImplOpenGL3_Shutdown();
            ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext();
        }
        glfwDestroyWindow(window_);
    }
    glfwTerminate();
}

void ViewerApp::setup() {
    glfwSetErrorCallback(glfwError);
    if (!glfwInit())
        throw engine::Error("view: cannot open the desktop window: " + g_glfw_error +
                            "; a display is needed (set DISPLAY, or run under Xvfb)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, options_.hidden_window ? GLFW_FALSE : GLFW_TRUE);
    window_ = glfwCreateWindow(options_.window_width, options_.window_height, "ladarvr view", nullptr, nullptr);
    if (!window_)
        throw engine::Error("view: cannot create an OpenGL 4.5 core window: " + g_glfw_error);
    glfwMakeContextCurrent(window_);
    render::loadGl(reinterpret_cast<GLADloadfunc>(glfwGetProcAddress));
    log_.set("gl", render::glDescription());
    input_.install(window_);   // before ImGui, which chains to these callbacks

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;   // no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    imgui_ = true;

    renderer_ = std::make_unique<PointRenderer>();
    overlay_ = std::make_unique<OverlayRenderer>();
    if (options_.gpu_timing) glCreateQueries(GL_TIME_ELAPSED, 1, &timer_query_);
    glCreateFramebuffers(2, swapchain_fbo_.data());

    if (options_.use_xr) {
        std::string reason;
        try {
            xr_ = XrStereoSession::create(window_, log_, reason);
        } catch (const engine::Error& e) {
            reason = e.what();
        }
        if (!xr_) fallBackToDesktop(reason);
    } else {
        fallBackToDesktop("OpenXR disabled (--no-xr)");
    }
    log_.set("xr_active_at_start", xr_ != nullptr);
    glfwSwapInterval(xr_ || !options_.vsync ? 0 : 1);
}

void ViewerApp::fallBackToDesktop(const std::string& reason) {
    xr_.reset();
    fallback_ = reason;
    desktop_since_frame_ = frames_;
    log_.event("desktop mode: " + reason);
    if (!options_.quiet)
        std::fprintf(stderr, "ladarvr: view: %s; desktop mode (mouse and keyboard camera)\n", reason.c_str());
}

RigPose ViewerApp::headTracking() const {
    if (xr_) return last_head_;
    return {glm::mat3_cast(lookOrientation(input_.lookYawRad(), input_.lookPitchRad())), glm::dvec3(0.0)};
}

void ViewerApp::toggleMode(const std::string& source) {
    const ViewMode from = modes_.mode();
    if (xr_) modes_.toggle(zoom_.apply(last_head_));
    else modes_.toggleDesktop(input_.lookYawRad(), input_.lookPitchRad());
    log_.modeSwitch(frames_, modeName(from), modeName(modes_.mode()), source);
    if (trial_.running) ++trial_.outcome.mode_switches;
    if (!options_.quiet) std::fprintf(stderr, "ladarvr: view: %s mode (%s)\n", modeName(modes_.mode()), source.c_str());
}

void ViewerApp::logFrame(bool xr, const std::array<RigPose, 2>& eyes_t, const std::array<RigPose, 2>& eyes_local,
                         const XrFrame* xr_frame, double cpu_ms) {
    if (!record_frames_) return;
    nlohmann::json f = {{"frame", frames_},
                        {"t_s", std::chrono::duration<double>(Clock::now() - start_).count()},
                        {"mode", modeName(modes_.mode())},
                        {"orbit_centre_local", vec(modes_.centre())},
                        {"xr", xr},
                        {"points_drawn", points_drawn_},
                        {"points_uploaded", renderer_->uploadedPoints()},
                        {"points_arrived", feed_->pointsArrived()},
                        {"cpu_ms", cpu_ms},
                        {"frame_ms", frame_ms_},
                        {"scale", zoom_.scale()},
                        {"colour", colourModeName(style_.colour)},
                        {"cut", cut_enabled_},
                        {"pointer", pointer_.log()},
                        {"pick_ms", pointer_.lastPickMs()},
                        {"pick_ready", pointer_.ready()}};
    if (trial_.index >= 0) f["trial"] = trial_.index;
    if (last_gpu_ms_ >= 0.0) f["gpu_ms"] = last_gpu_ms_;
    nlohmann::json tracking = nlohmann::json::array(), local = nlohmann::json::array();
    for (int i = 0; i < (xr ? 2 : 1); ++i) {
        nlohmann::json e = {{"position", vec(eyes_t[i].position)},
                            {"orientation", quat(glm::quat_cast(eyes_t[i].rotation))}};
        if (xr_frame) {
            const XrEye& x = xr_frame->eyes[i];
            e["fov_rad"] = {x.angle_left, x.angle_right, x.angle_up, x.angle_down};
        }
        tracking.push_back(e);
        local.push_back({{"position", vec(eyes_local[i].position)},
                         {"gaze", vec(eyes_local[i].rotation * glm::dvec3(0, 0, -1))}});
    }
    f["eyes_tracking"] = tracking;
    f["eyes_local"] = local;
    if (xr_frame) f["display_time_ns"] = xr_frame->display_time_ns;
    log_.frame(std::move(f));
}

/// After a frame was counted: the trace sample of the trial in flight.
void ViewerApp::frameCounted() {
    if (first_points_frame_ < 0 && points_drawn_ > 0) first_points_frame_ = frames_;
    if (!trial_.running || !observer_) return;
    TraceSample sample;
    sample.t_s = trialTime();
    const RigPose head = headLocal();
    sample.head_world = head.position + feed_->origin();
    sample.head_orientation = glm::quat_cast(head.rotation);
    sample.mode = modes_.mode();
    sample.scale = zoom_.scale();
    if (pointer_.hit()) sample.hit_world = pointer_.hit()->local + feed_->origin();
    observer_->onFrame(trial_.index, sample);
}

void ViewerApp::drawEyeAndOverlay(const EyeTarget& target, const EyeDraw& draw, GLuint fbo, int x, int y, int w,
                                  int h, std::size_t& drawn) {
    CutVolume cut;
    cut.enabled = cut_enabled_ && trial_.designated_local.has_value();
    if (cut.enabled) {
        cut.centre_local = *trial_.designated_local;
        cut.radius_m = cut_radius_m_;
    }
    if (trial_.ready_screen) {   // nothing of the cloud before the trial starts
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(x, y, w, h);
        glClearColor(0.02f, 0.02f, 0.03f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        return;
    }
    const ViewMode mode = replay_sample_ ? replay_sample_->mode : modes_.mode();
    drawn += renderer_->drawEye(target, draw, style_, mode, fbo, x, y, w, h, cut).points_drawn;
    overlay_->draw(overlay_list_, draw.view, draw.projection, fbo, x, y, w, h, 8.0f);
    if (xr_ && vignette_)
        overlay_->drawVignette(fbo, x, y, w, h, float(options_.vignette_aperture), float(options_.vignette_feather),
                               float(vignette_strength_));
}

bool ViewerApp::renderXrFrame(bool& rendered) {
    rendered = false;
    XrFrame frame;
    if (!xr_->beginFrame(frame)) return false;
    std::array<RigPose, 2> eyes_t, eyes_local;
    const int w = xr_->eyeWidth(), h = xr_->eyeHeight();
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window_, &fb_w, &fb_h);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    const Clock::time_point t0 = Clock::now();
    double cpu_ms = 0.0;
    if (frame.should_render && frame.views_valid) {
        if (timer_query_) glBeginQuery(GL_TIME_ELAPSED, timer_query_);
        for (int i = 0; i < 2; ++i) {
            eyes_t[i] = {glm::mat3_cast(frame.eyes[i].orientation), frame.eyes[i].position};
            last_eye_[i] = frame.eyes[i];
        }
        last_head_ = {eyes_t[0].rotation, 0.5 * (eyes_t[0].position + eyes_t[1].position)};
        const RigPose rig = modes_.rig();
        points_drawn_ = 0;
        std::array<EyeDraw, 2> draws;
        for (int i = 0; i < 2; ++i) {
            eyes_local[i] = compose(rig, zoom_.apply(eyes_t[i]));
            EyeDraw& draw = draws[i];
            draw.near_m = options_.modes.orbit.near_m;
            draw.far_m = options_.modes.orbit.far_m;
            draw.view = scaledView(eyes_local[i], zoom_.scale());
            const XrEye& e = frame.eyes[i];
            draw.projection = projectionFromFov(e.angle_left, e.angle_right, e.angle_up, e.angle_down,
                                                draw.near_m, draw.far_m);
        }
        renderer_->planFrame(draws, options_.point_budget, options_.cull);   // union of both eyes
        for (int i = 0; i < 2; ++i) {
            const EyeDraw& draw = draws[i];
            if (!eye_targets_[i].ensure(w, h)) return false;
            const unsigned texture = xr_->acquireEye(i);
            if (texture == 0) return false;
            glNamedFramebufferTexture(swapchain_fbo_[i], GL_COLOR_ATTACHMENT0, texture, 0);
            drawEyeAndOverlay(eye_targets_[i], draw, swapchain_fbo_[i], 0, 0, w, h, points_drawn_);
            if (headset_panel_ && panel_target_.colour != 0) {
                // The panel hangs 1.1 m ahead of the tracking origin (the head at the
                // session's start), its centre 0.6 m below eye level (below the gaze, where
                // the target is not), 0.8 m wide, in the tracking frame: a glance down
                // reads it, and it stays put when the head turns.
                const double pw = 0.8, ph = pw * panel_target_.height / std::max(1, panel_target_.width);
                const glm::dvec3 c(0.0, -0.6, -1.1);
                const std::array<glm::dvec3, 4> corners_t = {c + glm::dvec3(-pw / 2, -ph / 2, 0),
                                                             c + glm::dvec3(pw / 2, -ph / 2, 0),
                                                             c + glm::dvec3(pw / 2, ph / 2, 0),
                                                             c + glm::dvec3(-pw / 2, ph / 2, 0)};
                std::array<glm::dvec3, 4> corners_eye;
                for (int k = 0; k < 4; ++k)
                    corners_eye[k] = glm::transpose(eyes_t[i].rotation) * (corners_t[k] - eyes_t[i].position);
                overlay_->drawPanelQuad(panel_target_.colour, corners_eye, draw.projection, swapchain_fbo_[i], 0, 0, w, h);
            }
            const bool show = options_.mirror == MirrorEyes::Both || (options_.mirror == MirrorEyes::Left && i == 0) ||
                              (options_.mirror == MirrorEyes::Right && i == 1);
            if (show) {
                const bool both = options_.mirror == MirrorEyes::Both;
                const int area_w = both ? fb_w / 2 : fb_w;
                const Rect r = fitRect(both ? i * area_w : 0, area_w, fb_h, w, h);
                glBlitNamedFramebuffer(swapchain_fbo_[i], 0, 0, 0, w, h, r.x, r.y, r.x + r.w, r.y + r.h,
                                       GL_COLOR_BUFFER_BIT, GL_LINEAR);
            }
            glNamedFramebufferTexture(swapchain_fbo_[i], GL_COLOR_ATTACHMENT0, 0, 0);
            if (!xr_->releaseEye(i)) return false;
        }
        cpu_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        endGpuTimer();
        rendered = true;
    }
    if (!xr_->endFrame(frame, rendered)) return false;
    if (rendered && !quitting_) {
        ++frames_submitted_;
        ++frames_;
        logFrame(true, eyes_t, eyes_local, &frame, cpu_ms);
        frameCounted();
    }
    return true;
}

void ViewerApp::renderDesktop(int fb_w, int fb_h) {
    if (fb_w <= 0 || fb_h <= 0) return;   // minimised
    const Clock::time_point t0 = Clock::now();
    const RigPose head = headTracking();
    RigPose eye = compose(modes_.rig(), zoom_.apply(head));
    double scale = zoom_.scale();
    if (replay_sample_) {   // the recorded head, in the cloud's local frame
        eye = {glm::mat3_cast(replay_sample_->head_orientation), replay_sample_->head_world - feed_->origin()};
        scale = replay_sample_->scale;
    }
    EyeDraw draw;
    draw.near_m = options_.modes.orbit.near_m;
    draw.far_m = options_.modes.orbit.far_m;
    draw.view = scaledView(eye, scale);
    draw.projection = render::projectionMatrix(options_.modes.orbit.vfov_deg, double(fb_w) / fb_h,
                                               draw.near_m, draw.far_m);
    if (!desktop_target_.ensure(fb_w, fb_h)) return;
    if (timer_query_) glBeginQuery(GL_TIME_ELAPSED, timer_query_);
    renderer_->planFrame(std::span<const EyeDraw>(&draw, 1), options_.point_budget, options_.cull);
    points_drawn_ = 0;
    drawEyeAndOverlay(desktop_target_, draw, 0, 0, 0, fb_w, fb_h, points_drawn_);
    const double cpu_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    endGpuTimer();
    if (!xr_ && !quitting_) {
        ++frames_;
        logFrame(false, {head, head}, {eye, eye}, nullptr, cpu_ms);
        frameCounted();
    }
}

void ViewerApp::endGpuTimer() {
    if (!timer_query_) return;
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer_query_, GL_QUERY_RESULT, &ns);   // waits: benchmarks only
    last_gpu_ms_ = double(ns) * 1e-6;
}

void ViewerApp::drawPanel(double frame_ms, int fb_w, int fb_h) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    PanelView v;
    v.style = &style_;
    v.mode = modes_.mode();
    if (xr_) v.xr_state = xr_->focused() ? "focused" : (xr_->running() ? "running" : "waiting");
    v.frame_ms = frame_ms;
    v.points_uploaded = renderer_->uploadedPoints();
    v.points_arrived = feed_->pointsArrived();
    v.points_drawn = points_drawn_;
    v.cells = renderer_->cellCount();
    v.point_budget = options_.point_budget;
    v.loading = !feed_->finished();
    v.picking_ready = pointer_.ready();
    v.pick_ms = pointer_.lastPickMs();
    v.scale = zoom_.scale();
    v.cut_enabled = &cut_enabled_;
    v.cut_radius_m = &cut_radius_m_;
    v.highlight_candidates = &highlight_candidates_;
    v.candidates = candidates_.size();
    v.snap_turn = &snap_turn_;
    v.vignette = &vignette_;
    v.headset_panel = xr_ ? &headset_panel_ : nullptr;
    if (trial_.index >= 0) {
        char text[256];
        std::snprintf(text, sizeof text, "trial %d of %d: %s, %.1f s", trial_.index + 1, trials_total_,
                      trial_.setup.name.c_str(), trialTime());
        v.trial = text;
    }
    if (trial_.designated_local) {
        const glm::dvec3 w = *trial_.designated_local + feed_->origin();
        char text[160];
        std::snprintf(text, sizeof text, "designated %.2f %.2f %.2f (Enter / confirm button to confirm)", w.x, w.y, w.z);
        v.designation = text;
    }
    reset_zoom_button_ = drawSettingsPanel(v);
    if (trial_.ready_screen)
        drawReadyScreen(trial_.index, trials_total_, trial_.setup.name, readyToStart(), trial_.setup.time_limit_s);
    // The picked point's panel beside the dot (desktop: where the dot is on screen).
    if (pointer_.hit() && !xr_ && fb_w > 0 && fb_h > 0 && !trial_.ready_screen) {
        const RigPose eye = headLocal();
        const glm::dmat4 view = scaledView(eye, zoom_.scale());
        const glm::dmat4 proj = render::projectionMatrix(options_.modes.orbit.vfov_deg, double(fb_w) / fb_h,
                                                         options_.modes.orbit.near_m, options_.modes.orbit.far_m);
        const glm::dvec4 clip = proj * view * glm::dvec4(pointer_.hit()->local, 1.0);
        if (clip.w > 0.0) {
            const ImVec2 size = ImGui::GetIO().DisplaySize;
            const float sx = float((clip.x / clip.w * 0.5 + 0.5) * size.x);
            const float sy = float((0.5 - clip.y / clip.w * 0.5) * size.y);
            drawPickPanel(sx, sy, *pointer_.hit(), feed_->origin(), eye.position, feed_->fields().height_above_ground);
        }
    } else if (pointer_.hit() && xr_) {
        drawPickPanel(10.0f, ImGui::GetIO().DisplaySize.y - 90.0f, *pointer_.hit(), feed_->origin(),
                      headLocal().position, feed_->fields().height_above_ground);
    }
    ImGui::Render();
    if (xr_ && headset_panel_ && fb_w > 0 && fb_h > 0 && panel_target_.ensure(fb_w, fb_h)) {
        // The same windows into a texture for the headset's quad (shown from the next frame).
        glBindFramebuffer(GL_FRAMEBUFFER, panel_target_.fbo);
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, fb_w, fb_h);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool ViewerApp::screenshot(int fb_w, int fb_h) {
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(fb_w) * fb_h * 3);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, fb_w, fb_h, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
    if (!render::logGl("glReadPixels (screenshot)", __FILE__, __LINE__)) return false;
    try {
        engine::writePng(options_.screenshot, pixels, fb_w, fb_h, 3, engine::PngRows::BottomUp);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ladarvr: view: --screenshot: %s\n", e.what());
        return false;
    }
    log_.set("screenshot", nlohmann::json{{"path", options_.screenshot.string()}, {"width", fb_w},
                                          {"height", fb_h}, {"frame", frames_}});
    return true;
}

// --- trials --------------------------------------------------------------------------------
double ViewerApp::trialTime() const {
    if (!trial_.running) return 0.0;
    return std::chrono::duration<double>(Clock::now() - trial_.started).count();
}

bool ViewerApp::readyToStart() const {
    return (feed_->finished() && !feed_->error().empty()) || pointer_.ready();
}

void ViewerApp::beginTrial(int index) {
    if (trial_.index >= 0) source_->end(trial_.index);   // before its feed goes
    trial_ = TrialState{};
    trial_.index = index;
    loaded_since_frame_ = -1;   // loaded+N counts from this trial's cloud
    trial_.ready_screen = true;
    trial_.own_feed = std::make_unique<CloudFeed>();
    trial_.own_feed->enableLodOrder();
    feed_ = trial_.own_feed.get();
    renderer_ = std::make_unique<PointRenderer>();   // a fresh cloud on the GPU
    index_future_ = {};
    index_points_.clear();
    index_.reset();
    pointer_.setIndex(nullptr);
    pointer_.update(std::nullopt);
    modes_ = ModeController(options_.modes, glm::dvec3(0.0));
    zoom_.reset();
    centre_final_ = false;
    aim_world_.reset();
    cut_enabled_ = false;
    trial_.setup = source_->begin(index, *feed_);
    candidates_.set({}, glm::dvec3(0.0));
    log_.event("trial " + std::to_string(index) + ": ready screen (" + trial_.setup.name + ")");
    if (!options_.quiet)
        std::fprintf(stderr, "ladarvr: study: trial %d of %d (%s): ready screen\n", index + 1, trials_total_,
                     trial_.setup.name.c_str());
}

void ViewerApp::endTrial(Decision decision) {
    if (!trial_.running) return;
    trial_.running = false;
    TrialOutcome& o = trial_.outcome;
    o.decision = decision;
    o.time_to_decision_s = std::chrono::duration<double>(Clock::now() - trial_.started).count();
    o.target_known = index_ && index_->hasTargets();
    if (trial_.designated_local) {
        o.designated_world = *trial_.designated_local + feed_->origin();
        if (index_) o.target_distance_m = index_->nearestTargetDistance(*trial_.designated_local);
    }
    if (observer_) {
        for (std::size_t i = 0; i < candidates_.size(); ++i)
            if (candidates_.verdict(i) == Verdict::Unreviewed)
                observer_->onVerdict(trial_.index, o.time_to_decision_s, candidates_.candidate(i), Verdict::Unreviewed);
        observer_->onEnd(trial_.index, o);
    }
    decisions_.push_back({{"trial", trial_.index}, {"frame", frames_}, {"action", "end"},
                          {"decision", decisionName(decision)}});
    log_.event("trial " + std::to_string(trial_.index) + ": " + decisionName(decision));
    if (!options_.quiet)
        std::fprintf(stderr, "ladarvr: study: trial %d ended: %s after %.1f s\n", trial_.index + 1,
                     decisionName(decision), o.time_to_decision_s);
}

std::optional<LocalRay> ViewerApp::pointerRay(const OperatorInput& in) const {
    const RigPose rig = modes_.rig();
    const RigPose head = headLocal();
    if (aim_world_) {   // a script's aim: from the head to a world point
        const glm::dvec3 d = *aim_world_ - feed_->origin() - head.position;
        if (glm::length(d) > 0.0) return LocalRay{head.position, glm::normalize(d)};
    }
    if (in.controller_ray) {
        const glm::dvec3 o = rig.apply(zoom_.apply(in.controller_ray->origin));
        const glm::dvec3 d = rig.rotation * in.controller_ray->direction;
        return LocalRay{o, glm::normalize(d)};
    }
    double cx = 0.0, cy = 0.0;
    int win_w = 0, win_h = 0;
    glfwGetWindowSize(window_, &win_w, &win_h);
    if (!xr_ && win_w > 0 && win_h > 0 && input_.cursor(cx, cy)) {
        const double t = std::tan(options_.modes.orbit.vfov_deg * std::numbers::pi / 360.0);
        const double nx = 2.0 * cx / win_w - 1.0, ny = 1.0 - 2.0 * cy / win_h;
        const glm::dvec3 dir_eye(nx * t * double(win_w) / win_h, ny * t, -1.0);
        return LocalRay{head.position, glm::normalize(head.rotation * dir_eye)};
    }
    return std::nullopt;
}

void ViewerApp::streamAndIndex() {
    renderer_->stream(*feed_, options_.upload_points_per_frame, &index_points_);
    if (!index_future_.valid() && !index_ && feed_->finished() && feed_->error().empty() &&
        renderer_->pendingPoints() == 0 && !index_points_.empty()) {
        index_future_ = std::async(std::launch::async, [points = std::move(index_points_)] {
            return std::shared_ptr<const PickIndex>(std::make_shared<PickIndex>(points));
        });
        index_points_ = {};
    }
    if (index_future_.valid() && index_future_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        index_ = index_future_.get();
        pointer_.setIndex(index_);
        log_.event("picking ready: " + std::to_string(index_->size()) + " points indexed");
    }
    if (!trial_.candidates_placed && feed_->finished()) {   // the origin is known by now
        trial_.candidates_placed = true;
        candidates_.set(trial_.index >= 0 ? trial_.setup.candidates : options_.candidates, feed_->origin());
    }
}

void ViewerApp::applyInput(const OperatorInput& in, double dt) {
    auto record = [&](const char* action, nlohmann::json extra = nlohmann::json::object()) {
        extra["frame"] = frames_;
        extra["action"] = action;
        if (trial_.index >= 0) extra["trial"] = trial_.index;
        decisions_.push_back(std::move(extra));
    };
    if (trial_.ready_screen) {
        if (in.next && readyToStart() && feed_->error().empty()) {
            trial_.ready_screen = false;
            trial_.running = true;
            trial_.started = Clock::now();
            if (observer_) observer_->onStart(trial_.index);
            record("start");
            if (!options_.quiet) std::fprintf(stderr, "ladarvr: study: trial %d started\n", trial_.index + 1);
        }
        return;   // nothing else acts on the ready screen
    }
    if (in.toggle_mode) toggleMode(in.toggle_source);
    // Zoom: wheel about the pointer's hit (or straight ahead), script scale, two-hand grab.
    const RigPose rig = modes_.rig();
    auto trackingOf = [&](const glm::dvec3& local) {   // local point -> tracking frame
        return zoom_.unapply(glm::transpose(rig.rotation) * (local - rig.position));
    };
    const glm::dvec3 pivot = pointer_.hit() ? trackingOf(pointer_.hit()->local) : headTracking().position;
    if (in.wheel != 0.0) zoom_.scaleAbout(pivot, zoom_.scale() * std::pow(1.15, in.wheel));
    if (in.set_scale) {
        zoom_.scaleAbout(pivot, *in.set_scale);
        record("grab_scale", {{"scale", zoom_.scale()}});
    }
    if (in.grab_hands) {
        if (!zoom_.grabbing()) zoom_.beginGrab(in.grab_hands->first, in.grab_hands->second);
        else zoom_.updateGrab(in.grab_hands->first, in.grab_hands->second);
    } else if (zoom_.grabbing()) {
        zoom_.endGrab();
    }
    if (in.reset_zoom || reset_zoom_button_) zoom_.reset();
    if (in.cycle_colour) {   // the next mode colourModeName knows, then the first again
        const int next = static_cast<int>(style_.colour) + 1;
        style_.colour = std::string(colourModeName(static_cast<ColourMode>(next))) == "?" ? ColourMode::File
                                                                                          : static_cast<ColourMode>(next);
    }
    if (in.toggle_cut) cut_enabled_ = !cut_enabled_;
    if (in.cut_radius_step != 0.0) cut_radius_m_ = std::clamp(cut_radius_m_ * std::pow(1.25, in.cut_radius_step), 1.0, 500.0);
    // Comfort: snap turn in free mode (headset).
    if (in.snap_turn != 0 && modes_.mode() == ViewMode::Free) {
        const double now_s = std::chrono::duration<double>(Clock::now() - start_).count();
        if (now_s - last_snap_s_ >= options_.snap_turn_debounce_s) {
            modes_.snapTurn(in.snap_turn * options_.snap_turn_deg);
            last_snap_s_ = now_s;
        }
    }
    // Modes advance with real time; free-mode speed follows the zoom.
    Motion motion = in.motion;
    const double k = 1.0 / zoom_.scale();
    motion.forward *= k;
    motion.right *= k;
    motion.up *= k;
    if (trial_.running && modes_.mode() == ViewMode::Free) trial_.outcome.seconds_in_free_mode += dt;
    // The vignette fades in over 0.2 s of motion (or a snap) and out over 0.3 s at rest.
    const bool moving = modes_.mode() == ViewMode::Free &&
                        (std::abs(motion.forward) + std::abs(motion.right) + std::abs(motion.up) + std::abs(motion.turn) >
                             1e-3 || in.snap_turn != 0);
    vignette_strength_ = std::clamp(vignette_strength_ + (moving ? dt / 0.2 : -dt / 0.3), 0.0, 1.0);
    modes_.update(dt, motion, zoom_.apply(headTracking()));

    // The pointer and the candidates follow this frame's ray.
    const std::optional<LocalRay> ray = pointerRay(in);
    pointer_.update(ray);
    candidates_.update(ray);

    const double t_s = trialTime();
    if (in.designate) {
        if (pointer_.hit()) {
            trial_.designated_local = pointer_.hit()->local;
            const glm::dvec3 w = pointer_.hit()->local + feed_->origin();
            if (trial_.running) {
                ++trial_.outcome.designations;
                if (!trial_.outcome.time_to_first_designation_s) trial_.outcome.time_to_first_designation_s = t_s;
                if (observer_) observer_->onDesignate(trial_.index, t_s, w);
            }
            record("designate", {{"world", vec(w)}, {"label", std::string(engine::roleName(pointer_.hit()->label))}});
        } else {
            record("designate", {{"world", nullptr}});
        }
    }
    if (in.reject) {
        if (const auto i = candidates_.decide(Verdict::Rejected)) {
            if (observer_ && trial_.running) observer_->onVerdict(trial_.index, t_s, candidates_.candidate(*i), Verdict::Rejected);
            record("reject", {{"candidate", candidates_.candidate(*i).id}});
        } else {
            trial_.designated_local.reset();
            record("reject", {{"candidate", nullptr}});
        }
    }
    if (in.confirm) {
        if (const auto i = candidates_.decide(Verdict::Confirmed)) {
            // Confirming a candidate confirms it as the target: the trial ends with the
            // designation made, else the pointer's hit, else the box's centre.
            if (observer_ && trial_.running) observer_->onVerdict(trial_.index, t_s, candidates_.candidate(*i), Verdict::Confirmed);
            record("confirm", {{"candidate", candidates_.candidate(*i).id}});
            if (!trial_.designated_local)
                trial_.designated_local = pointer_.hit() ? pointer_.hit()->local
                                                         : candidates_.candidate(*i).centre_world - feed_->origin();
            endTrial(Decision::Confirm);
        } else if (trial_.designated_local) {
            record("confirm", {{"world", vec(*trial_.designated_local + feed_->origin())}});
            endTrial(Decision::Confirm);
        } else {
            record("confirm", {{"world", nullptr}});
        }
    }
    if (in.no_target && trial_.running) {
        record("no_target");
        endTrial(Decision::NoTarget);
    } else if (in.no_target) {
        record("no_target");
    }
    if (trial_.running && trial_.setup.time_limit_s > 0.0 && trialTime() >= trial_.setup.time_limit_s)
        endTrial(Decision::Timeout);

    overlay_list_.clear();
    pointer_.draw(overlay_list_, 200.0, !in.controller_ray);
    if (trial_.designated_local) {
        overlay_list_.dots.push_back({*trial_.designated_local, glm::vec4(1.0f, 0.2f, 1.0f, 1.0f)});
        const glm::dvec3 c = *trial_.designated_local;
        const double r = 1.0 / zoom_.scale();   // a 2 m cross at life size
        overlay_list_.line(c - glm::dvec3(r, 0, 0), c + glm::dvec3(r, 0, 0), glm::vec4(1.0f, 0.2f, 1.0f, 1.0f));
        overlay_list_.line(c - glm::dvec3(0, r, 0), c + glm::dvec3(0, r, 0), glm::vec4(1.0f, 0.2f, 1.0f, 1.0f));
        overlay_list_.line(c - glm::dvec3(0, 0, r), c + glm::dvec3(0, 0, r), glm::vec4(1.0f, 0.2f, 1.0f, 1.0f));
    }
    candidates_.draw(overlay_list_, highlight_candidates_);
    if (replay_sample_ && replay_sample_->hit_world)
        overlay_list_.dots.push_back({*replay_sample_->hit_world - feed_->origin(), glm::vec4(1.0f, 1.0f, 0.2f, 1.0f)});
}

int ViewerApp::run(CloudFeed* feed, TrialSource* source, TrialObserver* observer) {
    StopSignal stop_signal;   // before the window: a signal from now on ends the loop cleanly
    setup();
    source_ = source;
    observer_ = observer;
    feed_ = feed;
    if (source_) {
        trials_total_ = source_->count();
        beginTrial(0);
    }
    int status = 0;
    std::string exit_reason = "window closed";
    std::size_t script_next = 0;
    long script_last_frame = 0;   // frames_ when the previous script action ran (+N)
    bool& quitting = quitting_;
    bool screenshot_done = false;
    Clock::time_point quit_deadline{}, last = Clock::now();
    double frame_ms = 0.0;
    bool was_focused = false;
    std::string feed_error_reported;   // non-empty: loading failed
    auto startQuit = [&](const std::string& reason) {
        if (quitting) return;
        quitting = true;
        exit_reason = reason;
        quit_deadline = Clock::now() + std::chrono::seconds(3);
        if (xr_ && xr_->running()) xr_->requestExit();
    };

    while (true) {
        glfwPollEvents();
        OperatorInput in = input_.take(window_);
        // Scripted actions for the frame about to be counted. A `next` waits while the
        // trial's cloud is still loading (the ready screen cannot be dismissed then), so
        // a script does not race the loader.
        // An action that ends a trial or leaves a ready screen ends this frame's actions:
        // the next ones act on what follows it.
        bool script_barrier = false;
        while (script_next < options_.script.size() && !script_barrier) {
            const auto& ev = options_.script[script_next];
            const long base = ev.after_desktop  ? desktop_since_frame_
                              : ev.after_loaded ? loaded_since_frame_
                              : ev.relative     ? script_last_frame
                                                : 0;
            if (base < 0 || ev.frame + base > frames_) break;
            if (ev.key == ScriptEvent::Key::Next && trial_.ready_screen && !readyToStart()) break;
            ++script_next;
            script_last_frame = frames_;
            script_barrier = ev.key == ScriptEvent::Key::Next || ev.key == ScriptEvent::Key::Confirm ||
                             ev.key == ScriptEvent::Key::NoTarget;
            switch (ev.key) {
                case ScriptEvent::Key::Space:
                    if (!trial_.ready_screen) toggleMode("script");
                    break;
                case ScriptEvent::Key::Escape: in.quit = true; break;
                case ScriptEvent::Key::Aim: aim_world_ = glm::dvec3(ev.point[0], ev.point[1], ev.point[2]); break;
                case ScriptEvent::Key::Designate: in.designate = true; break;
                case ScriptEvent::Key::Confirm: in.confirm = true; break;
                case ScriptEvent::Key::Reject: in.reject = true; break;
                case ScriptEvent::Key::NoTarget: in.no_target = true; break;
                case ScriptEvent::Key::GrabScale: in.set_scale = ev.value; break;
                case ScriptEvent::Key::Next: in.next = true; break;
            }
        }
        const bool frames_done = options_.frames > 0 && frames_ >= options_.frames;
        const double elapsed_s = std::chrono::duration<double>(Clock::now() - start_).count();
        if (!quitting) {
            if (frames_done) startQuit("frames");
            else if (in.quit) startQuit("escape");
            else if (StopSignal::received()) startQuit(StopSignal::received() == SIGINT ? "SIGINT" : "SIGTERM");
            else if (glfwWindowShouldClose(window_)) startQuit("window closed");
            else if (options_.timeout_s > 0 && elapsed_s > options_.timeout_s) {
                startQuit("timeout");
                status = 1;
                std::fprintf(stderr, "ladarvr: view: timeout after %.1f s (%ld frames)\n", elapsed_s, frames_);
            }
            if (quitting) endTrial(Decision::Quit);
        }
        // Leave once the session has ended (or the runtime did not answer in time) and the
        // screenshot, if asked for, has been taken (one more uncounted frame if needed).
        if (quitting && (!xr_ || !xr_->running() || Clock::now() > quit_deadline) &&
            (options_.screenshot.empty() || screenshot_done || !feed_error_reported.empty() ||
             Clock::now() > quit_deadline))
            break;

        if (xr_) {
            const XrPoll poll = xr_->pollEvents();
            if (poll == XrPoll::Ok && xr_->focused() != was_focused) {
                was_focused = xr_->focused();
                if (!options_.quiet)
                    std::fprintf(stderr, "ladarvr: view: OpenXR session %s\n", was_focused ? "focused" : "not focused");
            }
            if (poll == XrPoll::Exit) {
                log_.event("xr: session exited");
                xr_.reset();
                if (quitting) break;
                fallBackToDesktop("the OpenXR session ended");
            } else if (poll == XrPoll::Lost) {
                fallBackToDesktop("the OpenXR runtime was lost");
                if (quitting) break;
            }
        }

        // Stream: a bounded number of points per frame keeps the frame within budget.
        streamAndIndex();
        if (feed_->finished() && !feed_->error().empty() && feed_error_reported.empty()) {
            feed_error_reported = feed_->error();
            log_.event("load error: " + feed_error_reported);
            // A file that does not read whole (or holds no point) is refused: one error line
            // (as main prints errors: escaped, capped), exit status 1, no screenshot and no
            // summary line, whatever was already shown of it.
            engine::printMessage("error", "view: " + feed_error_reported);
            status = 1;
            if (!quitting) {
                startQuit("load error");
                endTrial(Decision::Quit);
            }
        }
        if (loaded_since_frame_ < 0 && feed_->finished() && feed_->error().empty() &&
            renderer_->pendingPoints() == 0)
            loaded_since_frame_ = frames_;
        if (!centre_final_ && !renderer_->bounds().empty()) {
            modes_.setCentre(renderer_->bounds().centre());
            centre_final_ = feed_->finished() && renderer_->pendingPoints() == 0;
        }

        const Clock::time_point now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last).count();
        frame_ms = dt * 1000.0;
        frame_ms_ = frame_ms;
        last = now;
        if (xr_ && xr_->running()) {
            const XrInput xin = xr_->syncInput();
            if (xin.toggle_pressed) {
                in.toggle_mode = true;
                in.toggle_source = "controller";
            }
            in.designate = in.designate || xin.designate_pressed;
            in.next = in.next || xin.designate_pressed;   // the trigger starts a trial
            in.confirm = in.confirm || xin.confirm_pressed;
            in.reject = in.reject || xin.reject_pressed;
            in.no_target = in.no_target || xin.no_target_pressed;
            in.cycle_colour = in.cycle_colour || xin.cycle_colour_pressed;
            in.toggle_cut = in.toggle_cut || xin.toggle_cut_pressed;
            in.motion.forward += xin.move.y;
            in.motion.right += xin.move.x;
            if (snap_turn_) {
                if (std::abs(xin.turn) > 0.7f) in.snap_turn = xin.turn > 0 ? 1 : -1;
            } else {
                in.motion.turn = xin.turn;
            }
            if (xin.designate_pressed) pointer_hand_ = xin.last_designate_hand;
            const auto& aim = xin.aim[pointer_hand_] ? xin.aim[pointer_hand_] : xin.aim[1 - pointer_hand_];
            if (aim) {
                in.controller_ray = TrackingRay{aim->position, glm::mat3_cast(aim->orientation) * glm::dvec3(0, 0, -1)};
                if (xin.designate_pressed) aim_world_.reset();   // a controller took over from a script
            }
            if (xin.grab_held[0] && xin.grab_held[1] && xin.aim[0] && xin.aim[1])
                in.grab_hands = std::make_pair(xin.aim[0]->position, xin.aim[1]->position);
        }
        if (!options_.replay.empty() && centre_final_ && !replay_done_) {
            if (!replay_start_) replay_start_ = Clock::now();
            const double t = options_.replay.front().t_s + std::chrono::duration<double>(Clock::now() - *replay_start_).count();
            while (replay_next_ < options_.replay.size() && options_.replay[replay_next_].t_s <= t) ++replay_next_;
            replay_sample_ = options_.replay[replay_next_ == 0 ? 0 : replay_next_ - 1];
            if (replay_next_ >= options_.replay.size()) replay_done_ = true;   // the last sample is shown once
        } else if (replay_done_ && !quitting) {
            startQuit("replay done");
        }
        applyInput(in, dt);
        // The trial ended: the next one, or the end of the run.
        if (source_ && !trial_.running && !trial_.ready_screen && !quitting) {
            if (trial_.index + 1 < trials_total_) beginTrial(trial_.index + 1);
            else startQuit("trials done");
        }

        int fb_w = 0, fb_h = 0;
        glfwGetFramebufferSize(window_, &fb_w, &fb_h);
        if (xr_ && xr_->running()) {
            bool rendered = false;
            if (!renderXrFrame(rendered)) {
                fallBackToDesktop("the OpenXR runtime failed during a frame");
                renderDesktop(fb_w, fb_h);
            }
        } else {
            renderDesktop(fb_w, fb_h);
            if (xr_) std::this_thread::sleep_for(std::chrono::milliseconds(5));   // waiting for READY
        }
        drawPanel(frame_ms, fb_w, fb_h);
        const bool last_frame = options_.frames > 0 && frames_ >= options_.frames;
        if (!options_.screenshot.empty() && !screenshot_done && feed_error_reported.empty() &&
            (last_frame || quitting) && fb_w > 0) {
            screenshot_done = true;
            if (!screenshot(fb_w, fb_h)) status = 1;
        }
        glfwSwapBuffers(window_);
    }
    if (!options_.screenshot.empty() && !screenshot_done && feed_error_reported.empty()) {
        std::fprintf(stderr, "ladarvr: view: --screenshot: no frame was rendered\n");
        status = 1;
    }
    glFinish();
    log_.set("exit", exit_reason);
    log_.set("frames_counted", frames_);
    log_.set("frames_submitted", frames_submitted_);
    log_.set("first_points_frame", first_points_frame_);
    log_.set("points_arrived", feed_->pointsArrived());
    log_.set("points_uploaded", renderer_->uploadedPoints());
    log_.set("point_budget", options_.point_budget);
    log_.set("cull", options_.cull);
    log_.set("lod_cells", renderer_->cellCount());
    log_.set("mode_final", modeName(modes_.mode()));
    log_.set("fallback", fallback_);
    log_.set("xr_active_at_end", xr_ != nullptr);
    log_.set("orbit_centre_local", vec(modes_.centre()));
    log_.set("origin", vec(feed_->origin()));
    log_.set("actions", decisions_);
    log_.set("candidates", candidates_.log());
    log_.set("scale_final", zoom_.scale());
    log_.set("headset_panel", headset_panel_ && panel_target_.colour != 0);
    if (trial_.designated_local) log_.set("designated_world", vec(*trial_.designated_local + feed_->origin()));
    if (!options_.log_json.empty() && !log_.write(options_.log_json)) status = 1;
    if (!options_.quiet && feed_error_reported.empty())
        std::fprintf(stderr, "ladarvr: view: %ld frames (%ld submitted to OpenXR), %zu points, exit: %s\n",
                     frames_, frames_submitted_, renderer_->uploadedPoints(), exit_reason.c_str());
    if (const int sig = StopSignal::received(); sig != 0 && status == 0) status = 128 + sig;
    if (source_ && trial_.index >= 0) source_->end(trial_.index);
    return status;
}

}  // namespace

int runViewer(const ViewerOptions& options, CloudFeed& feed) {
    validate(options);
    ViewerApp app(options, !options.log_json.empty());
    return app.run(&feed, nullptr, nullptr);
}

int runViewer(const ViewerOptions& options, CloudFeed& feed, std::string& log_json) {
    validate(options);
    ViewerApp app(options, true);
    const int status = app.run(&feed, nullptr, nullptr);
    log_json = app.logJson();
    return status;
}

int runTrials(const ViewerOptions& options, TrialSource& source, TrialObserver& observer) {
    validate(options);
    if (source.count() <= 0) throw engine::Error("study: the plan has no trials");
    ViewerApp app(options, !options.log_json.empty());
    return app.run(nullptr, &source, &observer);
}

}  // namespace viewer
