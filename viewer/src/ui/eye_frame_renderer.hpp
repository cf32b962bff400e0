// viewer/src/ui/eye_frame_renderer.hpp: drawing one frame's eye images: the headset's two eyes into
// the OpenXR swapchains (mirrored into the window) or the desktop view, each with the
// points, the tools' overlay, the comfort vignette and the headset's panel quad. It reads
// what the frame loop decided (FrameView) and decides nothing itself.
#pragma once
#include "ui/overlay_renderer.hpp"
#include "points/point_renderer.hpp"
#include "xr/xr_session.hpp"

#include <viewer/mode_controller.hpp>
#include <viewer/trial.hpp>
#include <viewer/viewer.hpp>
#include <viewer/world_zoom.hpp>

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>

namespace viewer {

/// The pose of `b` seen through `a` (b in a's frame, then a's).
RigPose compose(const RigPose& a, const RigPose& b);
/// World-to-eye view of an eye at `eye` (local frame) with the zoom's scale applied after
/// the rigid part, in double.
glm::dmat4 scaledView(const RigPose& eye, double scale);

/// What a frame shows.
struct FrameView {
    RigPose rig;  // the mode's rig
    const WorldZoom* zoom = nullptr;
    RigPose head_tracking;  // desktop: the mouse-look camera
    const ViewStyle* style = nullptr;
    ViewMode mode = ViewMode::Automatic;  // on the plate (a replay's recorded mode)
    CutVolume cut;
    const OverlayList* overlay = nullptr;
    bool blank = false;                   // a ready screen: nothing of the cloud
    bool headset = false;                 // an OpenXR session exists (the vignette is drawn)
    const TraceSample* replay = nullptr;  // desktop: the recorded head and scale instead
    glm::dvec3 origin{0.0};               // world coordinates of the local frame (replay)
};

/// What a frame drew, for the run log.
struct FrameResult {
    bool rendered = false;  // both eyes (XR) or the desktop view were drawn
    std::array<RigPose, 2> eyes_tracking, eyes_local;
    XrFrame xr_frame;                         // XR frames only
    std::optional<XrDepthRange> depth_range;  // XR frames whose depth went to the compositor
    double cpu_ms = 0.0;
    std::size_t points_drawn = 0;          // the sum over the eyes (the run log's "points_drawn")
    std::size_t points_drawn_per_eye = 0;  // the most one eye drew (the desktop: its one view)
};

class EyeFrameRenderer {
  public:
    /// Needs the window's GL context current; throws core::Error (setup path).
    explicit EyeFrameRenderer(const ViewerOptions& options);
    ~EyeFrameRenderer();
    EyeFrameRenderer(const EyeFrameRenderer&) = delete;
    EyeFrameRenderer& operator=(const EyeFrameRenderer&) = delete;

    /// Begins an OpenXR frame (xrWaitFrame, xrBeginFrame, the eyes located at its
    /// predicted display time) before the frame's input is read, so that the controllers
    /// are located at that same time; lastHead() follows. A failure shows in renderXr.
    /// Never throws.
    void beginXr(XrStereoSession& xr);
    /// One OpenXR frame (begun here unless beginXr came first; both eyes, their depth where
    /// the session submits it, mirror blits, end). False on a runtime failure (the caller
    /// drops to the desktop). Never throws.
    bool renderXr(XrStereoSession& xr, PointRenderer& points, const FrameView& view, int fb_w, int fb_h,
                  FrameResult& out);
    /// The desktop view into the window's back buffer. Never throws.
    void renderDesktop(PointRenderer& points, const FrameView& view, int fb_w, int fb_h, FrameResult& out);
    /// The head between the eyes of the last XR frame (tracking frame).
    const RigPose& lastHead() const { return last_head_; }
    /// GPU milliseconds of the last frame (--gpu-timing), < 0 without.
    double lastGpuMs() const { return last_gpu_ms_; }
    /// The ImGui windows rendered for the headset's quad (shown from the next frame).
    EyeTarget& panelTarget() { return panel_target_; }
    bool show_panel = true;  // the headset panel is drawn on its quad

  private:
    void drawEye(const EyeTarget& target, PointRenderer& points, const FrameView& view, const EyeDraw& draw, GLuint fbo,
                 int x, int y, int w, int h, FrameResult& out);
    void drawPanelQuad(const RigPose& eye_tracking, const glm::dmat4& projection, GLuint fbo, int w, int h);
    void mirror(int eye, int w, int h, int fb_w, int fb_h);
    void endGpuTimer();

    const ViewerOptions& options_;
    OverlayRenderer overlay_;
    std::array<EyeTarget, 2> eye_targets_;
    EyeTarget desktop_target_, panel_target_;
    std::array<GLuint, 2> swapchain_fbo_{};
    GLuint timer_query_ = 0;  // GL_TIME_ELAPSED around the frame's draws (--gpu-timing)
    double last_gpu_ms_ = -1.0;
    RigPose last_head_;
    XrFrame begun_;              // the frame beginXr began
    bool begun_valid_ = false;   // beginXr ran since the last renderXr
    bool begun_failed_ = false;  // ... and the runtime failed
};

/// Reads the window's back buffer into a PNG at `path`. False (one line on stderr) on failure.
bool writeScreenshot(const std::filesystem::path& path, int fb_w, int fb_h);

}  // namespace viewer
