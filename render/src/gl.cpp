// render/src/gl.cpp: GL error names and checks, loader entry.
#include <render/gl.hpp>

#include <core/error.hpp>

#include <cstdio>
#include <string>

namespace render {

const char* glErrorName(GLenum error) {
    switch (error) {
        case GL_NO_ERROR: return "GL_NO_ERROR";
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
        case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
        default: break;
    }
    static thread_local char buffer[32];
    std::snprintf(buffer, sizeof buffer, "GL_error_0x%04x", static_cast<unsigned>(error));
    return buffer;
}

void loadGl(GLADloadfunc get_proc_address) {
    const int version = gladLoadGL(get_proc_address);
    if (version == 0) throw core::Error("gl: loading the OpenGL entry points failed (gladLoadGL)");
    const int major = GLAD_VERSION_MAJOR(version), minor = GLAD_VERSION_MINOR(version);
    if (major < 4 || (major == 4 && minor < 5))
        throw core::Error("gl: context is OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
                          "; OpenGL 4.5 core is required");
}

namespace {
std::string collectErrors(const char* expression, const char* file, int line, bool& any) {
    std::string names;
    any = false;
    for (int i = 0; i < 16; ++i) {  // a lost context can report errors forever
        const GLenum error = glGetError();
        if (error == GL_NO_ERROR) break;
        if (any) names += ", ";
        names += glErrorName(error);
        any = true;
    }
    if (!any) return {};
    return std::string("gl: ") + expression + ": " + names + " at " + file + ":" + std::to_string(line);
}
}  // namespace

void checkGl(const char* expression, const char* file, int line) {
    bool any = false;
    std::string message = collectErrors(expression, file, line, any);
    if (any) throw core::Error(message);
}

bool logGl(const char* expression, const char* file, int line) {
    bool any = false;
    std::string message = collectErrors(expression, file, line, any);
    if (any) std::fprintf(stderr, "ladarvr: %s\n", message.c_str());
    return !any;
}

std::string glDescription() {
    auto str = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "?");
    };
    return str(GL_VENDOR) + " / " + str(GL_RENDERER) + " / " + str(GL_VERSION);
}

}  // namespace render
