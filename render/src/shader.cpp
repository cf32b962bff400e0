// render/src/shader.cpp: GLSL compile/link with the driver's log in the error.
#include <render/shader.hpp>

#include <core/error.hpp>

#include <string>
#include <utility>
#include <vector>

namespace render {

const char* stageName(GLenum stage) {
    switch (stage) {
        case GL_VERTEX_SHADER: return "vertex";
        case GL_FRAGMENT_SHADER: return "fragment";
        case GL_GEOMETRY_SHADER: return "geometry";
        case GL_COMPUTE_SHADER: return "compute";
        case GL_TESS_CONTROL_SHADER: return "tessellation control";
        case GL_TESS_EVALUATION_SHADER: return "tessellation evaluation";
        default: return "unknown-stage";
    }
}

namespace {
std::string trimLog(std::string log) {
    while (!log.empty() && (log.back() == '\n' || log.back() == '\0' || log.back() == ' ')) log.pop_back();
    for (char& c : log)
        if (c == '\n') c = ' ';  // keep the error on one line
    return log;
}
}  // namespace

Program::Program(std::string_view name, std::initializer_list<ShaderStage> stages) {
    std::vector<GLuint> shaders;
    auto cleanup = [&] {
        for (GLuint s : shaders) glDeleteShader(s);
    };
    for (const ShaderStage& stage : stages) {
        const GLuint shader = glCreateShader(stage.stage);
        if (shader == 0) {
            cleanup();
            throw core::Error(std::string("shader: ") + std::string(name) + ": glCreateShader(" +
                              stageName(stage.stage) + ") failed");
        }
        shaders.push_back(shader);
        const GLchar* source = stage.source.data();
        const GLint length = static_cast<GLint>(stage.source.size());
        glShaderSource(shader, 1, &source, &length);
        glCompileShader(shader);
        GLint ok = GL_FALSE;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            GLint log_length = 0;
            glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &log_length);
            std::string log(static_cast<std::size_t>(log_length > 0 ? log_length : 1), '\0');
            glGetShaderInfoLog(shader, log_length, nullptr, log.data());
            cleanup();
            std::string where;
            if (!stage.files.empty()) where = " (source strings: " + std::string(stage.files) + ")";
            throw core::Error(std::string("shader: ") + std::string(name) + ": " + stageName(stage.stage) +
                              " compile failed: " + trimLog(log) + where);
        }
    }
    id_ = glCreateProgram();
    for (GLuint s : shaders) glAttachShader(id_, s);
    glLinkProgram(id_);
    cleanup();  // flagged for deletion, freed with the program
    GLint ok = GL_FALSE;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint log_length = 0;
        glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &log_length);
        std::string log(static_cast<std::size_t>(log_length > 0 ? log_length : 1), '\0');
        glGetProgramInfoLog(id_, log_length, nullptr, log.data());
        glDeleteProgram(id_);
        id_ = 0;
        throw core::Error(std::string("shader: ") + std::string(name) + ": link failed: " + trimLog(log));
    }
}

Program::~Program() {
    if (id_) glDeleteProgram(id_);
}

Program::Program(Program&& other) noexcept : id_(std::exchange(other.id_, 0)) {}

Program& Program::operator=(Program&& other) noexcept {
    if (this != &other) {
        if (id_) glDeleteProgram(id_);
        id_ = std::exchange(other.id_, 0);
    }
    return *this;
}

}  // namespace render
