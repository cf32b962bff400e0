// viewer/src/ui/overlay_renderer.cpp: the overlay's lines and dots (shaders/overlay_lines.vert).
#include "ui/overlay_renderer.hpp"

#include <shaders/shaders.hpp>

#include <algorithm>

namespace viewer {

namespace {
struct GpuVertex {
    float x, y, z;
    float r, g, b, a;
};
}  // namespace

OverlayRenderer::OverlayRenderer()
    : program_("viewer overlay",
               {{GL_VERTEX_SHADER, shaders::overlay_lines_vert, shaders::overlay_lines_vert_files},
                {GL_FRAGMENT_SHADER, shaders::vertex_colour_frag, shaders::vertex_colour_frag_files}}),
      vignette_("viewer comfort vignette",
                {{GL_VERTEX_SHADER, shaders::fullscreen_triangle_vert, shaders::fullscreen_triangle_vert_files},
                 {GL_FRAGMENT_SHADER, shaders::comfort_vignette_frag, shaders::comfort_vignette_frag_files}}),
      panel_("viewer headset panel", {{GL_VERTEX_SHADER, shaders::panel_quad_vert, shaders::panel_quad_vert_files},
                                      {GL_FRAGMENT_SHADER, shaders::panel_quad_frag, shaders::panel_quad_frag_files}}) {
    glCreateVertexArrays(1, &empty_vao_);
    glCreateVertexArrays(1, &panel_vao_);
    glCreateBuffers(1, &panel_buffer_);
    glNamedBufferData(panel_buffer_, 4 * 5 * sizeof(float), nullptr, GL_DYNAMIC_DRAW);
    glEnableVertexArrayAttrib(panel_vao_, 0);
    glVertexArrayAttribFormat(panel_vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(panel_vao_, 0, 0);
    glEnableVertexArrayAttrib(panel_vao_, 1);
    glVertexArrayAttribFormat(panel_vao_, 1, 2, GL_FLOAT, GL_FALSE, 12);
    glVertexArrayAttribBinding(panel_vao_, 1, 0);
    glVertexArrayVertexBuffer(panel_vao_, 0, panel_buffer_, 0, 5 * sizeof(float));
    glCreateVertexArrays(1, &vao_);
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_, 0, 0);
    glEnableVertexArrayAttrib(vao_, 1);
    glVertexArrayAttribFormat(vao_, 1, 4, GL_FLOAT, GL_FALSE, 12);
    glVertexArrayAttribBinding(vao_, 1, 0);
}

OverlayRenderer::~OverlayRenderer() {
    if (buffer_) glDeleteBuffers(1, &buffer_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (empty_vao_) glDeleteVertexArrays(1, &empty_vao_);
    if (panel_vao_) glDeleteVertexArrays(1, &panel_vao_);
    if (panel_buffer_) glDeleteBuffers(1, &panel_buffer_);
}

void OverlayRenderer::drawPanelQuad(GLuint texture, const std::array<glm::dvec3, 4>& corners_eye,
                                    const glm::dmat4& projection, GLuint fbo, int x, int y, int w, int h) const {
    if (texture == 0) return;
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    float data[4 * 5];
    for (int i = 0; i < 4; ++i) {
        data[i * 5 + 0] = float(corners_eye[i].x);
        data[i * 5 + 1] = float(corners_eye[i].y);
        data[i * 5 + 2] = float(corners_eye[i].z);
        data[i * 5 + 3] = uv[i][0];
        data[i * 5 + 4] = uv[i][1];
    }
    glNamedBufferSubData(panel_buffer_, 0, sizeof data, data);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(x, y, w, h);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    panel_.use();
    glUniformMatrix4fv(panel_.uniform("u_projection"), 1, GL_FALSE, &glm::mat4(projection)[0][0]);
    glBindTextureUnit(0, texture);
    glUniform1i(panel_.uniform("u_panel"), 0);
    glBindVertexArray(panel_vao_);
    glDrawArrays(GL_TRIANGLE_FAN, 0, 4);
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_BLEND);
    render::logGl("OverlayRenderer::drawPanelQuad", __FILE__, __LINE__);
}

void OverlayRenderer::drawVignette(GLuint fbo, int x, int y, int w, int h, float aperture, float feather,
                                   float strength) const {
    if (!(strength > 0.0f)) return;
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(x, y, w, h);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    vignette_.use();
    glUniform4f(vignette_.uniform("u_viewport"), float(x), float(y), float(w), float(h));
    glUniform1f(vignette_.uniform("u_aperture"), aperture);
    glUniform1f(vignette_.uniform("u_feather"), feather);
    glUniform1f(vignette_.uniform("u_strength"), strength);
    glBindVertexArray(empty_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_BLEND);
    render::logGl("OverlayRenderer::drawVignette", __FILE__, __LINE__);
}

void OverlayRenderer::draw(const OverlayList& list, const glm::dmat4& view, const glm::dmat4& projection, GLuint fbo,
                           int x, int y, int w, int h, float dot_px) const {
    const std::size_t n = list.lines.size() + list.dots.size();
    if (n == 0) return;
    std::vector<GpuVertex> data;
    data.reserve(n);
    for (const auto* part : {&list.lines, &list.dots})
        for (const OverlayVertex& v : *part) {
            const glm::dvec3 e = glm::dvec3(view * glm::dvec4(v.local, 1.0));
            data.push_back({float(e.x), float(e.y), float(e.z), v.colour.r, v.colour.g, v.colour.b, v.colour.a});
        }
    if (n > capacity_) {
        if (buffer_) glDeleteBuffers(1, &buffer_);
        glCreateBuffers(1, &buffer_);
        capacity_ = std::max<std::size_t>(n, 256);
        glNamedBufferData(buffer_, static_cast<GLsizeiptr>(capacity_ * sizeof(GpuVertex)), nullptr, GL_DYNAMIC_DRAW);
    }
    glNamedBufferSubData(buffer_, 0, static_cast<GLsizeiptr>(n * sizeof(GpuVertex)), data.data());
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(x, y, w, h);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glEnable(GL_PROGRAM_POINT_SIZE);
    program_.use();
    glUniformMatrix4fv(program_.uniform("u_projection"), 1, GL_FALSE, &glm::mat4(projection)[0][0]);
    glUniform1f(program_.uniform("u_size_px"), dot_px);
    glBindVertexArray(vao_);
    glVertexArrayVertexBuffer(vao_, 0, buffer_, 0, sizeof(GpuVertex));
    if (!list.lines.empty()) glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(list.lines.size()));
    if (!list.dots.empty())
        glDrawArrays(GL_POINTS, static_cast<GLint>(list.lines.size()), static_cast<GLsizei>(list.dots.size()));
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_BLEND);
    render::logGl("OverlayRenderer::draw", __FILE__, __LINE__);
}

}  // namespace viewer
