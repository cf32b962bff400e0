// metric/src/gpu_images.cpp: I1, I2, I3 and their counts on the GPU (paper §IV-B steps 1-3);
// see gpu_images.hpp.
#include "gpu_images.hpp"

#include <core/error.hpp>
#include <core/spatial_hash.hpp>
#include <shaders/shaders.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace metric::detail {
namespace {

GpuCloud upload(const core::PointCloud& cloud, double cell_m) {
    GpuCloud gpu;
    gpu.points = cloud.points.size();
    if (cloud.points.empty()) return gpu;
    const core::Bounds all = cloud.bounds();
    gpu.centre = all.centre();
    const core::CellBins cells = core::binByCell(cloud.points, cell_m);
    std::vector<glm::vec4> data;
    data.reserve(cloud.points.size());
    for (std::size_t c = 0; c < cells.cells(); ++c) {
        const auto indices = cells.cell(c);
        GpuCloud::Cell cell;
        cell.first = static_cast<std::uint32_t>(data.size());
        cell.count = static_cast<std::uint32_t>(indices.size());
        for (std::uint32_t i : indices) {
            const glm::dvec3 p(cloud.points[i].position);
            cell.bounds.extend(p);
            data.emplace_back(glm::vec3(p - gpu.centre), 0.0f);
        }
        gpu.cells.push_back(cell);
    }
    GL_CHECK(glCreateBuffers(1, &gpu.buffer));
    GL_CHECK(
        glNamedBufferStorage(gpu.buffer, static_cast<GLsizeiptr>(data.size() * sizeof(glm::vec4)), data.data(), 0));
    return gpu;
}

glm::mat4 toFloat(const glm::dmat4& m) { return glm::mat4(m); }

}  // namespace

GpuImages::GpuImages(const core::PointCloud& p1, const core::PointCloud& p2, const core::PointCloud& p3, double cell_m)
    : splat_program_("metric-splat",
                     {{GL_COMPUTE_SHADER, shaders::metric_splat_comp, shaders::metric_splat_comp_files}}),
      count_mask_program_("metric-count-mask", {{GL_COMPUTE_SHADER, shaders::metric_count_mask_comp,
                                                 shaders::metric_count_mask_comp_files}}),
      count_rgba_program_("metric-count-rgba", {{GL_COMPUTE_SHADER, shaders::metric_count_rgba_comp,
                                                 shaders::metric_count_rgba_comp_files}}) {
    clouds_[0] = upload(p1, cell_m);
    clouds_[1] = upload(p2, cell_m);
    clouds_[2] = upload(p3, cell_m);
    raster_[0].setCloud(p1, cell_m);
    raster_[1].setCloud(p2, cell_m);
    raster_[2].setCloud(p3, cell_m);
    GL_CHECK(glCreateBuffers(1, &counts_buffer_));
    GL_CHECK(glNamedBufferStorage(counts_buffer_, 8 * sizeof(GLuint), nullptr, GL_DYNAMIC_STORAGE_BIT));
}

GpuImages::~GpuImages() {
    for (GpuCloud& c : clouds_)
        if (c.buffer) glDeleteBuffers(1, &c.buffer);
    if (ranges_buffer_) glDeleteBuffers(1, &ranges_buffer_);
    if (counts_buffer_) glDeleteBuffers(1, &counts_buffer_);
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    for (GLuint t : {mask_, depth_, rgba_})
        if (t) glDeleteTextures(1, &t);
}

void GpuImages::ensureImages(int width, int height) {
    if (mask_ && width_ == width && height_ == height) return;
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    for (GLuint t : {mask_, depth_, rgba_})
        if (t) glDeleteTextures(1, &t);
    GL_CHECK(glCreateTextures(GL_TEXTURE_2D, 1, &mask_));
    GL_CHECK(glTextureStorage2D(mask_, 1, GL_R32UI, width, height));
    GL_CHECK(glCreateTextures(GL_TEXTURE_2D, 1, &depth_));
    GL_CHECK(glTextureStorage2D(depth_, 1, GL_R32UI, width, height));
    GL_CHECK(glCreateTextures(GL_TEXTURE_2D, 1, &rgba_));
    GL_CHECK(glTextureStorage2D(rgba_, 1, GL_RGBA8, width, height));
    GL_CHECK(glCreateFramebuffers(1, &fbo_));
    GL_CHECK(glNamedFramebufferTexture(fbo_, GL_COLOR_ATTACHMENT0, rgba_, 0));
    if (glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw core::Error("metric: offscreen framebuffer " + std::to_string(width) + "x" + std::to_string(height) +
                          " is incomplete");
    width_ = width;
    height_ = height;
}

std::size_t GpuImages::drawCompute(const GpuCloud& cloud, const glm::dmat4& view, const glm::dmat4& projection,
                                   const glm::dmat4& cull_matrix, int width, int height, const render::PixelRect& drawn,
                                   double splat_px, std::uint32_t bit, int mode, double margin_m, bool cull) {
    if (cloud.points == 0) return 0;
    const render::Frustum frustum = render::Frustum::fromMatrix(cull_matrix);
    ranges_.clear();
    std::uint32_t total = 0;
    for (const GpuCloud::Cell& cell : cloud.cells) {
        if (cull && !frustum.intersects(cell.bounds)) continue;
        ranges_.push_back(cell.first);
        ranges_.push_back(total);
        total += cell.count;
    }
    if (total == 0) return 0;
    const std::size_t bytes = ranges_.size() * sizeof(std::uint32_t);
    if (bytes > ranges_capacity_) {
        if (ranges_buffer_) glDeleteBuffers(1, &ranges_buffer_);
        ranges_capacity_ = std::max<std::size_t>(bytes, 4096) * 2;
        glCreateBuffers(1, &ranges_buffer_);
        glNamedBufferStorage(ranges_buffer_, static_cast<GLsizeiptr>(ranges_capacity_), nullptr,
                             GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(ranges_buffer_, 0, static_cast<GLsizeiptr>(bytes), ranges_.data());
    glm::dmat4 model(1.0);
    model[3] = glm::dvec4(cloud.centre, 1.0);
    const glm::mat4 mvp = toFloat(projection * view * model), mv = toFloat(view * model);
    const GLuint program = splat_program_.id();
    glUseProgram(program);
    glUniformMatrix4fv(splat_program_.uniform("u_mvp"), 1, GL_FALSE, &mvp[0][0]);
    glUniformMatrix4fv(splat_program_.uniform("u_mv"), 1, GL_FALSE, &mv[0][0]);
    glUniform1ui(splat_program_.uniform("u_range_count"), static_cast<GLuint>(ranges_.size() / 2));
    glUniform1ui(splat_program_.uniform("u_total"), total);
    glUniform2f(splat_program_.uniform("u_image_size"), static_cast<float>(width), static_cast<float>(height));
    glUniform2i(splat_program_.uniform("u_region_origin"), drawn.x0, drawn.y0);
    glUniform2i(splat_program_.uniform("u_region_size"), drawn.width(), drawn.height());
    glUniform1f(splat_program_.uniform("u_splat"), static_cast<float>(splat_px));
    glUniform1ui(splat_program_.uniform("u_bit"), bit);
    glUniform1i(splat_program_.uniform("u_mode"), mode);
    glUniform1f(splat_program_.uniform("u_margin_m"), static_cast<float>(margin_m));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, cloud.buffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, ranges_buffer_);
    glBindImageTexture(0, mask_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(1, depth_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    const GLuint groups = std::min<GLuint>(65535u, (total + 127u) / 128u);
    glDispatchCompute(groups, 1, 1);
    return total;
}

ImageCounts GpuImages::renderAndCount(const glm::dmat4& view, const glm::dmat4& projection, int width, int height,
                                      const render::PixelRect& drawn, const render::PixelRect& counted, double splat_px,
                                      double depth_margin_m, Rasterizer rasterizer, bool cull, std::size_t* points) {
    ensureImages(width, height);
    const bool full = drawn.x0 == 0 && drawn.y0 == 0 && drawn.x1 == width && drawn.y1 == height;
    const glm::dmat4 region_projection =
        full ? projection : render::subRectProjection(projection, width, height, drawn);
    std::size_t sent = 0;
    if (rasterizer == Rasterizer::Compute) {
        const GLuint zero = 0, far_bits = 0x7F800000u;  // +inf as float bits: larger than any distance
        glClearTexSubImage(mask_, 0, 0, 0, 0, drawn.width(), drawn.height(), 1, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glClearTexSubImage(depth_, 0, 0, 0, 0, drawn.width(), drawn.height(), 1, GL_RED_INTEGER, GL_UNSIGNED_INT,
                           &far_bits);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
        const glm::dmat4 cull_matrix = region_projection * view;
        sent +=
            drawCompute(clouds_[0], view, projection, cull_matrix, width, height, drawn, splat_px, 1u, 0, 0.0, cull);
        sent +=
            drawCompute(clouds_[1], view, projection, cull_matrix, width, height, drawn, splat_px, 2u, 1, 0.0, cull);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);  // P2's nearest distances are complete
        sent += drawCompute(clouds_[2], view, projection, cull_matrix, width, height, drawn, splat_px, 4u, 2,
                            depth_margin_m, cull);
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glViewport(0, 0, drawn.width(), drawn.height());
        glEnable(GL_SCISSOR_TEST);  // wide points are not clipped to the viewport, only to this
        glScissor(0, 0, drawn.width(), drawn.height());
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_BLEND);
        glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        render::SplatStyle style;
        style.point_size_px = static_cast<float>(splat_px);
        const GLboolean masks[3][3] = {
            {GL_TRUE, GL_FALSE, GL_FALSE}, {GL_FALSE, GL_TRUE, GL_FALSE}, {GL_FALSE, GL_FALSE, GL_TRUE}};
        for (int c = 0; c < 3; ++c) {
            glColorMaski(0, masks[c][0], masks[c][1], masks[c][2], GL_FALSE);
            sent += raster_[c].draw(view, region_projection, style, cull).points_drawn;
        }
        glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_SCISSOR_TEST);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    if (points) *points += sent;

    const GLuint zeros[8] = {};
    glNamedBufferSubData(counts_buffer_, 0, sizeof zeros, zeros);
    const render::Program& count = rasterizer == Rasterizer::Compute ? count_mask_program_ : count_rgba_program_;
    count.use();
    glUniform2i(count.uniform("u_offset"), counted.x0 - drawn.x0, counted.y0 - drawn.y0);
    glUniform2i(count.uniform("u_size"), counted.width(), counted.height());
    if (rasterizer == Rasterizer::Compute)
        glBindImageTexture(0, mask_, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    else
        glBindImageTexture(0, rgba_, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA8);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, counts_buffer_);
    glDispatchCompute(static_cast<GLuint>((counted.width() + 15) / 16),
                      static_cast<GLuint>((counted.height() + 15) / 16), 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint c[8] = {};
    glGetNamedBufferSubData(counts_buffer_, 0, sizeof c, c);
    render::checkGl("metric: splat and count", __FILE__, __LINE__);
    ImageCounts out;
    out.i1 = c[0];
    out.i2 = c[1];
    out.i3 = c[2];
    out.i4 = c[3];
    out.visible = c[4];
    out.depth_visible = rasterizer == Rasterizer::Compute ? static_cast<std::int64_t>(c[5]) : -1;
    return out;
}

MetricPictures GpuImages::readPictures(int view, int width, int height, Rasterizer rasterizer) {
    MetricPictures pictures;
    pictures.view = view;
    pictures.width = width;
    pictures.height = height;
    const std::size_t n = static_cast<std::size_t>(width) * height;
    std::vector<std::uint32_t> bits(n);
    if (rasterizer == Rasterizer::Compute) {
        GL_CHECK(glGetTextureSubImage(mask_, 0, 0, 0, 0, width, height, 1, GL_RED_INTEGER, GL_UNSIGNED_INT,
                                      static_cast<GLsizei>(n * sizeof(std::uint32_t)), bits.data()));
    } else {
        std::vector<std::uint8_t> rgba(n * 4);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        GL_CHECK(glGetTextureSubImage(rgba_, 0, 0, 0, 0, width, height, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                                      static_cast<GLsizei>(rgba.size()), rgba.data()));
        for (std::size_t i = 0; i < n; ++i)
            bits[i] =
                (rgba[4 * i] > 127 ? 1u : 0u) | (rgba[4 * i + 1] > 127 ? 2u : 0u) | (rgba[4 * i + 2] > 127 ? 4u : 0u);
    }
    pictures.i1.resize(n);
    pictures.i2.resize(n);
    pictures.i3.resize(n);
    pictures.i4.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const bool a = bits[i] & 1u, b = bits[i] & 2u, c = bits[i] & 4u;
        pictures.i1[i] = a ? 255 : 0;
        pictures.i2[i] = b ? 255 : 0;
        pictures.i3[i] = c ? 255 : 0;
        pictures.i4[i] = (b != c) ? 255 : 0;
    }
    return pictures;
}

}  // namespace metric::detail
