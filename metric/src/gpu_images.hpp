// metric/src/gpu_images.hpp (internal): the binary images I1, I2, I3 of paper §IV-B on the
// GPU and their pixel counts. Two interchangeable ways to draw the square splats:
//  - Compute (default): a compute shader projects every point and ORs its bit into an
//    R32UI mask image (bit 1 = P1, 2 = P2, 4 = P3); it also keeps, per pixel, the
//    distance of the nearest P2 point and sets bit 8 where a P3 point is nearer than that
//    by more than a margin (the depth-aware variant, docs/metric.md).
//  - Raster: GL_POINTS with gl_PointSize into an RGBA8 target through colour masks
//    (render::PointSplatRenderer, as the viewer draws); no depth-aware variant.
// Both rasterise the same pixels: those whose centres fall in the splat's square.
#pragma once
#include <metric/visibility.hpp>

#include <core/point_cloud.hpp>
#include <render/gl.hpp>
#include <render/orbit_camera.hpp>
#include <render/point_splat.hpp>
#include <render/shader.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace metric::detail {

struct ImageCounts {
    std::int64_t i1 = 0, i2 = 0, i3 = 0, i4 = 0, visible = 0, depth_visible = 0;
};

/// A cloud in one GPU buffer, sorted into spatial cells for culling.
struct GpuCloud {
    GLuint buffer = 0;  // vec4 per point: position - centre
    glm::dvec3 centre{0.0};
    struct Cell {
        std::uint32_t first = 0, count = 0;
        core::Bounds bounds;
    };
    std::vector<Cell> cells;
    std::size_t points = 0;
};

class GpuImages {
  public:
    /// Clouds in one local frame. Needs a current GL 4.5 context for its whole life.
    GpuImages(const core::PointCloud& p1, const core::PointCloud& p2, const core::PointCloud& p3, double cell_m);
    ~GpuImages();
    GpuImages(const GpuImages&) = delete;
    GpuImages& operator=(const GpuImages&) = delete;

    /// Draws the pixels `drawn` of a width x height image (`cull`: skip cells outside
    /// drawn's frustum) and counts those of `counted` (inside drawn). Adds the points
    /// sent to the GPU to *points.
    ImageCounts renderAndCount(const glm::dmat4& view, const glm::dmat4& projection, int width, int height,
                               const render::PixelRect& drawn, const render::PixelRect& counted, double splat_px,
                               double depth_margin_m, Rasterizer rasterizer, bool cull, std::size_t* points);

    /// Full-frame I1..I4 of the last renderAndCount call whose `drawn` was the whole image.
    MetricPictures readPictures(int view, int width, int height, Rasterizer rasterizer);

  private:
    void ensureImages(int width, int height);
    std::size_t drawCompute(const GpuCloud& cloud, const glm::dmat4& view, const glm::dmat4& projection,
                            const glm::dmat4& cull_matrix, int width, int height, const render::PixelRect& drawn,
                            double splat_px, std::uint32_t bit, int mode, double margin_m, bool cull);

    std::array<GpuCloud, 3> clouds_;
    render::PointSplatRenderer raster_[3];
    render::Program splat_program_, count_mask_program_, count_rgba_program_;
    GLuint ranges_buffer_ = 0, counts_buffer_ = 0;
    std::size_t ranges_capacity_ = 0;
    GLuint mask_ = 0, depth_ = 0, rgba_ = 0, fbo_ = 0;
    int width_ = 0, height_ = 0;
    std::vector<std::uint32_t> ranges_;
};

}  // namespace metric::detail
