// tests/render/point_chunks_test.cpp: the point storage both renderers draw from: a chunk
// filled in steps shows a growing prefix of each cell, positions are stored relative to
// their cell's centre (read back from the GPU buffer), and a
// removed chunk takes its points and cells with it.
#include <render/egl_context.hpp>
#include <render/point_chunks.hpp>

#include <doctest/doctest.h>

#include <vector>

namespace {

std::vector<core::CloudPoint> row(int n, float x0) {
    std::vector<core::CloudPoint> points;
    for (int i = 0; i < n; ++i) {
        core::CloudPoint p;
        p.position = glm::vec3(x0 + float(i), 0.0f, 0.0f);
        points.push_back(p);
    }
    return points;
}

core::Bounds boundsOf(const std::vector<core::CloudPoint>& points, std::size_t first, std::size_t count) {
    core::Bounds b;
    for (std::size_t i = first; i < first + count; ++i) b.extend(glm::dvec3(points[i].position));
    return b;
}

}  // namespace

TEST_CASE("chunks fill in steps, keep their cells' prefixes, and leave whole when removed") {
    render::EglContext context;
    render::PointChunks chunks;
    const auto a = row(10, 0.0f), b = row(6, 100.0f);
    // Chunk a: cells [0, 4) and [4, 10); chunk b: one cell.
    const std::vector<render::CellRange> cells_a = {{0, 4, boundsOf(a, 0, 4)}, {4, 6, boundsOf(a, 4, 6)}};
    const std::vector<render::CellRange> cells_b = {{0, 6, boundsOf(b, 0, 6)}};
    const auto id_a = chunks.addChunk(a.size(), cells_a);
    const auto id_b = chunks.addChunk(b.size(), cells_b);
    REQUIRE(id_a);
    REQUIRE(id_b);
    REQUIRE(chunks.cells().size() == 3);
    CHECK(chunks.cells()[1].centre.x == doctest::Approx(6.5));  // cell [4, 10): x 4..9
    CHECK(chunks.uploadedPoints() == 0);
    CHECK(chunks.available(0) == 0);
    // Three points, then the other seven: the first cell fills before the second starts.
    chunks.upload(*id_a, std::span(a).subspan(0, 3));
    CHECK(chunks.available(0) == 3);
    CHECK(chunks.available(1) == 0);
    chunks.upload(*id_a, std::span(a).subspan(3));
    CHECK(chunks.available(0) == 4);
    CHECK(chunks.available(1) == 6);
    chunks.upload(*id_b, b);
    CHECK(chunks.uploadedPoints() == 16);
    // More than the capacity is not written.
    chunks.upload(*id_b, b);
    CHECK(chunks.uploadedPoints() == 16);
    // The stored vertices are relative to their cell's centre.
    const GLuint buffer = chunks.buffer(*id_a);
    REQUIRE(buffer != 0);
    std::vector<render::GpuPoint> stored(10);
    glGetNamedBufferSubData(buffer, 0, GLsizeiptr(stored.size() * sizeof(render::GpuPoint)), stored.data());
    CHECK(stored[0].x == doctest::Approx(0.0 - 1.5));  // cell [0, 4): centre x 1.5
    CHECK(stored[4].x == doctest::Approx(4.0 - 6.5));  // cell [4, 10): centre x 6.5
    CHECK(stored[9].x == doctest::Approx(9.0 - 6.5));
    // Removing chunk a drops its 10 points and 2 cells; chunk b's cell stays drawable.
    chunks.removeChunk(*id_a);
    CHECK(chunks.uploadedPoints() == 6);
    REQUIRE(chunks.cells().size() == 1);
    CHECK(chunks.cells()[0].chunk == *id_b);
    CHECK(chunks.buffer(*id_a) == 0);
    CHECK(chunks.available(0) == 6);
    CHECK(chunks.bounds().hi.x == doctest::Approx(105.0));  // bounds keep everything ever added
    CHECK(glGetError() == GL_NO_ERROR);
}
