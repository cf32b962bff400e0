// render/point_chunks.hpp: the GPU storage both point renderers draw from.
//
// Points live in chunks (one GL buffer each), split into cells; a cell's points are stored
// as floats relative to the cell's centre and drawn with a model-view folded in double
// precision, so large coordinates never jitter (camera-relative rendering). A chunk can be
// filled in steps (a prefix is uploaded per call, for streaming) and removed again (a
// point source evicting a node). The metric's PointSplatRenderer and the viewer's
// PointRenderer each add their own program and their own choice of which cells to draw.
#pragma once
#include <core/point_cloud.hpp>
#include <render/gl.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace render {

/// One point as the shaders read it: location 0 position (relative to its cell's centre),
/// 1 colour 0xLLRRGGBB read as BGRA bytes (L = the ground-truth label), 2 height above ground.
struct GpuPoint {
    float x, y, z;
    std::uint32_t rgb;
    float above_ground_m;
};
static_assert(sizeof(GpuPoint) == 20);

/// A range of a chunk's points: [first, first + count), inside `bounds` (local frame).
struct CellRange {
    std::size_t first = 0, count = 0;
    core::Bounds bounds;
};

class PointChunks {
  public:
    struct Cell {
        std::size_t chunk = 0, first = 0, size = 0;
        glm::dvec3 centre{0.0};  // the cell's points are stored relative to it
        core::Bounds bounds;
    };

    /// Needs a current GL 4.5 context for its whole life.
    PointChunks();
    ~PointChunks();
    PointChunks(const PointChunks&) = delete;
    PointChunks& operator=(const PointChunks&) = delete;

    /// Allocates a chunk of `capacity` points made of `cells` (in order, covering it).
    /// Returns its id, none when the GPU has no room (logged): the caller shows what fits.
    std::optional<std::size_t> addChunk(std::size_t capacity, std::span<const CellRange> cells);
    /// Uploads `points`, the next points of chunk `chunk` after those already uploaded.
    void upload(std::size_t chunk, std::span<const core::CloudPoint> points);
    /// Frees the chunk's buffer and drops its cells; its id may be handed out again.
    void removeChunk(std::size_t chunk);
    void clear();

    const std::vector<Cell>& cells() const { return cells_; }
    /// Points of cell `i` on the GPU (a prefix of it while its chunk streams).
    std::size_t available(std::size_t i) const;
    std::size_t uploadedPoints() const { return uploaded_; }
    /// Bytes of the chunks' GL buffers now (capacity x sizeof(GpuPoint) per live chunk,
    /// allocated whole by addChunk, freed by removeChunk): what a GPU arena bound counts.
    std::size_t allocatedBytes() const { return allocated_bytes_; }
    /// Local-frame bounds of every cell ever added.
    const core::Bounds& bounds() const { return bounds_; }

    /// The GL buffer of chunk `chunk` (0 once removed).
    GLuint buffer(std::size_t chunk) const { return chunks_[chunk].buffer; }
    /// The vertex array the draws use (attributes 0-2 of GpuPoint).
    GLuint vao() const { return vao_; }
    /// Draws the first `n` points of cell `i` with the bound program; `bound_chunk` tracks
    /// which chunk's buffer is attached to the vertex array (start it at SIZE_MAX).
    void drawCell(std::size_t i, std::size_t n, std::size_t& bound_chunk) const;

  private:
    struct Chunk {
        GLuint buffer = 0;
        std::size_t capacity = 0, count = 0;  // count: uploaded so far (a prefix)
        std::size_t first_cell = 0, cells = 0;
        std::size_t next_cell = 0;  // cell of the next point to upload
    };
    GLuint vao_ = 0;
    std::vector<Chunk> chunks_;
    std::vector<Cell> cells_;
    std::vector<GpuPoint> staging_;
    std::vector<std::size_t> free_ids_;  // removed chunks' slots, reused by addChunk
    std::size_t uploaded_ = 0;
    std::size_t allocated_bytes_ = 0;
    core::Bounds bounds_;
};

}  // namespace render
