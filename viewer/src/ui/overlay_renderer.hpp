// viewer/src/ui/overlay_renderer.hpp: lines and dots drawn over an eye's image (the
// pointer's ray and hit, the designated point, candidate boxes). The tools fill an
// OverlayList in the cloud's local frame; the renderer transforms it per eye in double.
#pragma once
#include <render/gl.hpp>
#include <render/shader.hpp>

#include <glm/glm.hpp>

#include <array>
#include <optional>

#include <vector>

namespace viewer {

struct OverlayVertex {
    glm::dvec3 local{0.0};
    glm::vec4 colour{1.0f};
};

/// The comfort vignette (OverlayRenderer::drawVignette), drawn in the headset only.
struct VignetteStyle {
    float aperture = 0.7f, feather = 0.2f, strength = 0.0f;
};

/// What the tools draw this frame, local frame.
struct OverlayList {
    std::vector<OverlayVertex> lines;  // pairs
    std::vector<OverlayVertex> dots;
    std::optional<VignetteStyle> vignette;
    void line(const glm::dvec3& a, const glm::dvec3& b, const glm::vec4& colour) {
        lines.push_back({a, colour});
        lines.push_back({b, colour});
    }
    void clear() {
        lines.clear();
        dots.clear();
        vignette.reset();
    }
};

class OverlayRenderer {
  public:
    /// Compiles the program; throws core::Error("shader: ...") (setup path).
    OverlayRenderer();
    ~OverlayRenderer();
    OverlayRenderer(const OverlayRenderer&) = delete;
    OverlayRenderer& operator=(const OverlayRenderer&) = delete;

    /// Draws `list` into framebuffer `fbo` at viewport (x, y, w, h) with `view` (local to
    /// eye, may carry the zoom's scale) and `projection`; no depth test (always on top).
    void draw(const OverlayList& list, const glm::dmat4& view, const glm::dmat4& projection, GLuint fbo, int x, int y,
              int w, int h, float dot_px) const;

    /// Darkens the view outside `aperture` (fraction of the half view) with a `feather`
    /// wide fade, at `strength` in [0, 1] (the comfort vignette). Nothing at strength 0.
    void drawVignette(GLuint fbo, int x, int y, int w, int h, float aperture, float feather, float strength) const;

    /// Draws `texture` (the ImGui panel) on the quad whose corners are given in eye space
    /// (bottom left, bottom right, top right, top left), blended over the image.
    void drawPanelQuad(GLuint texture, const std::array<glm::dvec3, 4>& corners_eye, const glm::dmat4& projection,
                       GLuint fbo, int x, int y, int w, int h) const;

  private:
    render::Program program_;
    render::Program vignette_;
    render::Program panel_;
    GLuint panel_vao_ = 0, panel_buffer_ = 0;
    GLuint empty_vao_ = 0;
    GLuint vao_ = 0;
    mutable GLuint buffer_ = 0;  // grown on demand by draw()
    mutable std::size_t capacity_ = 0;
};

}  // namespace viewer
