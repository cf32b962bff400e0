// tests/viewer/ui/overlay_renderer_test.cpp: the overlay drawn headless (EGL): the comfort
// vignette's clear centre and dark edge, and a dot where its point projects.
#include "ui/overlay_renderer.hpp"
#include "points/point_renderer.hpp"

#include <render/egl_context.hpp>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <vector>

namespace {
constexpr int kSize = 64;
std::vector<std::uint8_t> readBack(const viewer::EyeTarget& t) {
    std::vector<std::uint8_t> rgba(std::size_t(kSize) * kSize * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(t.colour, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
    return rgba;
}
int red(const std::vector<std::uint8_t>& rgba, int x, int y) { return rgba[(std::size_t(y) * kSize + x) * 4]; }
}  // namespace

TEST_CASE("the comfort vignette keeps the centre and darkens the edge, by its strength") {
    render::EglContext context;
    viewer::EyeTarget target;
    REQUIRE(target.ensure(kSize, kSize));
    viewer::OverlayRenderer overlay;
    auto whiteThenVignette = [&](float strength) {
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        overlay.drawVignette(target.fbo, 0, 0, kSize, kSize, 0.7f, 0.2f, strength);
        return readBack(target);
    };
    const auto full = whiteThenVignette(1.0f);
    CHECK(red(full, kSize / 2, kSize / 2) == 255);       // centre: clear
    CHECK(red(full, 0, 0) == 0);                         // corner (radius ~1.4): black
    CHECK(red(full, kSize / 2, 1) < 10);                 // edge (radius ~0.97 > 0.9): black
    CHECK(red(full, kSize / 2, kSize / 2 - 20) == 255);  // radius ~0.63 < 0.7: clear
    const auto half = whiteThenVignette(0.5f);
    CHECK(std::abs(red(half, 0, 0) - 128) <= 2);  // half strength: half dark
    const auto none = whiteThenVignette(0.0f);
    CHECK(red(none, 0, 0) == 255);
    REQUIRE(glGetError() == GL_NO_ERROR);
    target.destroy();
}

TEST_CASE("an overlay dot lands where its point projects, at any distance from the origin") {
    render::EglContext context;
    viewer::EyeTarget target;
    REQUIRE(target.ensure(kSize, kSize));
    viewer::OverlayRenderer overlay;
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    // A point 10^6 m out, seen from 10 m above with an orthographic 64 m wide view.
    const glm::dvec3 p(1.0e6 + 8.0, -2.0e6, 5.0);
    const glm::dvec3 eye(1.0e6, -2.0e6, 15.0);
    const glm::dmat4 view = glm::lookAt(eye, eye - glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0));
    const glm::dmat4 projection = glm::ortho(-32.0, 32.0, -32.0, 32.0, 1.0, 100.0);
    viewer::OverlayList list;
    list.dots.push_back({p, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)});
    overlay.draw(list, view, projection, target.fbo, 0, 0, kSize, kSize, 3.0f);
    const auto rgba = readBack(target);
    CHECK(red(rgba, 32 + 8, 32) == 255);  // 8 m east of the eye = 8 px right of the centre
    CHECK(red(rgba, 32, 32) == 0);
    target.destroy();
}
