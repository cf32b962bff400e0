// render/src/egl_context.cpp: EGL surfaceless context (see egl_context.hpp).
#include <render/egl_context.hpp>
#include <render/gl.hpp>

#include <core/error.hpp>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace render {
namespace {

std::string eglErrorName(EGLint error) {
    switch (error) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        default: {
            char buffer[32];
            std::snprintf(buffer, sizeof buffer, "EGL_error_0x%04x", static_cast<unsigned>(error));
            return buffer;
        }
    }
}

[[noreturn]] void fail(const std::string& what) {
    throw core::Error("egl: " + what + ": " + eglErrorName(eglGetError()));
}

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

GLADapiproc loadProc(const char* name) { return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name)); }

}  // namespace

EglContext::EglContext(const EglContextOptions& options) {
    const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client_extensions) fail("no client extensions (EGL 1.5 / EGL_EXT_client_extensions needed)");
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) fail("eglGetPlatformDisplayEXT is missing");

    EGLDisplay display = EGL_NO_DISPLAY;
    if (hasExtension(client_extensions, "EGL_MESA_platform_surfaceless")) {
        display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        platform_ = "surfaceless";
    }
    if (display == EGL_NO_DISPLAY && hasExtension(client_extensions, "EGL_EXT_platform_device")) {
        auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        EGLDeviceEXT devices[8];
        EGLint count = 0;
        if (query_devices && query_devices(8, devices, &count) && count > 0) {
            display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
            platform_ = "device";
        }
    }
    if (display == EGL_NO_DISPLAY)
        fail("neither EGL_MESA_platform_surfaceless nor EGL_EXT_platform_device gives a display");

    EGLint egl_major = 0, egl_minor = 0;
    if (!eglInitialize(display, &egl_major, &egl_minor)) fail("eglInitialize (" + platform_ + ")");
    display_ = display;
    const char* display_extensions = eglQueryString(display, EGL_EXTENSIONS);
    for (const char* needed : {"EGL_KHR_surfaceless_context", "EGL_KHR_no_config_context"}) {
        if (!hasExtension(display_extensions, needed)) {
            eglTerminate(display);
            display_ = nullptr;
            throw core::Error(std::string("egl: display (") + platform_ + ") lacks " + needed);
        }
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        eglTerminate(display);
        display_ = nullptr;
        fail("eglBindAPI(EGL_OPENGL_API)");
    }
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 options.major,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 options.minor,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_CONTEXT_OPENGL_DEBUG,
                                 options.debug ? EGL_TRUE : EGL_FALSE,
                                 EGL_NONE};
    EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT) {
        const std::string error = eglErrorName(eglGetError());
        eglTerminate(display);
        display_ = nullptr;
        throw core::Error("egl: eglCreateContext(OpenGL " + std::to_string(options.major) + "." +
                          std::to_string(options.minor) + " core, no config): " + error);
    }
    context_ = context;
    try {
        makeCurrent();
        loadGl(&loadProc);
    } catch (...) {
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
        eglTerminate(display);
        throw;
    }
}

EglContext::~EglContext() {
    if (!display_) return;
    eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_) eglDestroyContext(static_cast<EGLDisplay>(display_), static_cast<EGLContext>(context_));
    // No eglTerminate: the display is shared by every EglContext of the process, and
    // terminating it would pull it from under another live context.
}

void EglContext::makeCurrent() {
    if (!eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE,
                        static_cast<EGLContext>(context_)))
        fail("eglMakeCurrent(no surface)");
}

}  // namespace render
