// Headless GL: an EGL surfaceless context, an FBO cleared and read back (Mesa llvmpipe in CI).
#include <render/egl_context.hpp>
#include <render/gl.hpp>
#include <render/shader.hpp>

#include <core/error.hpp>

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <string>

TEST_CASE("egl context: GL 4.5 core, FBO clear colour reads back") {
    render::EglContext context;
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    CHECK((major > 4 || (major == 4 && minor >= 5)));
    MESSAGE("GL: " << render::glDescription() << " on EGL " << context.platform());

    GLuint texture = 0, fbo = 0;
    GL_CHECK(glCreateTextures(GL_TEXTURE_2D, 1, &texture));
    GL_CHECK(glTextureStorage2D(texture, 1, GL_RGBA8, 8, 4));
    GL_CHECK(glCreateFramebuffers(1, &fbo));
    GL_CHECK(glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, texture, 0));
    REQUIRE(glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, 8, 4);
    glClearColor(0.2f, 0.4f, 0.6f, 1.0f);
    GL_CHECK(glClear(GL_COLOR_BUFFER_BIT));
    std::array<std::uint8_t, 8 * 4 * 4> pixels{};
    GL_CHECK(glReadPixels(0, 0, 8, 4, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data()));
    for (int i = 0; i < 8 * 4; ++i) {
        CHECK(pixels[4 * i + 0] == 51);
        CHECK(pixels[4 * i + 1] == 102);
        CHECK(pixels[4 * i + 2] == 153);
        CHECK(pixels[4 * i + 3] == 255);
    }
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &texture);
}

TEST_CASE("GL_CHECK throws naming the expression and the error") {
    render::EglContext context;
    try {
        GL_CHECK(glBindBuffer(0x1234, 0));  // not a buffer target
        FAIL("GL_CHECK did not throw");
    } catch (const core::Error& e) {
        const std::string message = e.what();
        CHECK(message.find("gl: glBindBuffer(0x1234, 0): GL_INVALID_ENUM at ") == 0);
        CHECK(message.find("egl_context_test.cpp:") != std::string::npos);
    }
}

TEST_CASE("shader compile errors are one readable line naming the program and stage") {
    render::EglContext context;
    try {
        render::Program bad("broken", {{GL_VERTEX_SHADER, "#version 450 core\nvoid main() { nope(); }\n"}});
        FAIL("bad shader compiled");
    } catch (const core::Error& e) {
        const std::string message = e.what();
        CHECK(message.find("shader: broken: vertex compile failed:") == 0);
        CHECK(message.find('\n') == std::string::npos);
    }
}
