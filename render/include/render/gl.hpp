// render/gl.hpp: the OpenGL 4.5 core API (glad 2, generated at build time) and error checks.
//
// Include this instead of any other GL header. A context must be current and
// render::loadGl() must have succeeded before any gl* call (EglContext does both).
#pragma once
#include <glad/gl.h>

#include <string>

namespace render {

/// "GL_INVALID_ENUM", ... for a glGetError() value; "GL_error_0x...." for unknown values.
const char* glErrorName(GLenum error);

/// Loads the GL entry points through `get_proc_address` (eglGetProcAddress,
/// glfwGetProcAddress, ...) for the current context. Throws
/// core::Error("gl: ...") if loading fails or the context is older than 4.5 core.
void loadGl(GLADloadfunc get_proc_address);

/// Drains glGetError(); if any error was pending throws core::Error("gl: <expr>: <ERROR>
/// at file:line"). Used by GL_CHECK on setup paths.
void checkGl(const char* expression, const char* file, int line);

/// Like checkGl but never throws: prints one line to stderr and returns false on an error.
/// For per-frame paths that must degrade instead of throwing.
bool logGl(const char* expression, const char* file, int line);

/// "vendor / renderer / version" of the current context.
std::string glDescription();

}  // namespace render

/// Runs a GL call, then throws core::Error naming the expression, the error and file:line.
#define GL_CHECK(expr)                                \
    do {                                              \
        expr;                                         \
        ::render::checkGl(#expr, __FILE__, __LINE__); \
    } while (0)

/// Runs a GL call, then logs (never throws) any error with the expression and file:line.
#define GL_LOG(expr)                                \
    do {                                            \
        expr;                                       \
        ::render::logGl(#expr, __FILE__, __LINE__); \
    } while (0)
