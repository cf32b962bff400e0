// render/egl_context.hpp: a headless OpenGL 4.5 core context, no X server, no window.
//
// EGL on the surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA) with
// EGL_KHR_no_config_context and no surface: draw into framebuffer objects only
// (docs/render.md). Works on Mesa llvmpipe in CI.
// Falls back to the EGL device platform (EGL_EXT_platform_device, e.g. NVIDIA's
// driver) when the surfaceless platform is missing.
#pragma once
#include <string>

namespace render {

struct EglContextOptions {
    int major = 4;  // at least 4.5 core is required by render
    int minor = 5;
    bool debug = false;  // EGL_CONTEXT_OPENGL_DEBUG (slower; for diagnosing)
};

/// Owns an EGLDisplay + EGLContext, current on the creating thread after construction,
/// with the glad GL entry points loaded through eglGetProcAddress.
class EglContext {
  public:
    /// Throws core::Error("egl: ...") naming the missing extension or the failing call.
    explicit EglContext(const EglContextOptions& options = {});
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    /// Makes the context current on the calling thread (and loads GL if not yet done).
    /// Throws core::Error("egl: eglMakeCurrent ...") on failure.
    void makeCurrent();
    /// "surfaceless" or "device": the EGL platform actually used.
    const std::string& platform() const { return platform_; }

  private:
    void* display_ = nullptr;  // EGLDisplay
    void* context_ = nullptr;  // EGLContext
    std::string platform_;
};

}  // namespace render
