// The viewer's offscreen stereo pair: a red wall in front of the head shows red in the
// centre of both eye images, turned away the culled plan draws nothing, the eyes sit an
// IPD apart, and bad sizes are refused before any GL work.
#include <viewer/offscreen_stereo.hpp>

#include <core/error.hpp>
#include <render/egl_context.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <numbers>
#include <vector>

namespace {

/// A 10 x 10 m wall of red points (0.1 m apart) in the plane z = -10: straight ahead of an
/// identity head pose, whose gaze is -z.
core::PointCloud redWall() {
    core::PointCloud cloud;
    for (int j = 0; j <= 100; ++j)
        for (int i = 0; i <= 100; ++i) {
            core::CloudPoint p;
            p.position = glm::vec3(-5.0f + 0.1f * float(i), -5.0f + 0.1f * float(j), -10.0f);
            p.rgb = core::packRgb(255, 0, 0);
            cloud.points.push_back(p);
        }
    return cloud;
}

/// The RGBA of pixel (x, y) of a bottom-up image `width` pixels wide.
const std::uint8_t* pixel(const std::vector<std::uint8_t>& rgba, int width, int x, int y) {
    return &rgba[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4];
}

}  // namespace

TEST_CASE("offscreen stereo: a red wall ahead is red in the centre of both eyes, turned away nothing is drawn") {
    render::EglContext context;
    viewer::StereoOptions options;
    options.eye_width_px = options.eye_height_px = 64;
    viewer::OffscreenStereo stereo(options);
    const core::PointCloud wall = redWall();
    stereo.upload(wall);
    CHECK(stereo.uploadedPoints() == wall.points.size());
    CHECK(stereo.cellCount() > 0);
    CHECK(stereo.bounds().centre().z == doctest::Approx(-10.0));

    const viewer::RigPose ahead;
    const viewer::ViewStyle style;
    CHECK(stereo.draw(ahead, style, viewer::ViewMode::Free) > 0);
    for (int eye = 0; eye < 2; ++eye) {
        CAPTURE(eye);
        const std::vector<std::uint8_t> image = stereo.readEye(eye);
        REQUIRE(image.size() == 64u * 64u * 4u);
        const std::uint8_t* centre = pixel(image, 64, 32, 32);
        CHECK(int(centre[0]) > 120);
        CHECK(int(centre[0]) > 2 * int(centre[1]));
        CHECK(int(centre[0]) > 2 * int(centre[2]));
    }

    viewer::RigPose away;  // half a turn about x: the gaze is +z, the wall behind the head
    away.rotation = glm::dmat3(glm::rotate(glm::dmat4(1.0), std::numbers::pi, glm::dvec3(1, 0, 0)));
    stereo.plan(away, 0, true);
    CHECK(stereo.draw(away, style, viewer::ViewMode::Free) == 0);
    const std::uint8_t* centre = pixel(stereo.readEye(0), 64, 32, 32);
    CHECK(int(centre[0]) < 120);
    stereo.plan(ahead, 0, true);
    CHECK(stereo.draw(ahead, style, viewer::ViewMode::Free) > 0);
}

TEST_CASE("offscreen stereo: the eyes' views are an IPD apart along the head's x axis") {
    render::EglContext context;
    viewer::StereoOptions options;
    options.eye_width_px = options.eye_height_px = 32;
    options.ipd_m = 0.07;
    const viewer::OffscreenStereo stereo(options);
    viewer::RigPose head;
    head.position = glm::dvec3(100.0, -20.0, 5.0);
    const glm::dvec4 point(100.0, -20.0, -5.0, 1.0);  // 10 m straight ahead of the head
    const glm::dvec4 left = stereo.eyeView(head, 0) * point, right = stereo.eyeView(head, 1) * point;
    CHECK(left.x == doctest::Approx(0.035));
    CHECK(right.x == doctest::Approx(-0.035));
    CHECK(left.z == doctest::Approx(-10.0));
    CHECK(right.z == doctest::Approx(-10.0));
}

TEST_CASE("offscreen stereo options are validated with the field and range") {
    viewer::StereoOptions o;
    o.eye_width_px = 8;
    CHECK_THROWS_WITH_AS(viewer::validate(o), doctest::Contains("eye size 8x1600"), core::Error);
    o = {};
    o.ipd_m = -0.01;
    CHECK_THROWS_WITH_AS(viewer::validate(o), doctest::Contains("ipd_m"), core::Error);
    o = {};
    o.angle_left_rad = 1.0;
    CHECK_THROWS_WITH_AS(viewer::validate(o), doctest::Contains("field of view"), core::Error);
    CHECK_NOTHROW(viewer::validate(viewer::StereoOptions{}));
}
