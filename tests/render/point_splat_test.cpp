// Point splats land on the pixel their position projects to, with the requested size,
// also far from the origin (camera-relative rendering), and culling skips what is off screen.
#include <render/egl_context.hpp>
#include <render/orbit_camera.hpp>
#include <render/point_splat.hpp>

#include <doctest/doctest.h>

#include <vector>

namespace {

struct Target {
    GLuint texture = 0, fbo = 0;
    int w, h;
    Target(int width, int height) : w(width), h(height) {
        glCreateTextures(GL_TEXTURE_2D, 1, &texture);
        glTextureStorage2D(texture, 1, GL_R8, w, h);
        glCreateFramebuffers(1, &fbo);
        glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, texture, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, w, h);
        glClearColor(0, 0, 0, 0);
        glClear(GL_COLOR_BUFFER_BIT);
    }
    ~Target() {
        glDeleteFramebuffers(1, &fbo);
        glDeleteTextures(1, &texture);
    }
    std::vector<unsigned char> read() const {
        std::vector<unsigned char> pixels(static_cast<std::size_t>(w * h));
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, w, h, GL_RED, GL_UNSIGNED_BYTE, pixels.data());
        return pixels;
    }
};

}  // namespace

TEST_CASE("a point far from the origin lands on its pixel with a size x size splat") {
    render::EglContext context;
    render::PointSplatRenderer splats;
    // Local frame coordinates 100 km away: floats alone would be ~4 mm apart there.
    const glm::dvec3 far_centre{1.0e5, -2.0e5, 50.0};
    render::CameraPose pose;
    pose.eye = far_centre + glm::dvec3(0.0, -30.0, 0.0);
    pose.look_at = far_centre;
    pose.up = {0.0, 0.0, 1.0};
    const int w = 64, h = 64;
    const glm::dmat4 view = render::viewMatrix(pose);
    const glm::dmat4 projection = render::projectionMatrix(30.0, 1.0, 0.1, 1000.0);
    // A point exactly on the ray through pixel (40, 20)'s centre.
    core::PointCloud cloud;
    core::CloudPoint point;
    point.position = glm::vec3(pose.eye + 30.0 * render::pixelCentreDirection(pose, 30.0, w, h, 40, 20));
    cloud.points.push_back(point);
    splats.setCloud(cloud);
    CHECK(splats.pointCount() == 1);
    for (int size : {1, 3}) {
        Target target(w, h);
        render::SplatStyle style;
        style.point_size_px = static_cast<float>(size);
        const render::SplatDrawStats stats = splats.draw(view, projection, style);
        CHECK(stats.points_drawn == 1);
        const auto pixels = target.read();
        int lit = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                if (pixels[static_cast<std::size_t>(y * w + x)] > 127) {
                    ++lit;
                    CHECK(std::abs(x - 40) <= size / 2);
                    CHECK(std::abs(y - 20) <= size / 2);
                }
        CHECK(lit == size * size);
    }
}

TEST_CASE("chunks outside the frustum are culled, those inside drawn") {
    render::EglContext context;
    render::PointSplatRenderer splats;
    core::PointCloud cloud;
    for (int i = 0; i < 100; ++i) {
        core::CloudPoint p;
        p.position = {static_cast<float>(i) * 10.0f, 0.0f, 0.0f};  // a line along +x, 1 km
        cloud.points.push_back(p);
    }
    splats.setCloud(cloud, 16.0);
    CHECK(splats.chunkCount() > 10);
    render::CameraPose pose;
    pose.eye = {0.0, -50.0, 0.0};
    pose.look_at = {0.0, 0.0, 0.0};
    pose.up = {0.0, 0.0, 1.0};
    Target target(32, 32);
    const render::SplatDrawStats culled =
        splats.draw(render::viewMatrix(pose), render::projectionMatrix(30.0, 1.0, 0.1, 1000.0), {}, true);
    const render::SplatDrawStats all =
        splats.draw(render::viewMatrix(pose), render::projectionMatrix(30.0, 1.0, 0.1, 1000.0), {}, false);
    CHECK(all.points_drawn == 100);
    CHECK(culled.points_drawn < 10);
    CHECK(culled.points_drawn >= 2);  // x = 0 and 10 m are in view (half width ~13 m)
    CHECK(culled.chunks_culled > 0);
}
