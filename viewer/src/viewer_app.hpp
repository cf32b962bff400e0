// viewer/src/viewer_app.hpp: the frame loop's state (viewer.cpp): the window, the input
// sources, the tools (one ToolSet), the trial controller and its questionnaires, the point
// source's stream, the eye renderer and the headset, each its own component; ViewerApp
// only runs them in order.
#pragma once
#include <viewer/cloud_feed_source.hpp>
#include <viewer/viewer.hpp>
#include <viewer/world_zoom.hpp>

#include "frame_facts.hpp"
#include "input/desktop_input.hpp"
#include "input/replay_player.hpp"
#include "input/script_player.hpp"
#include "input/xr_input_mapping.hpp"
#include "points/point_renderer.hpp"
#include "points/source_stream.hpp"
#include "run_log.hpp"
#include "stop_signal.hpp"
#include "tools/tool_set.hpp"
#include "trial/questionnaire_flow.hpp"
#include "trial/trial_controller.hpp"
#include "ui/desktop_window.hpp"
#include "ui/eye_frame_renderer.hpp"
#include "ui/panel.hpp"
#include "xr/headset.hpp"
#include "xr/xr_session.hpp"

#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace viewer {

class ViewerApp {
  public:
    using Clock = std::chrono::steady_clock;
    /// `record_frames`: keep per-frame records in the log (for --log-json and benchmarks;
    /// an interactive session would otherwise grow it for nothing).
    ViewerApp(const ViewerOptions& options, bool record_frames, TrialSource* trials, TrialObserver* observer);
    /// A plain run over `feed` or `points` (no trial source), or the trials of the source.
    int run(CloudFeed* feed, PointSource* points = nullptr);
    std::string logJson() const { return log_.json().dump(); }

  private:
    // Stages of a frame.
    OperatorInput gatherInput();
    void checkQuit(const OperatorInput& in);
    bool pollXr();
    void updateSource();
    /// Takes the terrain terrain_ hands over (or its failure), once.
    void takeTerrain();
    /// Above-ground colours are asked for and their terrain is coming but not yet bound.
    bool awaitingTerrain() const;
    /// The --frames count is reached, and above-ground colours wait for no terrain (a run
    /// that asks for them shows them in its last frame and screenshot; --timeout bounds it).
    bool framesDone() const;
    void update(OperatorInput in, double dt);
    void render(int fb_w, int fb_h);
    void present(int fb_w, int fb_h);
    // Helpers.
    void startQuit(const std::string& reason);
    void toggleMode(const std::string& source);
    void beginTrial(int index);
    void updateTools(OperatorInput& in, double dt);
    void recordToolActions();
    bool readyToStart() const;
    RigPose headTracking() const;
    RigPose headLocal() const { return compose(modes_.rig(), zoom_.apply(headTracking())); }
    std::optional<LocalRay> pointerRay(const OperatorInput& in) const;
    LodFocus operatorFocus(const CutVolume& cut) const;
    TrialContext trialContext();
    void frameCounted(const FrameResult& result, bool xr);
    void drawPanel(int fb_w, int fb_h);
    int finish(int status);

    StopSignal stop_signal_;  // before the window: a signal from now on ends the loop cleanly
    const ViewerOptions& options_;
    bool record_frames_ = true;
    RunLog log_;
    DesktopInput input_;
    DesktopWindow window_;
    ScriptPlayer script_;
    ReplayPlayer replay_;
    XrInputMapping xr_input_;
    TrialController trials_;
    QuestionnaireFlow questions_;
    long pickable_since_frame_ = -1;  // when the pointer could first pick (a script's pickable+N)
    CloudFeed empty_feed_;            // a run of questions only shows no cloud
    ViewStyle style_;
    ModeController modes_;
    WorldZoom zoom_;
    ToolSet tools_;
    std::vector<ToolAction> tool_actions_;  // this frame's, until recorded
    OverlayList overlay_list_;
    std::unique_ptr<CloudFeedSource> plain_source_;
    SourceStream stream_;
    std::unique_ptr<EyeFrameRenderer> eyes_;
    Headset headset_;
    Clock::time_point start_ = Clock::now(), last_ = start_, quit_deadline_{};
    long frames_ = 0;                   // counted frames (XR: submitted with both eyes)
    double source_ms_ = 0.0;            // this frame's updateSource (the adaptive budget's CPU share)
    std::int64_t last_display_ns_ = 0;  // the last XR frame's predicted display time
    double display_period_ms_ = 0.0;    // the least step between them so far (0: none yet)
    long frames_submitted_ = 0;
    long first_points_frame_ = -1;
    std::size_t points_drawn_ = 0;          // the last frame's, summed over the eyes
    std::size_t points_drawn_per_eye_ = 0;  // the most one eye of it drew (the panel's figure)
    std::string exit_reason_ = "window closed";
    bool quitting_ = false;    // frames after the exit request are not counted
    bool start_free_ = false;  // the trial begun starts in free mode (its condition's)
    bool screenshot_done_ = false, reset_zoom_button_ = false, headset_panel_ = true;
    std::shared_ptr<TerrainFeed> terrain_;  // the shown cloud's: the trial's, else ViewerOptions::terrain
    bool terrain_failed_ = false;           // the terrain feed said none will come
    int status_ = 0;
    double frame_ms_ = 0.0;                // wall time since the previous loop iteration
    std::optional<glm::dvec3> aim_world_;  // a script's aim: the pointer follows the head to it
    std::optional<TraceSample> replay_sample_;
};

}  // namespace viewer
