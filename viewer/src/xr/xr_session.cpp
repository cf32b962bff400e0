// viewer/src/xr/xr_session.cpp: OpenXR instance, GLX-bound session, swapchains, actions and the
// session state machine (paper §IV-A: the HMD side of the immersive setup).
//
// This file sees X11/GLX headers (for XrGraphicsBindingOpenGLXlibKHR) and therefore never
// includes glad; it makes no GL calls. The renderer attaches the swapchain textures.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <GL/glx.h>
#include <X11/Xlib.h>

// GLFW's native-access functions (glfw3native.h), declared here because that header pulls
// in X11/extensions/Xrandr.h, which the build does not otherwise need.
extern "C" {
Display* glfwGetX11Display(void);
GLXContext glfwGetGLXContext(GLFWwindow* window);
GLXWindow glfwGetGLXWindow(GLFWwindow* window);
}
#undef None  // X11 macros that collide with C++ code below
#undef Status
#undef Bool
#undef Always

#define XR_USE_PLATFORM_XLIB
#define XR_USE_GRAPHICS_API_OPENGL
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

// OpenXR's idiom `XrFoo foo{XR_TYPE_FOO};` value-initialises the other members on purpose.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

#include "xr/xr_actions.hpp"
#include "xr/xr_check.hpp"
#include "xr/xr_session.hpp"

#include <core/error.hpp>
#include <platform/safe_file.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <vector>

namespace viewer {

const char* sessionStateName(int state) {
    switch (static_cast<XrSessionState>(state)) {
        case XR_SESSION_STATE_IDLE: return "IDLE";
        case XR_SESSION_STATE_READY: return "READY";
        case XR_SESSION_STATE_SYNCHRONIZED: return "SYNCHRONIZED";
        case XR_SESSION_STATE_VISIBLE: return "VISIBLE";
        case XR_SESSION_STATE_FOCUSED: return "FOCUSED";
        case XR_SESSION_STATE_STOPPING: return "STOPPING";
        case XR_SESSION_STATE_LOSS_PENDING: return "LOSS_PENDING";
        case XR_SESSION_STATE_EXITING: return "EXITING";
        default: return "UNKNOWN";
    }
}

// --- implementation ----------------------------------------------------------------------
namespace {
constexpr std::int64_t kGlRgba8 = 0x8058, kGlRgba16 = 0x805B, kGlRgba16f = 0x881A, kGlSrgb8Alpha8 = 0x8C43,
                       kGlRgb10A2 = 0x8059;
// The eye targets' depth format: the depth swapchain must match it for a plain image copy.
constexpr std::int64_t kGlDepth32f = 0x8CAC;

struct EyeSwapchain {
    XrSwapchain handle = XR_NULL_HANDLE;
    std::vector<XrSwapchainImageOpenGLKHR> images;
    bool acquired = false;
};
}  // namespace

struct XrStereoSession::Impl {
    XrInstance instance = XR_NULL_HANDLE;
    XrSystemId system = XR_NULL_SYSTEM_ID;
    ::XrSession session = XR_NULL_HANDLE;
    XrSpace space = XR_NULL_HANDLE;  // LOCAL reference space: the rig's frame
    XrSessionState state = XR_SESSION_STATE_UNKNOWN;
    bool running = false;
    bool exit_requested = false;
    std::array<EyeSwapchain, 2> eyes;
    bool depth_extension = false;        // XR_KHR_composition_layer_depth enabled
    std::array<EyeSwapchain, 2> depths;  // handles only when depth is submitted
    long depth_frames = 0;               // frames ended with depth
    XrDuration period_last = 0, period_min = 0, period_max = 0;
    long period_frames = 0;
    int width = 0, height = 0;
    std::int64_t format = 0;
    std::array<XrView, 2> views{};
    XrActions actions;
    XrTime last_display_time = 0;
    XrTime input_time = 0;  // what syncInput located at since the last beginFrame
    RunLog* log = nullptr;
    int focused_syncs = 0;         // frames whose input was read while focused
    bool controller_seen = false;  // a hand was bound to an interaction profile
    bool no_controllers = false;   // none after kControllerWaitFrames focused frames (said once)

    ~Impl() {
        for (auto& e : eyes)
            if (e.handle != XR_NULL_HANDLE) xrDestroySwapchain(e.handle);
        for (auto& e : depths)
            if (e.handle != XR_NULL_HANDLE) xrDestroySwapchain(e.handle);
        if (space != XR_NULL_HANDLE) xrDestroySpace(space);
        actions.destroy();
        if (session != XR_NULL_HANDLE) xrDestroySession(session);
        if (instance != XR_NULL_HANDLE) xrDestroyInstance(instance);
    }
};

XrStereoSession::XrStereoSession(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

namespace {
/// Whether the runtime has bound a controller: the run log's `xr_controllers` says so
/// once it is known; a runtime that binds none within kControllerWaitFrames focused
/// frames (Monado's simulated HMD alone) gets one warning line and an event, and a
/// controller bound later still counts.
void noteControllers(XrStereoSession::Impl& s, int hands_bound) {
    ++s.focused_syncs;
    if (hands_bound > 0 && !s.controller_seen) {
        s.controller_seen = true;
        s.no_controllers = false;
        s.log->set("xr_controllers", true);
        if (s.focused_syncs > XrStereoSession::kControllerWaitFrames) s.log->event("xr: a controller was bound");
    } else if (!s.controller_seen && !s.no_controllers && s.focused_syncs == XrStereoSession::kControllerWaitFrames) {
        s.no_controllers = true;
        s.log->set("xr_controllers", false);
        s.log->event("xr: the runtime reports no controllers");
        platform::printMessage("warning",
                               "view: the OpenXR runtime reports no controllers: the pointer cannot be used in "
                               "the headset (no designation, no box to point at; the desktop's keys still work); "
                               "Monado emulates both controllers with QWERTY_ENABLE=1 (docs/headset.md)");
    }
}
}  // namespace
XrStereoSession::~XrStereoSession() = default;

// The steps of create(), in order; each returns false with `reason` set when the runtime
// cannot give what the viewer needs (desktop mode), and throws core::Error on a failed
// call that should not fail.
namespace {

bool createInstance(XrStereoSession::Impl& s, std::string& reason) {
    // Instance: the loader finds the active runtime; none means desktop mode.
    std::uint32_t ext_count = 0;
    XrResult r = xrEnumerateInstanceExtensionProperties(nullptr, 0, &ext_count, nullptr);
    if (XR_FAILED(r)) {
        reason = "no OpenXR runtime (" + xrResultName(XR_NULL_HANDLE, r) + ")";
        return false;
    }
    std::vector<XrExtensionProperties> exts(ext_count, {XR_TYPE_EXTENSION_PROPERTIES});
    xrEnumerateInstanceExtensionProperties(nullptr, ext_count, &ext_count, exts.data());
    auto offered = [&](const char* name) {
        return std::any_of(exts.begin(), exts.end(),
                           [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
    };
    if (!offered(XR_KHR_OPENGL_ENABLE_EXTENSION_NAME)) {
        reason = "the OpenXR runtime does not offer " XR_KHR_OPENGL_ENABLE_EXTENSION_NAME;
        return false;
    }
    std::vector<const char*> enabled = {XR_KHR_OPENGL_ENABLE_EXTENSION_NAME};
    // Depth lets the compositor reproject with the scene's depth; optional.
    s.depth_extension = offered(XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    if (s.depth_extension) enabled.push_back(XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    XrInstanceCreateInfo create_info{XR_TYPE_INSTANCE_CREATE_INFO};
    std::strcpy(create_info.applicationInfo.applicationName, "ladarvr");
    create_info.applicationInfo.applicationVersion = 1;
    std::strcpy(create_info.applicationInfo.engineName, "ladarvr");
    create_info.applicationInfo.apiVersion = XR_API_VERSION_1_0;
    create_info.enabledExtensionCount = static_cast<std::uint32_t>(enabled.size());
    create_info.enabledExtensionNames = enabled.data();
    r = xrCreateInstance(&create_info, &s.instance);
    if (XR_FAILED(r)) {
        reason = "no OpenXR runtime (xrCreateInstance: " + xrResultName(XR_NULL_HANDLE, r) + ")";
        return false;
    }
    const XrInstance instance = s.instance;
    XrInstanceProperties instance_props{XR_TYPE_INSTANCE_PROPERTIES};
    XR_CHECK(instance, xrGetInstanceProperties(instance, &instance_props));
    s.log->set("xr_runtime", std::string(instance_props.runtimeName));

    XrSystemGetInfo system_info{XR_TYPE_SYSTEM_GET_INFO};
    system_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    r = xrGetSystem(instance, &system_info, &s.system);
    if (XR_FAILED(r)) {
        reason = std::string("OpenXR runtime '") + instance_props.runtimeName + "' has no head-mounted display (" +
                 xrResultName(instance, r) + ")";
        return false;
    }
    XrSystemProperties system_props{XR_TYPE_SYSTEM_PROPERTIES};
    XR_CHECK(instance, xrGetSystemProperties(instance, s.system, &system_props));
    s.log->set("xr_system", std::string(system_props.systemName));

    return true;
}

bool createGlSession(XrStereoSession::Impl& s, GLFWwindow* window, std::string& reason) {
    const XrInstance instance = s.instance;
    XrResult r = XR_SUCCESS;
    // OpenGL requirements must be queried before xrCreateSession.
    PFN_xrGetOpenGLGraphicsRequirementsKHR get_requirements = nullptr;
    XR_CHECK(instance, xrGetInstanceProcAddr(instance, "xrGetOpenGLGraphicsRequirementsKHR",
                                             reinterpret_cast<PFN_xrVoidFunction*>(&get_requirements)));
    XrGraphicsRequirementsOpenGLKHR requirements{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
    XR_CHECK(instance, get_requirements(instance, s.system, &requirements));
    if (XR_MAKE_VERSION(4, 5, 0) < requirements.minApiVersionSupported) {
        reason = "the OpenXR runtime needs a newer OpenGL than 4.5";
        return false;
    }

    // The Xlib/GLX binding comes from the GLFW window and its (current) context.
    Display* display = glfwGetX11Display();
    GLXContext context = glfwGetGLXContext(window);
    GLXWindow drawable = glfwGetGLXWindow(window);
    if (!display || !context) {
        reason = "the desktop window has no GLX context (not running on X11?)";
        return false;
    }
    int fbconfig_id = 0;
    glXQueryContext(display, context, GLX_FBCONFIG_ID, &fbconfig_id);
    const int attribs[] = {GLX_FBCONFIG_ID, fbconfig_id, 0};
    int config_count = 0;
    GLXFBConfig* configs = glXChooseFBConfig(display, DefaultScreen(display), attribs, &config_count);
    XrGraphicsBindingOpenGLXlibKHR binding{XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR};
    binding.xDisplay = display;
    binding.glxContext = context;
    binding.glxDrawable = drawable;
    if (configs && config_count > 0) {
        binding.glxFBConfig = configs[0];
        if (XVisualInfo* visual = glXGetVisualFromFBConfig(display, configs[0])) {
            binding.visualid = static_cast<std::uint32_t>(visual->visualid);
            XFree(visual);
        }
    }
    XrSessionCreateInfo session_info{XR_TYPE_SESSION_CREATE_INFO};
    session_info.next = &binding;
    session_info.systemId = s.system;
    r = xrCreateSession(instance, &session_info, &s.session);
    if (configs) XFree(configs);
    if (XR_FAILED(r)) {
        reason = "OpenXR session creation failed (" + xrResultName(instance, r) + ")";
        return false;
    }

    XrReferenceSpaceCreateInfo space_info{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    space_info.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    space_info.poseInReferenceSpace.orientation.w = 1.0f;
    XR_CHECK(instance, xrCreateReferenceSpace(s.session, &space_info, &s.space));

    return true;
}

bool createSwapchains(XrStereoSession::Impl& s, std::string& reason) {
    const XrInstance instance = s.instance;
    // Views and swapchains: one per eye at the recommended size.
    std::uint32_t view_count = 0;
    XR_CHECK(instance, xrEnumerateViewConfigurationViews(instance, s.system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                                                         0, &view_count, nullptr));
    std::vector<XrViewConfigurationView> config_views(view_count, {XR_TYPE_VIEW_CONFIGURATION_VIEW});
    XR_CHECK(instance, xrEnumerateViewConfigurationViews(instance, s.system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                                                         view_count, &view_count, config_views.data()));
    if (view_count != 2) {
        reason = "the HMD's primary stereo configuration has " + std::to_string(view_count) + " views";
        return false;
    }
    s.width = static_cast<int>(config_views[0].recommendedImageRectWidth);
    s.height = static_cast<int>(config_views[0].recommendedImageRectHeight);

    std::uint32_t format_count = 0;
    XR_CHECK(instance, xrEnumerateSwapchainFormats(s.session, 0, &format_count, nullptr));
    std::vector<std::int64_t> formats(format_count);
    XR_CHECK(instance, xrEnumerateSwapchainFormats(s.session, format_count, &format_count, formats.data()));
    nlohmann::json offered = nlohmann::json::array();
    for (auto f : formats) offered.push_back(f);
    s.log->set("xr_formats_offered", offered);
    // Linear 8/16-bit formats first: the eye images are blitted in and mirrored out as is.
    for (std::int64_t want : {kGlRgba8, kGlRgba16, kGlRgb10A2, kGlRgba16f, kGlSrgb8Alpha8}) {
        if (std::find(formats.begin(), formats.end(), want) != formats.end()) {
            s.format = want;
            break;
        }
    }
    if (s.format == 0) {
        if (formats.empty()) {
            reason = "the OpenXR runtime offers no OpenGL swapchain format";
            return false;
        }
        s.format = formats.front();
    }
    s.log->set("xr_swapchain_format", s.format);
    s.log->set("xr_eye_size", nlohmann::json::array({s.width, s.height}));

    auto create = [&](EyeSwapchain& eye, std::int64_t format, XrSwapchainUsageFlags usage) {
        XrSwapchainCreateInfo sc{XR_TYPE_SWAPCHAIN_CREATE_INFO};
        sc.usageFlags = usage;
        sc.format = format;
        sc.sampleCount = 1;
        sc.width = static_cast<std::uint32_t>(s.width);
        sc.height = static_cast<std::uint32_t>(s.height);
        sc.faceCount = 1;
        sc.arraySize = 1;
        sc.mipCount = 1;
        XR_CHECK(instance, xrCreateSwapchain(s.session, &sc, &eye.handle));
        std::uint32_t image_count = 0;
        XR_CHECK(instance, xrEnumerateSwapchainImages(eye.handle, 0, &image_count, nullptr));
        eye.images.assign(image_count, {XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR});
        XR_CHECK(instance,
                 xrEnumerateSwapchainImages(eye.handle, image_count, &image_count,
                                            reinterpret_cast<XrSwapchainImageBaseHeader*>(eye.images.data())));
    };
    for (auto& eye : s.eyes)
        create(eye, s.format,
               XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT |
                   XR_SWAPCHAIN_USAGE_TRANSFER_SRC_BIT);

    // Depth: the eye targets' GL_DEPTH_COMPONENT32F copied as is into a swapchain image of
    // the same format (an image copy needs identical depth formats).
    nlohmann::json depth = {{"extension", s.depth_extension}};
    if (!s.depth_extension) {
        depth["reason"] = "the OpenXR runtime does not offer " XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME;
    } else if (std::find(formats.begin(), formats.end(), kGlDepth32f) == formats.end()) {
        depth["reason"] = "the OpenXR runtime offers no GL_DEPTH_COMPONENT32F swapchain format";
    } else {
        for (auto& eye : s.depths)
            create(eye, kGlDepth32f,
                   XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT);
        depth["format"] = kGlDepth32f;
    }
    depth["submitted"] = s.depths[0].handle != XR_NULL_HANDLE;
    s.log->set("xr_depth", depth);
    return true;
}

}  // namespace

std::unique_ptr<XrStereoSession> XrStereoSession::create(GLFWwindow* window, RunLog& log, std::string& reason) {
    auto impl = std::make_unique<Impl>();
    impl->log = &log;
    if (!createInstance(*impl, reason) || !createGlSession(*impl, window, reason) || !createSwapchains(*impl, reason))
        return nullptr;
    impl->actions.create(impl->instance, impl->session);
    for (auto& v : impl->views) v = {XR_TYPE_VIEW};
    return std::unique_ptr<XrStereoSession>(new XrStereoSession(std::move(impl)));
}

XrPoll XrStereoSession::pollEvents() {
    Impl& s = *impl_;
    for (int guard = 0; guard < 64; ++guard) {
        XrEventDataBuffer event{XR_TYPE_EVENT_DATA_BUFFER};
        const XrResult r = xrPollEvent(s.instance, &event);
        if (r == XR_EVENT_UNAVAILABLE) break;
        if (!XR_LOG(s.instance, r)) return XrPoll::Lost;
        switch (event.type) {
            case XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING:
                s.log->event("xr: instance loss pending");
                return XrPoll::Lost;
            case XR_TYPE_EVENT_DATA_EVENTS_LOST: s.log->event("xr: events lost"); break;
            case XR_TYPE_EVENT_DATA_REFERENCE_SPACE_CHANGE_PENDING:
                s.log->event("xr: reference space change pending");
                break;
            case XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED: s.log->event("xr: interaction profile changed"); break;
            case XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED: {
                const auto& changed = *reinterpret_cast<const XrEventDataSessionStateChanged*>(&event);
                s.state = changed.state;
                s.log->state(sessionStateName(changed.state));
                switch (changed.state) {
                    case XR_SESSION_STATE_READY: {
                        XrSessionBeginInfo begin{XR_TYPE_SESSION_BEGIN_INFO};
                        begin.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
                        if (!XR_LOG(s.instance, xrBeginSession(s.session, &begin))) return XrPoll::Lost;
                        s.running = true;
                        break;
                    }
                    case XR_SESSION_STATE_STOPPING:
                        s.running = false;
                        if (!XR_LOG(s.instance, xrEndSession(s.session))) return XrPoll::Lost;
                        break;
                    case XR_SESSION_STATE_LOSS_PENDING: s.running = false; return XrPoll::Lost;
                    case XR_SESSION_STATE_EXITING:
                        s.running = false;
                        // Our own request (Escape, window closed) ends the app; the runtime
                        // ending the session on its own leaves the desktop mirror running.
                        return s.exit_requested ? XrPoll::Exit : XrPoll::Lost;
                    case XR_SESSION_STATE_IDLE:
                    case XR_SESSION_STATE_SYNCHRONIZED:
                    case XR_SESSION_STATE_VISIBLE:
                    case XR_SESSION_STATE_FOCUSED:
                    default: break;
                }
                break;
            }
            default: break;
        }
    }
    return XrPoll::Ok;
}

bool XrStereoSession::running() const { return impl_->running; }
bool XrStereoSession::focused() const { return impl_->state == XR_SESSION_STATE_FOCUSED; }
int XrStereoSession::eyeWidth() const { return impl_->width; }
int XrStereoSession::eyeHeight() const { return impl_->height; }

namespace {
/// The predicted display periods so far, as the run log's summary (milliseconds).
void recordPeriod(XrStereoSession::Impl& s, XrDuration period_ns) {
    s.period_last = period_ns;
    s.period_min = s.period_frames == 0 ? period_ns : std::min(s.period_min, period_ns);
    s.period_max = s.period_frames == 0 ? period_ns : std::max(s.period_max, period_ns);
    ++s.period_frames;
    s.log->set("xr_display_period_ms", nlohmann::json{{"last", double(s.period_last) * 1e-6},
                                                      {"min", double(s.period_min) * 1e-6},
                                                      {"max", double(s.period_max) * 1e-6},
                                                      {"frames", s.period_frames}});
}
}  // namespace

bool XrStereoSession::beginFrame(XrFrame& frame) {
    Impl& s = *impl_;
    frame = XrFrame{};
    XrFrameState state{XR_TYPE_FRAME_STATE};
    XrFrameWaitInfo wait{XR_TYPE_FRAME_WAIT_INFO};
    if (!XR_LOG(s.instance, xrWaitFrame(s.session, &wait, &state))) return false;
    XrFrameBeginInfo begin{XR_TYPE_FRAME_BEGIN_INFO};
    if (!XR_LOG(s.instance, xrBeginFrame(s.session, &begin))) return false;
    frame.should_render = state.shouldRender == XR_TRUE;
    frame.display_time_ns = state.predictedDisplayTime;
    frame.display_period_ns = state.predictedDisplayPeriod;
    s.last_display_time = state.predictedDisplayTime;
    s.input_time = 0;
    recordPeriod(s, state.predictedDisplayPeriod);
    if (!frame.should_render) return true;

    XrViewLocateInfo locate{XR_TYPE_VIEW_LOCATE_INFO};
    locate.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    locate.displayTime = state.predictedDisplayTime;
    locate.space = s.space;
    XrViewState view_state{XR_TYPE_VIEW_STATE};
    std::uint32_t count = 0;
    for (auto& v : s.views) v = {XR_TYPE_VIEW};
    if (!XR_LOG(s.instance, xrLocateViews(s.session, &locate, &view_state, 2, &count, s.views.data()))) return false;
    frame.views_valid = count == 2 && (view_state.viewStateFlags & XR_VIEW_STATE_ORIENTATION_VALID_BIT);
    for (int i = 0; i < 2; ++i) {
        const XrView& v = s.views[i];
        XrEye& e = frame.eyes[i];
        e.orientation =
            glm::dquat(v.pose.orientation.w, v.pose.orientation.x, v.pose.orientation.y, v.pose.orientation.z);
        e.position = glm::dvec3(v.pose.position.x, v.pose.position.y, v.pose.position.z);
        e.angle_left = v.fov.angleLeft;
        e.angle_right = v.fov.angleRight;
        e.angle_up = v.fov.angleUp;
        e.angle_down = v.fov.angleDown;
    }
    return true;
}

namespace {
unsigned acquire(XrInstance instance, EyeSwapchain& sc) {
    if (sc.handle == XR_NULL_HANDLE) return 0;
    std::uint32_t index = 0;
    XrSwapchainImageAcquireInfo acquire{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
    if (!XR_LOG(instance, xrAcquireSwapchainImage(sc.handle, &acquire, &index))) return 0;
    sc.acquired = true;
    XrSwapchainImageWaitInfo wait{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wait.timeout = 1'000'000'000;  // 1 s: a runtime that does not hand the image back is lost
    if (!XR_LOG(instance, xrWaitSwapchainImage(sc.handle, &wait))) return 0;
    return index < sc.images.size() ? sc.images[index].image : 0;
}

bool release(XrInstance instance, EyeSwapchain& sc) {
    if (!sc.acquired) return true;
    sc.acquired = false;
    XrSwapchainImageReleaseInfo info{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
    return XR_LOG(instance, xrReleaseSwapchainImage(sc.handle, &info));
}
}  // namespace

unsigned XrStereoSession::acquireEye(int eye) { return acquire(impl_->instance, impl_->eyes[eye]); }
bool XrStereoSession::releaseEye(int eye) { return release(impl_->instance, impl_->eyes[eye]); }
bool XrStereoSession::depthAvailable() const { return impl_->depths[0].handle != XR_NULL_HANDLE; }
unsigned XrStereoSession::acquireEyeDepth(int eye) { return acquire(impl_->instance, impl_->depths[eye]); }
bool XrStereoSession::releaseEyeDepth(int eye) { return release(impl_->instance, impl_->depths[eye]); }

double XrStereoSession::predictedDisplayPeriod_s() const { return double(impl_->period_last) * 1e-9; }
std::int64_t XrStereoSession::inputTime_ns() const { return impl_->input_time; }

bool XrStereoSession::endFrame(const XrFrame& frame, bool rendered, const std::optional<XrDepthRange>& depth) {
    Impl& s = *impl_;
    std::array<XrCompositionLayerProjectionView, 2> views{};
    std::array<XrCompositionLayerDepthInfoKHR, 2> depths{};
    const bool with_depth = rendered && depth && depthAvailable();
    XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    const XrCompositionLayerBaseHeader* layers[] = {reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer)};
    XrFrameEndInfo end{XR_TYPE_FRAME_END_INFO};
    end.displayTime = frame.display_time_ns;
    end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    if (rendered) {
        for (int i = 0; i < 2; ++i) {
            views[i] = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
            views[i].pose = s.views[i].pose;
            views[i].fov = s.views[i].fov;
            views[i].subImage.swapchain = s.eyes[i].handle;
            views[i].subImage.imageRect = {{0, 0}, {s.width, s.height}};
            if (with_depth) {
                depths[i] = {XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR};
                depths[i].subImage.swapchain = s.depths[i].handle;
                depths[i].subImage.imageRect = views[i].subImage.imageRect;
                depths[i].minDepth = 0.0f;
                depths[i].maxDepth = 1.0f;
                depths[i].nearZ = depth->near_m;
                depths[i].farZ = depth->far_m;
                views[i].next = &depths[i];
            }
        }
        layer.space = s.space;
        layer.viewCount = 2;
        layer.views = views.data();
        end.layerCount = 1;
        end.layers = layers;
    }
    if (!XR_LOG(s.instance, xrEndFrame(s.session, &end))) return false;
    if (with_depth && s.depth_frames++ == 0) {
        char line[96];
        std::snprintf(line, sizeof line, "xr: depth submitted (near %g m, far %g m)", double(depth->near_m),
                      double(depth->far_m));
        s.log->event(line);
    }
    if (with_depth) s.log->set("xr_depth_frames", s.depth_frames);
    return true;
}

XrInput XrStereoSession::syncInput() {
    Impl& s = *impl_;
    if (s.state != XR_SESSION_STATE_FOCUSED) return {};
    s.input_time = s.last_display_time;
    XrInput input = s.actions.sync(s.space, s.last_display_time);
    noteControllers(s, input.hands_bound);
    return input;
}

bool XrStereoSession::noControllers() const { return impl_->no_controllers; }

void XrStereoSession::requestExit() {
    Impl& s = *impl_;
    s.exit_requested = true;
    if (s.session != XR_NULL_HANDLE && s.running) XR_LOG(s.instance, xrRequestExitSession(s.session));
}

}  // namespace viewer
