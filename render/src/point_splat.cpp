// render/src/point_splat.cpp: chunked, camera-relative square point splats.
#include <render/point_splat.hpp>
#include <render/orbit_camera.hpp>
#include <shaders/shaders.hpp>

#include <core/error.hpp>
#include <core/spatial_hash.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace render {
namespace {

constexpr std::size_t kMaxChunkPoints = 1u << 18;  // keeps culling useful in dense cells

}  // namespace

PointSplatRenderer::PointSplatRenderer()
    : program_("point-splat", {{GL_VERTEX_SHADER, shaders::point_splat_vert, shaders::point_splat_vert_files},
                               {GL_FRAGMENT_SHADER, shaders::vertex_colour_frag, shaders::vertex_colour_frag_files}}) {
    u_mvp_ = program_.uniform("u_mvp");
    u_point_size_ = program_.uniform("u_point_size");
    u_colour_ = program_.uniform("u_colour");
    u_use_point_colours_ = program_.uniform("u_use_point_colours");
}

PointSplatRenderer::~PointSplatRenderer() = default;

void PointSplatRenderer::clear() { chunks_.clear(); }

void PointSplatRenderer::appendChunk(std::span<const core::CloudPoint> points) {
    for (std::size_t start = 0; start < points.size(); start += kMaxChunkPoints) {
        const auto part = points.subspan(start, std::min(kMaxChunkPoints, points.size() - start));
        CellRange cell{0, part.size(), {}};
        for (const auto& p : part) cell.bounds.extend(glm::dvec3(p.position));
        const auto id = chunks_.addChunk(part.size(), std::span<const CellRange>(&cell, 1));
        if (!id) throw core::Error("gl: no GPU memory for a chunk of " + std::to_string(part.size()) + " points");
        chunks_.upload(*id, part);
        checkGl("PointChunks::upload", __FILE__, __LINE__);
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

SplatDrawStats PointSplatRenderer::draw(const glm::dmat4& view, const glm::dmat4& projection, const SplatStyle& style,
                                        bool cull) const {
    SplatDrawStats stats;
    const auto& cells = chunks_.cells();
    if (cells.empty()) return stats;
    const glm::dmat4 view_projection = projection * view;
    const Frustum frustum = Frustum::fromMatrix(view_projection);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glUseProgram(program_.id());
    glUniform1f(u_point_size_, std::max(1.0f, style.point_size_px));
    glUniform4fv(u_colour_, 1, &style.colour[0]);
    glUniform1i(u_use_point_colours_, style.use_point_colours ? 1 : 0);
    glBindVertexArray(chunks_.vao());
    std::size_t bound = SIZE_MAX;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const PointChunks::Cell& c = cells[i];
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
        const std::size_t n = chunks_.available(i);
        chunks_.drawCell(i, n, bound);
        ++stats.chunks_drawn;
        stats.points_drawn += n;
    }
    glBindVertexArray(0);
    return stats;
}

}  // namespace render
