// render/src/point_splat.cpp: chunked, camera-relative square point splats.
#include <render/point_splat.hpp>
#include <render/orbit_camera.hpp>
#include <shaders/shaders.hpp>

#include <core/spatial_hash.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace render {
namespace {

struct GpuPoint {
    glm::vec3 position;
    std::uint32_t rgb;
};
static_assert(sizeof(GpuPoint) == 16);

constexpr std::size_t kMaxChunkPoints = 1u << 18;  // keeps culling useful in dense cells

}  // namespace

PointSplatRenderer::PointSplatRenderer()
    : program_("point-splat", {{GL_VERTEX_SHADER, shaders::point_splat_vert, shaders::point_splat_vert_files},
                               {GL_FRAGMENT_SHADER, shaders::vertex_colour_frag, shaders::vertex_colour_frag_files}}) {
    u_mvp_ = program_.uniform("u_mvp");
    u_point_size_ = program_.uniform("u_point_size");
    u_colour_ = program_.uniform("u_colour");
    u_use_point_colours_ = program_.uniform("u_use_point_colours");
    GL_CHECK(glCreateVertexArrays(1, &vao_));
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, offsetof(GpuPoint, position));
    glVertexArrayAttribBinding(vao_, 0, 0);
    glEnableVertexArrayAttrib(vao_, 1);
    GL_CHECK(glVertexArrayAttribFormat(vao_, 1, GL_BGRA, GL_UNSIGNED_BYTE, GL_TRUE, offsetof(GpuPoint, rgb)));
    glVertexArrayAttribBinding(vao_, 1, 0);
}

PointSplatRenderer::~PointSplatRenderer() {
    clear();
    if (vao_) glDeleteVertexArrays(1, &vao_);
}

void PointSplatRenderer::clear() {
    for (Chunk& c : chunks_) glDeleteBuffers(1, &c.buffer);
    chunks_.clear();
    point_count_ = 0;
    bounds_ = {};
}

void PointSplatRenderer::upload(std::span<const core::CloudPoint> points, const core::Bounds& bounds) {
    Chunk chunk;
    chunk.bounds = bounds;
    chunk.centre = bounds.centre();
    chunk.count = static_cast<GLsizei>(points.size());
    std::vector<GpuPoint> data(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        data[i].position = glm::vec3(glm::dvec3(points[i].position) - chunk.centre);
        data[i].rgb = points[i].rgb;
    }
    GL_CHECK(glCreateBuffers(1, &chunk.buffer));
    GL_CHECK(glNamedBufferStorage(chunk.buffer, static_cast<GLsizeiptr>(data.size() * sizeof(GpuPoint)),
                                  data.data(), 0));
    chunks_.push_back(chunk);
    point_count_ += points.size();
    bounds_.extend(bounds);
}

void PointSplatRenderer::appendChunk(std::span<const core::CloudPoint> points) {
    for (std::size_t start = 0; start < points.size(); start += kMaxChunkPoints) {
        const auto part = points.subspan(start, std::min(kMaxChunkPoints, points.size() - start));
        core::Bounds b;
        for (const auto& p : part) b.extend(glm::dvec3(p.position));
        upload(part, b);
    }
}

void PointSplatRenderer::setCloud(const core::PointCloud& cloud, double chunk_size_m) {
    clear();
    if (cloud.points.empty()) return;
    if (!(chunk_size_m > 0.0)) chunk_size_m = 16.0;
    // Bin into cells, then upload each cell (split if it is very dense).
    const core::CellBins cells = core::binByCell(cloud.points, chunk_size_m);
    std::vector<core::CloudPoint> buffer;
    for (std::size_t c = 0; c < cells.cells(); ++c) {
        buffer.clear();
        for (std::uint32_t i : cells.cell(c)) buffer.push_back(cloud.points[i]);
        appendChunk(buffer);
    }
}

SplatDrawStats PointSplatRenderer::draw(const glm::dmat4& view, const glm::dmat4& projection,
                                        const SplatStyle& style, bool cull) const {
    SplatDrawStats stats;
    if (chunks_.empty()) return stats;
    const glm::dmat4 view_projection = projection * view;
    const Frustum frustum = Frustum::fromMatrix(view_projection);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUseProgram(program_.id());
    glUniform1f(u_point_size_, std::max(1.0f, style.point_size_px));
    glUniform4fv(u_colour_, 1, &style.colour[0]);
    glUniform1i(u_use_point_colours_, style.use_point_colours ? 1 : 0);
    glBindVertexArray(vao_);
    for (const Chunk& c : chunks_) {
        if (cull && !frustum.intersects(c.bounds)) {
            ++stats.chunks_culled;
            continue;
        }
        // The translation to the chunk centre is folded in double precision, so the
        // float positions stay small: no jitter far from the origin.
        glm::dmat4 model(1.0);
        model[3] = glm::dvec4(c.centre, 1.0);
        const glm::mat4 mvp(view_projection * model);
        glUniformMatrix4fv(u_mvp_, 1, GL_FALSE, &mvp[0][0]);
        glVertexArrayVertexBuffer(vao_, 0, c.buffer, 0, sizeof(GpuPoint));
        glDrawArrays(GL_POINTS, 0, c.count);
        ++stats.chunks_drawn;
        stats.points_drawn += static_cast<std::size_t>(c.count);
    }
    glBindVertexArray(0);
    return stats;
}

}  // namespace render
