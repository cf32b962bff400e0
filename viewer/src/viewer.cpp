// viewer/src/viewer.cpp: the frame loop of `ladarvr view` (paper §IV-A): desktop mirror
// window, optional OpenXR session, modes, ImGui panel, script, screenshot and run log.
//
// Setup throws engine::Error; once the loop runs nothing throws: OpenXR failures drop to
// the desktop mode with the cloud kept, GL errors are logged.
#include <render/gl.hpp>   // glad first
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <viewer/viewer.hpp>

#include "point_renderer.hpp"
#include "run_log.hpp"
#include "xr_session.hpp"

#include <engine/error.hpp>
#include <engine/png.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
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

/// Keyboard and mouse state, filled by GLFW callbacks (chained by ImGui).
struct DesktopInput {
    bool toggle = false;
    bool quit = false;
    double look_yaw_rad = 0.0, look_pitch_rad = 0.0;
    bool dragging = false;
    double last_x = 0.0, last_y = 0.0;
};

void keyCallback(GLFWwindow* window, int key, int, int action, int) {
    auto* in = static_cast<DesktopInput*>(glfwGetWindowUserPointer(window));
    if (action != GLFW_PRESS || (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard)) return;
    if (key == GLFW_KEY_SPACE) in->toggle = true;
    if (key == GLFW_KEY_ESCAPE) in->quit = true;
}

void mouseButtonCallback(GLFWwindow* window, int button, int action, int) {
    auto* in = static_cast<DesktopInput*>(glfwGetWindowUserPointer(window));
    if (button != GLFW_MOUSE_BUTTON_LEFT && button != GLFW_MOUSE_BUTTON_RIGHT) return;
    if (action == GLFW_PRESS && !(ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse)) {
        in->dragging = true;
        glfwGetCursorPos(window, &in->last_x, &in->last_y);
    } else if (action == GLFW_RELEASE) {
        in->dragging = false;
    }
}

void cursorCallback(GLFWwindow* window, double x, double y) {
    auto* in = static_cast<DesktopInput*>(glfwGetWindowUserPointer(window));
    if (!in->dragging) return;
    in->look_yaw_rad -= (x - in->last_x) * 0.004;
    in->look_pitch_rad = std::clamp(in->look_pitch_rad - (y - in->last_y) * 0.004, -1.5, 1.5);
    in->last_x = x;
    in->last_y = y;
}

nlohmann::json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
nlohmann::json quat(const glm::dquat& q) { return {q.w, q.x, q.y, q.z}; }

RigPose compose(const RigPose& a, const RigPose& b) {
    return {a.rotation * b.rotation, a.rotation * b.position + a.position};
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

class ViewerApp {
public:
    /// `record_frames`: keep per-frame records in the log (for --log-json and benchmarks;
    /// an interactive session would otherwise grow it for nothing).
    ViewerApp(const ViewerOptions& options, CloudFeed& feed, bool record_frames) : options_(options), feed_(feed),
        style_(options.style), modes_(options.modes, glm::dvec3(0.0)), record_frames_(record_frames) {}
    ~ViewerApp();
    int run();
    std::string logJson() const { return log_.json().dump(); }

private:
    void setup();
    void fallBackToDesktop(const std::string& reason);
    bool renderXrFrame(bool& rendered);
    void renderDesktop(int fb_w, int fb_h);
    void drawPanel(double frame_ms);
    void endGpuTimer();
    void toggleMode(const std::string& source);
    RigPose headPose() const;
    void logFrame(bool xr, const std::array<RigPose, 2>& eyes_t, const std::array<RigPose, 2>& eyes_local,
                  const XrFrame* xr_frame, double cpu_ms);
    bool screenshot(int fb_w, int fb_h);

    ViewerOptions options_;
    CloudFeed& feed_;
    ViewStyle style_;
    ModeController modes_;
    RunLog log_;
    DesktopInput input_;
    GLFWwindow* window_ = nullptr;
    bool imgui_ = false;
    std::unique_ptr<PointRenderer> renderer_;
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
    bool quitting_ = false;      // frames after the exit request are not counted
    GLuint timer_query_ = 0;     // GL_TIME_ELAPSED around the frame's draws (--gpu-timing)
    double last_gpu_ms_ = -1.0;
    double frame_ms_ = 0.0;      // wall time since the previous loop iteration
    bool record_frames_ = true;
    Clock::time_point start_ = Clock::now();
};

ViewerApp::~ViewerApp() {
    xr_.reset();
    if (window_) {
        glfwMakeContextCurrent(window_);
        renderer_.reset();
        for (auto& t : eye_targets_) t.destroy();
        desktop_target_.destroy();
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
    glfwSetWindowUserPointer(window_, &input_);
    glfwSetKeyCallback(window_, keyCallback);
    glfwSetMouseButtonCallback(window_, mouseButtonCallback);
    glfwSetCursorPosCallback(window_, cursorCallback);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;   // no imgui.ini next to the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
    imgui_ = true;

    renderer_ = std::make_unique<PointRenderer>();
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

RigPose ViewerApp::headPose() const {
    if (xr_) return last_head_;
    return {glm::mat3_cast(lookOrientation(input_.look_yaw_rad, input_.look_pitch_rad)), glm::dvec3(0.0)};
}

void ViewerApp::toggleMode(const std::string& source) {
    const ViewMode from = modes_.mode();
    if (xr_) modes_.toggle(last_head_);
    else modes_.toggleDesktop(input_.look_yaw_rad, input_.look_pitch_rad);
    log_.modeSwitch(frames_, modeName(from), modeName(modes_.mode()), source);
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
                        {"points_arrived", feed_.pointsArrived()},
                        {"cpu_ms", cpu_ms},
                        {"frame_ms", frame_ms_}};
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
            eyes_local[i] = compose(rig, eyes_t[i]);
            EyeDraw& draw = draws[i];
            draw.near_m = options_.modes.orbit.near_m;
            draw.far_m = options_.modes.orbit.far_m;
            draw.view = viewFromPose(eyes_local[i]);
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
            points_drawn_ += renderer_->drawEye(eye_targets_[i], draw, style_, modes_.mode(),
                                                swapchain_fbo_[i], 0, 0, w, h).points_drawn;
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
        if (first_points_frame_ < 0 && points_drawn_ > 0) first_points_frame_ = frames_;
        logFrame(true, eyes_t, eyes_local, &frame, cpu_ms);
    }
    return true;
}

void ViewerApp::renderDesktop(int fb_w, int fb_h) {
    if (fb_w <= 0 || fb_h <= 0) return;   // minimised
    const Clock::time_point t0 = Clock::now();
    const RigPose head = headPose();
    const RigPose eye = compose(modes_.rig(), head);
    EyeDraw draw;
    draw.near_m = options_.modes.orbit.near_m;
    draw.far_m = options_.modes.orbit.far_m;
    draw.view = viewFromPose(eye);
    draw.projection = render::projectionMatrix(options_.modes.orbit.vfov_deg, double(fb_w) / fb_h,
                                               draw.near_m, draw.far_m);
    if (!desktop_target_.ensure(fb_w, fb_h)) return;
    if (timer_query_) glBeginQuery(GL_TIME_ELAPSED, timer_query_);
    renderer_->planFrame(std::span<const EyeDraw>(&draw, 1), options_.point_budget, options_.cull);
    points_drawn_ = renderer_->drawEye(desktop_target_, draw, style_, modes_.mode(), 0, 0, 0, fb_w, fb_h).points_drawn;
    const double cpu_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    endGpuTimer();
    if (!xr_ && !quitting_) {
        ++frames_;
        if (first_points_frame_ < 0 && points_drawn_ > 0) first_points_frame_ = frames_;
        logFrame(false, {head, head}, {eye, eye}, nullptr, cpu_ms);
    }
}

void ViewerApp::endGpuTimer() {
    if (!timer_query_) return;
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer_query_, GL_QUERY_RESULT, &ns);   // waits: benchmarks only
    last_gpu_ms_ = double(ns) * 1e-6;
}

void ViewerApp::drawPanel(double frame_ms) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.75f);
    ImGui::Begin("ladarvr view", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("Mode: %s  (space / controller button)", modeName(modes_.mode()));
    if (xr_) ImGui::Text("OpenXR: %s", xr_->focused() ? "focused" : (xr_->running() ? "running" : "waiting"));
    else ImGui::Text("Desktop mode (drag: look, WASD/QE: move in free mode)");
    ImGui::SliderFloat("point size (px)", &style_.point_size_px, 1.0f, 16.0f, "%.1f");
    ImGui::Checkbox("attenuate with distance", &style_.attenuate);
    int colour = static_cast<int>(style_.colour);
    if (ImGui::Combo("colours", &colour, "file colours\0height jet\0white\0ground truth (target red)\0"))
        style_.colour = static_cast<ColourMode>(colour);
    ImGui::Checkbox("eye-dome lighting", &style_.eye_dome);
    if (style_.eye_dome) ImGui::SliderFloat("EDL strength", &style_.edl_strength, 0.1f, 4.0f, "%.2f");
    ImGui::Text("frame %.2f ms (%.0f Hz)", frame_ms, frame_ms > 0 ? 1000.0 / frame_ms : 0.0);
    ImGui::Text("points %zu on GPU / %zu read%s", renderer_->uploadedPoints(), feed_.pointsArrived(),
                feed_.finished() ? "" : " (loading)");
    ImGui::Text("points drawn %zu / %zu (budget %s per eye, %zu cells)", points_drawn_, renderer_->uploadedPoints(),
                options_.point_budget ? std::to_string(options_.point_budget).c_str() : "unlimited",
                renderer_->cellCount());
    ImGui::End();
    ImGui::Render();
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window_, &fb_w, &fb_h);
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

int ViewerApp::run() {
    setup();
    int status = 0;
    std::string exit_reason = "window closed";
    std::size_t script_next = 0;
    bool& quitting = quitting_;
    bool screenshot_done = false;
    Clock::time_point quit_deadline{}, last = Clock::now();
    double frame_ms = 0.0;
    bool centre_final = false, was_focused = false;
    std::string feed_error_reported;   // non-empty: loading failed

    while (true) {
        glfwPollEvents();
        // Scripted keys for the frame about to be counted.
        while (script_next < options_.script.size()) {
            const auto& ev = options_.script[script_next];
            const long base = ev.after_desktop ? desktop_since_frame_ : 0;
            if (base < 0 || ev.frame + base > frames_) break;
            ++script_next;
            if (ev.key == ScriptEvent::Key::Space) toggleMode("script");
            else input_.quit = true;
        }
        if (input_.toggle) {
            input_.toggle = false;
            toggleMode("key");
        }
        const bool frames_done = options_.frames > 0 && frames_ >= options_.frames;
        const double elapsed_s = std::chrono::duration<double>(Clock::now() - start_).count();
        if (!quitting && (frames_done || input_.quit || glfwWindowShouldClose(window_) ||
                          (options_.timeout_s > 0 && elapsed_s > options_.timeout_s))) {
            quitting = true;
            exit_reason = frames_done ? "frames" : input_.quit ? "escape"
                        : glfwWindowShouldClose(window_) ? "window closed" : "timeout";
            if (exit_reason == "timeout") {
                status = 1;
                std::fprintf(stderr, "ladarvr: view: timeout after %.1f s (%ld frames)\n", elapsed_s, frames_);
            }
            quit_deadline = Clock::now() + std::chrono::seconds(3);
            if (xr_ && xr_->running()) xr_->requestExit();
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
        renderer_->stream(feed_, options_.upload_points_per_frame);
        if (feed_.finished() && !feed_.error().empty() && feed_error_reported.empty()) {
            feed_error_reported = feed_.error();
            log_.event("load error: " + feed_error_reported);
            // A file that does not read whole (or holds no point) is refused: one line,
            // exit status 1 and no screenshot, whatever was already shown of it.
            std::fprintf(stderr, "ladarvr: view: %s\n", feed_error_reported.c_str());
            status = 1;
            if (!quitting) {
                quitting = true;
                exit_reason = "load error";
                quit_deadline = Clock::now() + std::chrono::seconds(3);
                if (xr_ && xr_->running()) xr_->requestExit();
            }
        }
        if (!centre_final && !renderer_->bounds().empty()) {
            modes_.setCentre(renderer_->bounds().centre());
            centre_final = feed_.finished() && renderer_->pendingPoints() == 0;
        }

        // Modes advance with real time.
        const Clock::time_point now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last).count();
        frame_ms = dt * 1000.0;
        frame_ms_ = frame_ms;
        last = now;
        Motion motion;
        if (xr_ && xr_->running()) {
            const XrInput xin = xr_->syncInput();
            if (xin.toggle_pressed) toggleMode("controller");
            motion.forward = xin.move.y;
            motion.right = xin.move.x;
            motion.turn = xin.turn;
        }
        if (!ImGui::GetIO().WantCaptureKeyboard) {
            auto key = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS ? 1.0 : 0.0; };
            const double boost = key(GLFW_KEY_LEFT_SHIFT) > 0 ? 4.0 : 1.0;
            motion.forward += (key(GLFW_KEY_W) - key(GLFW_KEY_S)) * boost;
            motion.right += (key(GLFW_KEY_D) - key(GLFW_KEY_A)) * boost;
            motion.up += (key(GLFW_KEY_E) - key(GLFW_KEY_Q)) * boost;
        }
        modes_.update(dt, motion, headPose());

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
        drawPanel(frame_ms);
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
    log_.set("points_arrived", feed_.pointsArrived());
    log_.set("points_uploaded", renderer_->uploadedPoints());
    log_.set("point_budget", options_.point_budget);
    log_.set("cull", options_.cull);
    log_.set("lod_cells", renderer_->cellCount());
    log_.set("mode_final", modeName(modes_.mode()));
    log_.set("fallback", fallback_);
    log_.set("xr_active_at_end", xr_ != nullptr);
    log_.set("orbit_centre_local", vec(modes_.centre()));
    log_.set("origin", vec(feed_.origin()));
    if (!options_.log_json.empty() && !log_.write(options_.log_json)) status = 1;
    if (!options_.quiet)
        std::fprintf(stderr, "ladarvr: view: %ld frames (%ld submitted to OpenXR), %zu points, exit: %s\n",
                     frames_, frames_submitted_, renderer_->uploadedPoints(), exit_reason.c_str());
    return status;
}

}  // namespace

int runViewer(const ViewerOptions& options, CloudFeed& feed) {
    validate(options);
    ViewerApp app(options, feed, !options.log_json.empty());
    return app.run();
}

int runViewer(const ViewerOptions& options, CloudFeed& feed, std::string& log_json) {
    validate(options);
    ViewerApp app(options, feed, true);
    const int status = app.run();
    log_json = app.logJson();
    return status;
}

}  // namespace viewer
