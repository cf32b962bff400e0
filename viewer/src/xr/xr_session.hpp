// viewer/src/xr/xr_session.hpp: the OpenXR side of the viewer (paper §IV-A's HMD, on any
// OpenXR runtime): instance, system, session bound to the GLFW window's GLX context
// (XR_KHR_opengl_enable, Xlib binding), one colour swapchain per eye, a depth swapchain
// per eye where the runtime offers XR_KHR_composition_layer_depth (the compositor then
// reprojects with the points' depth), the action set of xr_actions.cpp (mode, decisions,
// pointer, grab, motion), and the whole session lifecycle.
//
// Setup (create) throws core::Error or returns null with a reason; everything called
// per frame never throws: it returns a status and the caller degrades to the desktop.
#pragma once
#include "run_log.hpp"
#include "xr/xr_input.hpp"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

struct GLFWwindow;

namespace viewer {

/// One eye as the runtime located it, in the session's reference space (metres; OpenXR
/// convention: x right, y up, -z forward). Angles are the asymmetric FoV in radians.
struct XrEye {
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 position{0.0};
    float angle_left = -0.8f, angle_right = 0.8f, angle_up = 0.8f, angle_down = -0.8f;
};

/// What the session tells the loop each frame.
struct XrFrame {
    bool should_render = false;          // the runtime wants pixels this frame
    std::int64_t display_time_ns = 0;    // xrWaitFrame's predicted display time: eyes, hands and xrEndFrame
    std::int64_t display_period_ns = 0;  // xrWaitFrame's predicted display period (the frame budget)
    std::int64_t input_time_ns = 0;      // the controllers' locate time this frame, 0 when not read
    bool views_valid = false;
    std::array<XrEye, 2> eyes;
};

/// The depth range of the projection the eyes were drawn with (mode_controller.hpp's
/// projectionFromFov: OpenGL, not reversed, finite far), in the tracking frame's metres:
/// window depth 0 is near_m, 1 is far_m.
struct XrDepthRange {
    float near_m = 0.1f;
    float far_m = 20000.0f;
};

enum class XrPoll {
    Ok,    // keep going (the session may or may not be running)
    Exit,  // the session ended at our request (or the runtime's): leave the app
    Lost,  // runtime or session lost: fall back to the desktop mode
};

class XrStereoSession {
  public:
    /// Tries to start OpenXR on `window`'s current GLX context. Returns null with `reason`
    /// set when there is no runtime, no HMD, or no OpenGL support; throws core::Error
    /// only for programming errors. Records runtime/system/format in `log`.
    static std::unique_ptr<XrStereoSession> create(GLFWwindow* window, RunLog& log, std::string& reason);
    ~XrStereoSession();
    XrStereoSession(const XrStereoSession&) = delete;
    XrStereoSession& operator=(const XrStereoSession&) = delete;

    /// Drains the event queue and runs the state machine (begin/end session).
    XrPoll pollEvents();
    /// True between xrBeginSession and xrEndSession.
    bool running() const;
    /// True once FOCUSED (input is live).
    bool focused() const;
    /// xrWaitFrame + xrBeginFrame + xrLocateViews at the frame's predicted display time.
    /// False on a runtime error (caller: Lost).
    bool beginFrame(XrFrame& frame);
    /// Acquires and waits the eye's swapchain image; returns its GL texture name (0 on error).
    unsigned acquireEye(int eye);
    bool releaseEye(int eye);
    /// True when depth swapchains exist (the runtime offers XR_KHR_composition_layer_depth
    /// and a GL_DEPTH_COMPONENT32F swapchain format); the run log says why not otherwise.
    bool depthAvailable() const;
    /// The eye's depth swapchain image (GL_DEPTH_COMPONENT32F texture), 0 on error or
    /// without depthAvailable().
    unsigned acquireEyeDepth(int eye);
    bool releaseEyeDepth(int eye);
    /// xrEndFrame at the frame's predicted display time with a projection layer of both
    /// eyes when `rendered`, else no layers; with `depth`, each view chains its depth image
    /// (XrCompositionLayerDepthInfoKHR, window depth 0..1 mapped to depth's near and far).
    bool endFrame(const XrFrame& frame, bool rendered, const std::optional<XrDepthRange>& depth = std::nullopt);
    /// xrSyncActions and reads the actions (aim poses at the display time of the frame
    /// begun last, the one the eyes are drawn for); zeroed unless focused.
    XrInput syncInput();
    /// The predicted display period of the frame begun last (the frame budget), 0 before one.
    double predictedDisplayPeriod_s() const;
    /// The time syncInput located the controllers at since the last beginFrame, 0 if none.
    std::int64_t inputTime_ns() const;
    /// The runtime has bound no controller after kControllerWaitFrames focused frames
    /// (said once on stderr and in the run log): the pointer needs the desktop then.
    bool noControllers() const;
    /// Focused frames a runtime has to bind a controller before noControllers().
    static constexpr int kControllerWaitFrames = 10;
    /// Asks the runtime to end the session (Escape / window closed): EXITING follows.
    void requestExit();

    int eyeWidth() const;
    int eyeHeight() const;

    struct Impl;

  private:
    explicit XrStereoSession(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// Session state name as in the spec without the prefix ("FOCUSED").
const char* sessionStateName(int state);

}  // namespace viewer
