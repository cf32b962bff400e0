// render/src/point_chunks.cpp: chunked, camera-relative point storage on the GPU.
#include <render/point_chunks.hpp>

#include <algorithm>

namespace render {

PointChunks::PointChunks() {
    glCreateVertexArrays(1, &vao_);
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, offsetof(GpuPoint, x));
    glVertexArrayAttribBinding(vao_, 0, 0);
    glEnableVertexArrayAttrib(vao_, 1);
    glVertexArrayAttribFormat(vao_, 1, GL_BGRA, GL_UNSIGNED_BYTE, GL_TRUE, offsetof(GpuPoint, rgb));
    glVertexArrayAttribBinding(vao_, 1, 0);
    glEnableVertexArrayAttrib(vao_, 2);
    glVertexArrayAttribFormat(vao_, 2, 1, GL_FLOAT, GL_FALSE, offsetof(GpuPoint, above_ground_m));
    glVertexArrayAttribBinding(vao_, 2, 0);
    logGl("PointChunks (vertex array)", __FILE__, __LINE__);
}

PointChunks::~PointChunks() {
    clear();
    if (vao_) glDeleteVertexArrays(1, &vao_);
}

void PointChunks::clear() {
    for (Chunk& c : chunks_)
        if (c.buffer) glDeleteBuffers(1, &c.buffer);
    chunks_.clear();
    cells_.clear();
    free_ids_.clear();
    uploaded_ = 0;
    allocated_bytes_ = 0;
    bounds_ = {};
}

std::optional<std::size_t> PointChunks::addChunk(std::size_t capacity, std::span<const CellRange> cells) {
    Chunk chunk;
    chunk.capacity = capacity;
    glCreateBuffers(1, &chunk.buffer);
    glNamedBufferStorage(chunk.buffer, static_cast<GLsizeiptr>(capacity * sizeof(GpuPoint)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    if (!logGl("glNamedBufferStorage (point chunk)", __FILE__, __LINE__)) {
        glDeleteBuffers(1, &chunk.buffer);
        return std::nullopt;
    }
    std::size_t id = chunks_.size();
    if (!free_ids_.empty()) {  // a removed chunk's slot: the table stays as long as what is held
        id = free_ids_.back();
        free_ids_.pop_back();
    }
    chunk.first_cell = chunk.next_cell = cells_.size();
    chunk.cells = cells.size();
    for (const CellRange& c : cells) {
        cells_.push_back({id, c.first, c.count, c.bounds.centre(), c.bounds});
        bounds_.extend(c.bounds);
    }
    if (id == chunks_.size())
        chunks_.push_back(chunk);
    else
        chunks_[id] = chunk;
    allocated_bytes_ += capacity * sizeof(GpuPoint);
    return id;
}

void PointChunks::upload(std::size_t id, std::span<const core::CloudPoint> points) {
    Chunk& chunk = chunks_[id];
    const std::size_t n = std::min(points.size(), chunk.capacity - chunk.count);
    if (n == 0 || chunk.buffer == 0) return;
    staging_.resize(n);
    const std::size_t end_cell = chunk.first_cell + chunk.cells;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = chunk.count + i;
        while (chunk.next_cell + 1 < end_cell && k >= cells_[chunk.next_cell].first + cells_[chunk.next_cell].size)
            ++chunk.next_cell;
        const core::CloudPoint& p = points[i];
        const glm::dvec3 rel = glm::dvec3(p.position) - cells_[chunk.next_cell].centre;
        staging_[i] = {float(rel.x), float(rel.y), float(rel.z), (p.rgb & 0xFFFFFFu) | (std::uint32_t(p.label) << 24),
                       p.height_above_ground_m};
    }
    glNamedBufferSubData(chunk.buffer, static_cast<GLintptr>(chunk.count * sizeof(GpuPoint)),
                         static_cast<GLsizeiptr>(n * sizeof(GpuPoint)), staging_.data());
    chunk.count += n;
    uploaded_ += n;
}

void PointChunks::removeChunk(std::size_t id) {
    Chunk& chunk = chunks_[id];
    if (chunk.buffer == 0) return;  // removed already
    if (chunk.buffer) glDeleteBuffers(1, &chunk.buffer);
    const auto first = cells_.begin() + static_cast<std::ptrdiff_t>(chunk.first_cell);
    cells_.erase(first, first + static_cast<std::ptrdiff_t>(chunk.cells));
    for (Chunk& c : chunks_)
        if (c.first_cell > chunk.first_cell) {
            c.first_cell -= chunk.cells;
            c.next_cell -= chunk.cells;
        }
    uploaded_ -= chunk.count;
    allocated_bytes_ -= chunk.capacity * sizeof(GpuPoint);
    chunk = Chunk{};
    chunk.first_cell = chunk.next_cell = cells_.size();  // no cells: never drawn
    free_ids_.push_back(id);
}

std::size_t PointChunks::available(std::size_t i) const {
    const Cell& c = cells_[i];
    const std::size_t up = chunks_[c.chunk].count;
    return up <= c.first ? 0 : std::min(c.size, up - c.first);
}

void PointChunks::drawCell(std::size_t i, std::size_t n, std::size_t& bound_chunk) const {
    const Cell& c = cells_[i];
    if (bound_chunk != c.chunk) {
        glVertexArrayVertexBuffer(vao_, 0, chunks_[c.chunk].buffer, 0, sizeof(GpuPoint));
        bound_chunk = c.chunk;
    }
    glDrawArrays(GL_POINTS, static_cast<GLint>(c.first), static_cast<GLsizei>(n));
}

}  // namespace render
