// viewer/src/point_renderer.hpp: the viewer's point drawing: streamed GPU chunks,
// camera-relative positions, file / height-jet / white colours, pixel or distance-attenuated
// point size, eye-dome lighting, and the mode indicator drawn into every eye view.
#pragma once
#include <viewer/camera_rig.hpp>
#include <viewer/cloud_feed.hpp>
#include <viewer/viewer.hpp>

#include <engine/frames.hpp>
#include <render/gl.hpp>
#include <render/shader.hpp>

#include <cstddef>
#include <deque>
#include <vector>

namespace viewer {

/// An offscreen colour (RGBA8) + depth (32F) target for one eye or the desktop view.
struct EyeTarget {
    GLuint fbo = 0, colour = 0, depth = 0;
    int width = 0, height = 0;
    /// (Re)allocates at this size if needed. Returns false on a GL error (logged).
    bool ensure(int w, int h);
    void destroy();
};

/// Per-draw parameters for one eye.
struct EyeDraw {
    glm::dmat4 view{1.0};        // world(local)-to-eye, double
    glm::dmat4 projection{1.0};
    double near_m = 0.1, far_m = 20000.0;
};

struct DrawStats {
    std::size_t points_drawn = 0;
    std::size_t chunks_drawn = 0;
};

class PointRenderer {
public:
    /// Compiles the programs; throws engine::Error("shader: ...") (setup path).
    PointRenderer();
    ~PointRenderer();
    PointRenderer(const PointRenderer&) = delete;
    PointRenderer& operator=(const PointRenderer&) = delete;

    /// Takes what the feed delivered and uploads at most `budget_points` points this frame.
    /// Returns the number uploaded. Never throws.
    std::size_t stream(CloudFeed& feed, std::size_t budget_points);
    /// Points on the GPU / waiting in CPU memory.
    std::size_t uploadedPoints() const { return uploaded_; }
    std::size_t pendingPoints() const { return pending_points_; }
    /// Bounds (local frame) of everything received so far, and heights for the jet colours.
    const engine::Bounds& bounds() const { return bounds_; }

    /// Draws the cloud into `target` (cleared), then resolves it with eye-dome lighting (if
    /// on) into the framebuffer `out_fbo` at viewport (x, y, w, h), then the mode indicator.
    DrawStats drawEye(const EyeTarget& target, const EyeDraw& eye, const ViewStyle& style,
                      ViewMode mode, GLuint out_fbo, int x, int y, int w, int h) const;

private:
    struct Chunk {
        GLuint buffer = 0;
        std::size_t capacity = 0, count = 0;
        glm::dvec3 centre{0.0};
        engine::Bounds bounds;
    };
    struct Pending {
        std::vector<engine::CloudPoint> points;
        std::size_t next = 0;     // first point not uploaded yet
        std::size_t chunk = 0;    // index into chunks_
    };

    render::Program points_, resolve_, indicator_;
    GLuint vao_ = 0, empty_vao_ = 0;
    std::vector<Chunk> chunks_;
    std::deque<Pending> pending_;
    std::size_t pending_points_ = 0, uploaded_ = 0;
    engine::Bounds bounds_;
    bool origin_known_ = false;
};

}  // namespace viewer
