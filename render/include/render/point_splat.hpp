// render/point_splat.hpp: draws point clouds as square splats of a fixed size in pixels.
//
// The metric's renderer (white binary images, paper §IV-B); the viewer's PointRenderer
// is its sibling over the same storage (render/point_chunks.hpp). Points are binned into
// spatial chunks of one cell each; each stores float positions relative to its own
// centre and is drawn with a model-view-projection computed in double precision, so
// large coordinates never jitter (camera-relative rendering). Chunks whose bounds miss
// the view frustum are skipped.
#pragma once
#include <core/point_cloud.hpp>
#include <render/gl.hpp>
#include <render/point_chunks.hpp>
#include <render/shader.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace render {

struct SplatStyle {
    float point_size_px = 1.0f;      // side of the square splat, pixels (>= 1)
    bool use_point_colours = false;  // true: each point's rgb; false: `colour`
    glm::vec4 colour{1.0f, 1.0f, 1.0f, 1.0f};
};

struct SplatDrawStats {
    std::size_t chunks_drawn = 0;
    std::size_t chunks_culled = 0;
    std::size_t points_drawn = 0;
};

/// GPU point storage + draw. Needs a current GL 4.5 context for its whole life (create,
/// use and destroy it on the thread where the context is current).
class PointSplatRenderer {
  public:
    /// Compiles the splat program; throws core::Error("shader: ...") on failure.
    PointSplatRenderer();
    ~PointSplatRenderer();
    PointSplatRenderer(const PointSplatRenderer&) = delete;
    PointSplatRenderer& operator=(const PointSplatRenderer&) = delete;

    /// Replaces the stored points by `cloud`'s, binned into cubic cells of `chunk_size_m`
    /// (local frame) so that frustum culling can skip whole cells.
    void setCloud(const core::PointCloud& cloud, double chunk_size_m = 16.0);
    /// Appends `points` (local frame of the cloud being streamed) as one more chunk, for
    /// streaming; the chunk's bounds are computed from its points. Empty spans are ignored.
    /// Throws core::Error("gl: ...") when the GPU has no room for it.
    void appendChunk(std::span<const core::CloudPoint> points);
    /// Drops every stored point.
    void clear();

    std::size_t pointCount() const { return chunks_.uploadedPoints(); }
    std::size_t chunkCount() const { return chunks_.cells().size(); }
    /// Local-frame bounds of every stored point.
    const core::Bounds& bounds() const { return chunks_.bounds(); }

    /// Draws the stored points into the current framebuffer and viewport with
    /// `projection * view` (local frame, double precision). With `cull`, chunks outside
    /// that frustum are skipped. Leaves the depth/blend state to the caller; enables
    /// GL_PROGRAM_POINT_SIZE. Never throws.
    SplatDrawStats draw(const glm::dmat4& view, const glm::dmat4& projection, const SplatStyle& style,
                        bool cull = true) const;

  private:
    Program program_;
    GLint u_mvp_ = -1, u_point_size_ = -1, u_colour_ = -1, u_use_point_colours_ = -1;
    PointChunks chunks_;  // one cell per chunk
};

}  // namespace render
