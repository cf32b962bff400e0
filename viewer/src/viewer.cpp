// viewer/src/viewer.cpp: the frame loop of `ladarvr view` and of a study's trials (paper
// §IV-A), in hello_xr's shape: poll events, gather the operator's input, update the
// tools, the modes and the trials, render the eyes, present.
//
// Input sources each return one OperatorInput (input/: desktop_input.cpp, script_player.cpp,
// xr_input_mapping.cpp for the OpenXR actions, replay_player.cpp); the tools (tools/) and
// the trial controller (trial/trial_controller.cpp) consume their merge;
// ui/eye_frame_renderer.cpp draws what they decided; frame_facts.cpp is what the run log
// records. The points come from a point source
// (viewer/point_source.hpp). Setup throws core::Error; once the loop runs nothing
// throws: OpenXR failures drop to the desktop mode with the cloud kept, GL errors are
// logged.
#include <render/gl.hpp>  // glad first
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>

#include "viewer_app.hpp"

#include "points/point_attributes.hpp"
#include "tools/candidates_tool.hpp"
#include "tools/colour_tool.hpp"
#include "tools/comfort_tool.hpp"
#include "tools/cut_tool.hpp"
#include "tools/pointer_tool.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <thread>

namespace viewer {

using Clock = ViewerApp::Clock;

ViewerApp::ViewerApp(const ViewerOptions& options, bool record_frames, TrialSource* trials, TrialObserver* observer)
    : options_(options),
      record_frames_(record_frames),
      window_(options, input_),
      script_(options.script),
      replay_(options.replay, options.replay_marks),
      trials_(trials, observer, log_, options.quiet),
      questions_(trials_, log_, options.quiet),
      style_(options.style),
      modes_(options.modes, glm::dvec3(0.0)),
      tools_(viewerTools(options)),
      headset_(log_, options.quiet),
      headset_panel_(options.headset_panel) {
    log_.set("gl", render::glDescription());
    terrain_ = options_.terrain;
    stream_.start(options_, log_);
    style_.rasterizer = stream_.rasterizer();
    eyes_ = std::make_unique<EyeFrameRenderer>(options_);
    headset_.start(window_.handle, options_.use_xr);
    glfwSwapInterval(headset_.session() || !options_.vsync ? 0 : 1);
}

RigPose ViewerApp::headTracking() const {
    if (headset_.session()) return eyes_->lastHead();
    return {glm::mat3_cast(lookOrientation(input_.lookYawRad(), input_.lookPitchRad())), glm::dvec3(0.0)};
}

void ViewerApp::toggleMode(const std::string& source) {
    const ViewMode from = modes_.mode();
    if (headset_.session())
        modes_.toggle(zoom_.apply(eyes_->lastHead()));
    else
        modes_.toggleDesktop(input_.lookYawRad(), input_.lookPitchRad());
    log_.modeSwitch(frames_, modeName(from), modeName(modes_.mode()), source);
    trials_.countModeSwitch();
    if (!options_.quiet) std::fprintf(stderr, "ladarvr: view: %s mode (%s)\n", modeName(modes_.mode()), source.c_str());
}

void ViewerApp::startQuit(const std::string& reason) {
    if (quitting_) return;
    quitting_ = true;
    exit_reason_ = reason;
    quit_deadline_ = Clock::now() + std::chrono::seconds(3);
    // A screenshot still to take is taken of this frame first (present() asks the session
    // to end then): the runtime may end it within the next poll, before a frame is drawn.
    const bool shot = options_.screenshot.empty() || screenshot_done_ || stream_.failed();
    if (headset_.running() && shot) headset_.session()->requestExit();
}

bool ViewerApp::readyToStart() const {
    // A trial in above-ground colours starts with its terrain bound (or refused), so the
    // participant never sees its colours change under them.
    return (stream_.source().finished() && !stream_.source().error().empty()) ||
           (tools_.get<PointerTool>().ready() && trials_.breakLeft() <= 0.0 && !awaitingTerrain());
}

bool ViewerApp::awaitingTerrain() const {
    return terrain_ && style_.colour == ColourMode::AboveGround && !stream_.renderer().hasTerrain() &&
           !terrain_failed_ && !stream_.failed();
}

void ViewerApp::beginTrial(int index) {
    stream_.reset(trials_.begin(index));  // a fresh cloud on the GPU
    pickable_since_frame_ = -1;           // and no pick index yet
    // The trial's own terrain for its cloud, else the run's (none in a study).
    terrain_ = trials_.setup().terrain ? trials_.setup().terrain : options_.terrain;
    terrain_failed_ = false;
    // A trial's own display settings (a study's condition); the others stay as they stand.
    if (trials_.setup().colour) style_.colour = *trials_.setup().colour;
    if (trials_.setup().eye_dome) style_.eye_dome = *trials_.setup().eye_dome;
    start_free_ = trials_.setup().start_mode == ViewMode::Free;
    tools_.offer(trials_.setup().tools.value_or(kAllTrialTools));
    tools_.beginTrial();  // no pick index, candidates or cutting volume of the last trial
    tools_.get<CutTool>().startTrial(trials_.setup().cut, trials_.setup().cut_radius_m);
    modes_ = ModeController(options_.modes, glm::dvec3(0.0));
    zoom_.reset();
    aim_world_.reset();
}

TrialContext ViewerApp::trialContext() {
    return {frames_, stream_.source().origin(), &tools_.get<PointerTool>(), &tools_.get<CandidatesTool>(),
            stream_.picks().get()};
}

int ViewerApp::run(CloudFeed* feed, PointSource* points) {
    if (trials_.study()) {
        // The questions before the first trial come up over its ready screen (its cloud
        // loads meanwhile); a resumed session with only questions left shows no cloud.
        questions_.ask(0);
        if (trials_.total() > 0) {
            beginTrial(0);
        } else {
            plain_source_ = std::make_unique<CloudFeedSource>(empty_feed_);
            stream_.reset(*plain_source_);
        }
    } else if (points) {
        stream_.reset(*points);
    } else {
        plain_source_ = std::make_unique<CloudFeedSource>(*feed);
        stream_.reset(*plain_source_);
    }
    while (true) {
        glfwPollEvents();
        OperatorInput in = gatherInput();
        checkQuit(in);
        if (!pollXr()) break;
        const Clock::time_point source_start = Clock::now();
        updateSource();
        source_ms_ = std::chrono::duration<double, std::milli>(Clock::now() - source_start).count();
        const Clock::time_point now = Clock::now();
        const double dt = std::chrono::duration<double>(now - last_).count();
        frame_ms_ = dt * 1000.0;
        last_ = now;
        if (headset_.running()) {  // the frame first: its controllers and eyes share its display time
            eyes_->beginXr(*headset_.session());
            merge(in, xr_input_.map(headset_.session()->syncInput(), tools_.get<ComfortTool>().snapTurn()));
        }
        // A replay plays once its cloud is whole and the terrain of its colours is bound.
        merge(in, replay_.take(stream_.centreFinal() && !awaitingTerrain(), Clock::now()));
        update(in, dt);
        int fb_w = 0, fb_h = 0;
        glfwGetFramebufferSize(window_.handle, &fb_w, &fb_h);
        render(fb_w, fb_h);
        present(fb_w, fb_h);
    }
    return finish(status_);
}

OperatorInput ViewerApp::gatherInput() {
    OperatorInput in = input_.take(window_.handle);
    const ScriptClock clock{frames_,
                            headset_.desktopSinceFrame(),
                            stream_.loadedSinceFrame(),
                            trials_.readyScreen() && (!readyToStart() || questions_.active()),
                            questions_.awaitsPointAnswer(),
                            pickable_since_frame_,
                            questions_.active()};
    merge(in, script_.take(clock));
    return in;
}

void ViewerApp::checkQuit(const OperatorInput& in) {
    if (quitting_) return;
    const double elapsed_s = std::chrono::duration<double>(Clock::now() - start_).count();
    if (framesDone())
        startQuit("frames");
    else if (in.quit)
        startQuit("escape");
    else if (StopSignal::received())
        startQuit(StopSignal::received() == SIGINT ? "SIGINT" : "SIGTERM");
    else if (glfwWindowShouldClose(window_.handle))
        startQuit("window closed");
    else if (options_.timeout_s > 0 && elapsed_s > options_.timeout_s) {
        startQuit("timeout");
        status_ = 1;
        std::fprintf(stderr, "ladarvr: view: timeout after %.1f s (%ld frames)\n", elapsed_s, frames_);
    }
    if (quitting_) trials_.end(Decision::Quit, trialContext());
}

/// Leaves (false) once quitting and the session has ended (or the runtime did not answer
/// in time) and the screenshot, if asked for, was taken; else runs the session's events.
bool ViewerApp::pollXr() {
    const bool late = Clock::now() > quit_deadline_;
    const bool shot = options_.screenshot.empty() || screenshot_done_ || stream_.failed() || late;
    if (quitting_ && (!headset_.running() || late) && shot) return false;
    return headset_.poll(quitting_, frames_);
}

/// Streams a bounded number of points (the frame stays within budget), picks up the pick
/// index, places the candidates, and refuses a cloud that failed to load.
void ViewerApp::updateSource() {
    const SourceEvents ev = stream_.update(frames_, log_);
    if (ev.picks_ready) tools_.get<PointerTool>().setIndex(stream_.picks());
    if (ev.picks_ready && pickable_since_frame_ < 0) pickable_since_frame_ = frames_;
    if (trials_.placeCandidates(stream_.source().originFinal()))
        tools_.get<CandidatesTool>().set(trials_.study() ? trials_.setup().candidates : options_.candidates,
                                         stream_.source().origin());
    if (!ev.load_error.empty()) {
        // A file that does not read whole (or holds no point) is refused: one error line
        // (as main prints errors: escaped, capped), exit status 1, no screenshot and no
        // summary line, whatever was already shown of it.
        platform::printMessage("error", "view: " + ev.load_error);
        status_ = 1;
        if (!quitting_) {
            startQuit("load error");
            trials_.end(Decision::Quit, trialContext());
        }
    }
    // Once points are in, the cloud's fields are known: above-ground colours without heights
    // above ground fall back to height colours, said once (the point shader shows them);
    // with a terrain coming, they wait for it instead.
    if (stream_.renderer().uploadedPoints() > 0) {
        takeTerrain();
        if (!terrain_) tools_.get<ColourTool>().noteCloud(style_.colour, stream_.source().fields().height_above_ground);
    }
    if (stream_.centreChanged()) {
        // A cloud our generator made (it carries the range field) keeps the paper's orbit.
        const core::Bounds& cloud = stream_.cloudBounds();
        if (stream_.source().fields().range)
            modes_.setCentre(cloud.centre());
        else
            modes_.setCloudBounds(cloud.lo, cloud.hi);
    }
}

bool ViewerApp::framesDone() const {
    // Above-ground colours waiting for their terrain are not the picture the run is for.
    return options_.frames > 0 && frames_ >= options_.frames && !awaitingTerrain();
}

void ViewerApp::takeTerrain() {
    if (!terrain_) return;
    std::optional<ViewTerrain> terrain = terrain_->take();
    if (terrain && terrain->empty()) {
        terrain.reset();
        terrain_->fail("the terrain handed over holds no cells");
    }
    if (terrain) {
        stream_.renderer().setTerrain(*terrain, stream_.source().origin(), stream_.source());
        if (!options_.quiet)
            std::fprintf(stderr, "ladarvr: view: above-ground colours from %s\n",
                         platform::messageLine(terrain->source).c_str());
        log_.set("terrain", nlohmann::json{{"source", terrain->source},
                                           {"cells", std::size_t(terrain->nx) * std::size_t(terrain->ny)}});
        trials_.noteTerrain(terrain->source, {});
    }
    if (std::optional<std::string> why = terrain_->takeFailure()) {
        terrain_failed_ = true;
        platform::printMessage("warning", "view: no terrain for above-ground colours: " + *why + "; showing heights");
        log_.set("terrain", nlohmann::json{{"failure", *why}});
        trials_.noteTerrain({}, *why);
    }
}

void ViewerApp::update(OperatorInput in, double dt) {
    if (in.aim_world) aim_world_ = in.aim_world;
    if (in.release_aim) aim_world_.reset();
    if (in.replay) replay_sample_ = in.replay;
    if (in.replay_done && !quitting_) startQuit("replay done");
    for (const TrialMark& mark : in.replay_marks) trials_.replayMark(mark, trialContext());
    if (questions_.active()) {
        const EyeTarget& panel = eyes_->panelTarget();
        questions_.update(
            in, {frames_, headset_.session() != nullptr, panel.width, panel.height, eyes_->lastHead().position});
        overlay_list_.clear();
    } else if (trials_.handleReadyScreen(in, readyToStart() && stream_.source().error().empty(), frames_)) {
        overlay_list_.clear();
    } else {
        if (start_free_) {  // the condition's start mode, once the cloud and its centre are in
            start_free_ = false;
            if (modes_.mode() != ViewMode::Free) {
                if (headset_.session())
                    modes_.toggle(zoom_.apply(eyes_->lastHead()));
                else
                    modes_.toggleDesktop(input_.lookYawRad(), input_.lookPitchRad());
                log_.modeSwitch(frames_, modeName(ViewMode::Automatic), modeName(ViewMode::Free), "condition");
            }
        }
        if (in.toggle_mode) toggleMode(in.toggle_source);
        updateTools(in, dt);
        // The trial's designation mark goes over the pointer's dot and under the boxes.
        overlay_list_.clear();
        tools_.draw(ToolLayer::UnderDesignation, overlay_list_);
        trials_.draw(overlay_list_, zoom_.scale());
        tools_.draw(ToolLayer::OverDesignation, overlay_list_);
        if (replay_sample_ && replay_sample_->hit_world)
            overlay_list_.dots.push_back(
                {*replay_sample_->hit_world - stream_.source().origin(), {1.0f, 1.0f, 0.2f, 1.0f}});
    }
    // The trial ended: the questions after it, then the next one, or the end of the run.
    if (trials_.study() && !trials_.running() && !trials_.readyScreen() && !quitting_ && !questions_.active()) {
        const int gap = trials_.index() + 1;
        questions_.ask(gap);
        if (!questions_.active()) {
            if (gap < trials_.total())
                beginTrial(gap);
            else
                startQuit("trials done");
        }
    }
}

/// The tools' stages in order, the frame loop's work between them: the motion scaled by
/// the zoom the View stage left, the rig moved after the comfort tool's snap turn, the
/// pointer's ray after the rig, and the trial's decision last.
void ViewerApp::updateTools(OperatorInput& in, double dt) {
    const PointerTool& pointer = tools_.get<PointerTool>();
    const RigPose rig = modes_.rig();
    ToolFrame f;
    f.dt_s = dt;
    f.now_s = std::chrono::duration<double>(Clock::now() - start_).count();
    f.modes = &modes_;
    f.zoom = &zoom_;
    f.style = &style_;
    f.actions = &tool_actions_;
    CutVolume cut;  // what the cut tool leaves of it (off while the trial leaves the tool out)
    f.designated = trials_.designated();
    f.cut = &cut;
    // The zoom's pivot: the pointer's hit (in the tracking frame), else the head.
    f.zoom_pivot_tracking = pointer.hit()
                                ? zoom_.unapply(glm::transpose(rig.rotation) * (pointer.hit()->local - rig.position))
                                : headTracking().position;
    in.reset_zoom = in.reset_zoom || reset_zoom_button_;
    tools_.update(ToolStage::View, in, f);
    recordToolActions();
    // Modes advance with real time; free-mode speed follows the zoom.
    const double k = 1.0 / zoom_.scale();
    f.motion = {in.motion.forward * k, in.motion.right * k, in.motion.up * k, in.motion.turn};
    if (modes_.mode() == ViewMode::Free) trials_.addFreeModeSeconds(dt);
    tools_.update(ToolStage::Motion, in, f);
    recordToolActions();
    modes_.update(dt, f.motion, zoom_.apply(headTracking()));
    // The pointer and the candidates follow this frame's ray; the trial decides.
    f.ray = pointerRay(in);
    tools_.update(ToolStage::Aim, in, f);
    recordToolActions();
    trials_.decide(in, trialContext());
}

/// What the tools asked to record (a script's grab_scale), into the trial's decisions.
void ViewerApp::recordToolActions() {
    for (ToolAction& a : tool_actions_) trials_.record(a.action, frames_, std::move(a.extra));
    tool_actions_.clear();
}

std::optional<LocalRay> ViewerApp::pointerRay(const OperatorInput& in) const {
    PointerSources p{modes_.rig(),
                     headLocal(),
                     &zoom_,
                     std::nullopt,
                     in.controller_ray,
                     std::nullopt,
                     0,
                     0,
                     options_.modes.orbit.vfov_deg};
    if (aim_world_) p.aim_local = *aim_world_ - stream_.source().origin();
    double cx = 0.0, cy = 0.0;
    glfwGetWindowSize(window_.handle, &p.window_w, &p.window_h);
    if (!headset_.session() && input_.cursor(cx, cy)) p.cursor_px = glm::dvec2(cx, cy);
    p.replay = !options_.replay.empty();
    return pointerRayOf(p);
}

/// Where the operator works, drawn whole whatever the point budget: around the pointer's
/// hit, the designated point and inside the cutting volume.
LodFocus ViewerApp::operatorFocus(const CutVolume& cut) const {
    LodFocus focus;
    if (const std::optional<PickHit>& hit = tools_.get<PointerTool>().hit())
        focus.spheres.push_back({hit->local, kPointerFocusRadius_m});
    if (trials_.designated()) focus.spheres.push_back({*trials_.designated(), kDesignationFocusRadius_m});
    if (cut.enabled) focus.spheres.push_back({cut.centre_local, cut.radius_m});
    return focus;
}

void ViewerApp::render(int fb_w, int fb_h) {
    FrameView view;
    view.rig = modes_.rig();
    view.zoom = &zoom_;
    view.head_tracking = headTracking();
    view.style = &style_;
    view.mode = replay_sample_ ? replay_sample_->mode : modes_.mode();
    view.cut = tools_.get<CutTool>().volume(trials_.designated());
    stream_.renderer().setFocus(operatorFocus(view.cut));
    view.overlay = &overlay_list_;
    view.blank = trials_.readyScreen() || questions_.active();
    view.headset = headset_.session() != nullptr;
    view.replay = replay_sample_ ? &*replay_sample_ : nullptr;
    view.origin = stream_.source().origin();
    eyes_->show_panel = headset_panel_ || questions_.active();
    FrameResult result;
    if (headset_.running()) {
        if (!eyes_->renderXr(*headset_.session(), stream_.renderer(), view, fb_w, fb_h, result)) {
            headset_.fallBack("the OpenXR runtime failed during a frame", frames_);
            eyes_->renderDesktop(stream_.renderer(), view, fb_w, fb_h, result);
            frameCounted(result, false);
        } else {
            if (result.rendered && !quitting_) ++frames_submitted_;
            frameCounted(result, true);
        }
    } else {
        eyes_->renderDesktop(stream_.renderer(), view, fb_w, fb_h, result);
        if (!headset_.session()) {
            frameCounted(result, false);
        } else {  // waiting for READY: drawn, not counted
            if (result.rendered) {
                points_drawn_ = result.points_drawn;
                points_drawn_per_eye_ = result.points_drawn_per_eye;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }
}

/// After a frame was drawn: counts it (not after the exit request), logs it, and hands the
/// trial's observer its trace sample.
void ViewerApp::frameCounted(const FrameResult& result, bool xr) {
    if (!result.rendered) return;
    points_drawn_ = result.points_drawn;
    points_drawn_per_eye_ = result.points_drawn_per_eye;
    if (quitting_) return;
    ++frames_;
    // The first counted frame is an event a caller can wait for (a test's signal, a demo).
    if (frames_ == 1 && !options_.quiet) std::fprintf(stderr, "ladarvr: view: first frame drawn\n");
    const PointRenderer& points = stream_.renderer();
    if (record_frames_) {
        FrameFacts facts{frames_,
                         std::chrono::duration<double>(Clock::now() - start_).count(),
                         modes_.mode(),
                         modes_.centre(),
                         xr,
                         points_drawn_,
                         points.uploadedPoints(),
                         stream_.source().pointsArrived(),
                         frame_ms_,
                         zoom_.scale(),
                         colourModeName(style_.colour),
                         trials_.index(),
                         eyes_->lastGpuMs(),
                         &result,
                         nlohmann::json::object()};
        facts.points_drawn_per_eye = points_drawn_per_eye_;
        tools_.logFrame(facts.tools);
        nlohmann::json record = frameRecord(facts);
        record["stream"] = stream_.frameFigures();
        log_.frame(std::move(record));
    }
    // The adaptive budget judges the frame's own work: streaming, planning and drawing on
    // the CPU, and the GPU's time when it is measured (--gpu-timing), against the display
    // period: the runtime's in the headset (the least step between consecutive predicted
    // display times: a missed frame makes a step of two periods), else the monitor's
    // refresh with vsync, else 90 Hz.
    double period_ms = 1000.0 / 90.0;
    if (xr && result.xr_frame.display_time_ns > last_display_ns_ && last_display_ns_ > 0) {
        const double step_ms = double(result.xr_frame.display_time_ns - last_display_ns_) * 1e-6;
        display_period_ms_ = display_period_ms_ > 0.0 ? std::min(display_period_ms_, step_ms) : step_ms;
    }
    if (xr && display_period_ms_ > 0.0)
        period_ms = display_period_ms_;
    else if (!xr && options_.vsync)
        if (const GLFWvidmode* mode = glfwGetVideoMode(glfwGetPrimaryMonitor()); mode && mode->refreshRate > 0)
            period_ms = 1000.0 / mode->refreshRate;
    if (xr) last_display_ns_ = result.xr_frame.display_time_ns;
    // While the budget is measured the GPU's share must count: without --gpu-timing the
    // frame waits for the GPU here, and the wait is its share.
    double gpu_ms = std::max(0.0, eyes_->lastGpuMs());
    if (stream_.measuring() && eyes_->lastGpuMs() < 0.0) {
        const Clock::time_point t0 = Clock::now();
        glFinish();
        gpu_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    }
    if (stream_.frameTimed(source_ms_ + result.cpu_ms + gpu_ms, period_ms, points_drawn_, frames_, log_))
        style_.rasterizer = stream_.rasterizer();  // the budget's measure draws with each in turn
    if (first_points_frame_ < 0 && points_drawn_ > 0) first_points_frame_ = frames_;
    if (!trials_.running()) return;
    const RigPose head = headLocal();
    const glm::dvec3 origin = stream_.source().origin();
    std::optional<glm::dvec3> hit_world;
    if (const std::optional<PickHit>& hit = tools_.get<PointerTool>().hit()) hit_world = hit->local + origin;
    trials_.observeFrame({trials_.time(), head.position + origin, glm::quat_cast(head.rotation), modes_.mode(),
                          zoom_.scale(), hit_world});
}

void ViewerApp::present(int fb_w, int fb_h) {
    drawPanel(fb_w, fb_h);
    const bool last_frame = framesDone();
    if (!options_.screenshot.empty() && !screenshot_done_ && !stream_.failed() && (last_frame || quitting_) &&
        fb_w > 0) {
        screenshot_done_ = true;
        if (quitting_ && headset_.running()) headset_.session()->requestExit();  // held for the shot
        if (writeScreenshot(options_.screenshot, fb_w, fb_h))
            log_.set(
                "screenshot",
                nlohmann::json{
                    {"path", options_.screenshot.string()}, {"width", fb_w}, {"height", fb_h}, {"frame", frames_}});
        else
            status_ = 1;
    }
    glfwSwapBuffers(window_.handle);
}

void ViewerApp::drawPanel(int fb_w, int fb_h) {
    PanelView v;
    v.style = &style_;
    v.mode = modes_.mode();
    v.units = options_.units;
    v.length_unit = options_.length_unit;
    v.height_unit = options_.height_unit;
    if (const XrStereoSession* xr = headset_.session())
        v.xr_state = xr->focused() ? (xr->noControllers() ? "focused, no controllers: no pointer" : "focused")
                                   : (xr->running() ? "running" : "waiting");
    v.frame_ms = frame_ms_;
    v.points_uploaded = stream_.renderer().uploadedPoints();
    v.points_arrived = stream_.source().pointsArrived();
    v.points_drawn = points_drawn_per_eye_;
    v.cells = stream_.renderer().cellCount();
    v.point_budget = stream_.pointBudget();
    v.arena = stream_.renderer().arena();
    v.source = stream_.source().stats();
    v.loading = !stream_.source().finished();
    v.scale = zoom_.scale();
    tools_.describe(v);
    v.headset_panel = headset_.session() ? &headset_panel_ : nullptr;
    PanelFrame p;
    p.origin = stream_.source().origin();
    p.has_height = stream_.source().fields().height_above_ground || stream_.renderer().hasTerrain();
    v.colour_note = colourNote(style_.colour, stream_.renderer().colourSources(), terrain_ != nullptr, terrain_failed_);
    trials_.describe(p);
    p.ready_to_start = readyToStart();
    p.hit = tools_.get<PointerTool>().hit();
    // A survey's points without heights above ground carry their class in the packed word.
    if (p.hit && stream_.source().fromElsewhere() && !stream_.source().fields().height_above_ground)
        p.hit->asprs_class = classOfPacked(p.hit->height_above_ground_m);
    if (p.hit)  // the height above a bound terrain, where there is one
        if (const std::optional<double> h = stream_.renderer().heightAboveTerrain(p.hit->local))
            p.hit->height_above_ground_m = float(*h);
    p.headset = headset_.session() != nullptr;
    questions_.describe(p);
    const RigPose eye = headLocal();
    p.head_local = eye.position;
    p.view_projection = render::projectionMatrix(options_.modes.orbit.vfov_deg, double(fb_w) / std::max(fb_h, 1),
                                                 options_.modes.orbit.near_m, options_.modes.orbit.far_m) *
                        scaledView(eye, zoom_.scale());
    EyeTarget* headset_target =
        headset_.session() && (headset_panel_ || questions_.active()) ? &eyes_->panelTarget() : nullptr;
    reset_zoom_button_ = drawFramePanels(v, p, fb_w, fb_h, headset_target);
}

int ViewerApp::finish(int status) {
    if (!options_.screenshot.empty() && !screenshot_done_ && !stream_.failed()) {
        std::fprintf(stderr, "ladarvr: view: --screenshot: no frame was rendered\n");
        status = 1;
    }
    glFinish();
    const PointRenderer& points = stream_.renderer();
    RunSummary s{exit_reason_,
                 headset_.fallbackReason(),
                 frames_,
                 frames_submitted_,
                 first_points_frame_,
                 stream_.source().pointsArrived(),
                 points.uploadedPoints(),
                 stream_.pointBudget(),
                 points.cellCount(),
                 options_.cull,
                 headset_.session() != nullptr,
                 headset_panel_ && eyes_->panelTarget().colour != 0,
                 modes_.mode(),
                 modes_.centre(),
                 stream_.source().origin(),
                 trials_.decisions(),
                 zoom_.scale(),
                 std::nullopt,
                 nlohmann::json::object()};
    tools_.logRun(s.tools);
    if (trials_.designated()) s.designated_world = *trials_.designated() + stream_.source().origin();
    recordSummary(log_, s);
    if (const std::optional<std::size_t> hwm = peakResidentBytes()) log_.set("vm_hwm_bytes", *hwm);
    if (!options_.log_json.empty() && !log_.write(options_.log_json)) status = 1;
    if (!options_.quiet && !stream_.failed())
        std::fprintf(stderr, "ladarvr: view: %ld frames (%ld submitted to OpenXR), %zu points, exit: %s\n", frames_,
                     frames_submitted_, points.uploadedPoints(), exit_reason_.c_str());
    if (const int sig = StopSignal::received(); sig != 0 && status == 0) status = 128 + sig;
    trials_.finish();
    return status;
}

int runViewer(const ViewerOptions& options, CloudFeed& feed) {
    validate(options);
    ViewerApp app(options, !options.log_json.empty(), nullptr, nullptr);
    return app.run(&feed);
}

int runViewer(const ViewerOptions& options, CloudFeed& feed, std::string& log_json) {
    validate(options);
    ViewerApp app(options, true, nullptr, nullptr);
    const int status = app.run(&feed);
    log_json = app.logJson();
    return status;
}

int runViewer(const ViewerOptions& options, PointSource& source) {
    validate(options);
    ViewerApp app(options, !options.log_json.empty(), nullptr, nullptr);
    return app.run(nullptr, &source);
}

int runTrials(const ViewerOptions& options, TrialSource& source, TrialObserver& observer) {
    validate(options);
    if (source.count() <= 0 && source.questions(0).empty()) throw core::Error("study: the plan has no trials");
    ViewerApp app(options, !options.log_json.empty(), &source, &observer);
    return app.run(nullptr);
}

}  // namespace viewer
