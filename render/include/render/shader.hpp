// render/shader.hpp: GLSL compile and link with readable errors, as an owning Program.
#pragma once
#include <render/gl.hpp>

#include <initializer_list>
#include <string>
#include <string_view>

namespace render {

/// One stage of a program: GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER, ...
/// `files` says which file each source-string number of the text's #line directives
/// names ("0 = x.vert, 1 = include/y.glsl", the *_files of <shaders/shaders.hpp>); a
/// compile error quotes it, so the driver's "1:12" leads to include/y.glsl line 12.
struct ShaderStage {
    GLenum stage;
    std::string_view source;
    std::string_view files = {};
};

/// A linked GL program; deletes it on destruction. Needs a current GL 4.5 context.
class Program {
  public:
    Program() = default;
    /// Compiles and links; throws core::Error("shader: <name>: <stage> compile failed:
    /// <driver log> (source strings: <files>)") or ("shader: <name>: link failed: <log>").
    Program(std::string_view name, std::initializer_list<ShaderStage> stages);
    ~Program();
    Program(Program&& other) noexcept;
    Program& operator=(Program&& other) noexcept;
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;

    GLuint id() const { return id_; }
    void use() const { glUseProgram(id_); }
    /// Uniform location, or -1 if the uniform is absent or was optimised away.
    GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

  private:
    GLuint id_ = 0;
};

/// "vertex", "fragment", "compute", ... for a shader stage enum.
const char* stageName(GLenum stage);

}  // namespace render
