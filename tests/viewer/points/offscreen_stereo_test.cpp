// tests/viewer/points/offscreen_stereo_test.cpp: the viewer's offscreen stereo pair: a red
// wall in front of the head shows red in the centre of both eye images, turned away the
// culled plan draws nothing, the eyes sit an IPD apart, the compute rasterizer draws the
// picture GL_POINTS draws, and bad sizes are refused before any GL work.
#include <viewer/offscreen_stereo.hpp>

#include <core/error.hpp>
#include <render/egl_context.hpp>

#include <doctest/doctest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <numbers>
#include <random>
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

TEST_CASE("offscreen stereo: the compute rasterizer draws the picture GL_POINTS draws") {
    render::EglContext context;
    viewer::StereoOptions options;
    options.eye_width_px = 160;
    options.eye_height_px = 128;
    viewer::OffscreenStereo stereo(options);
    // Two clouds (two chunks, many cells each) in the same box ahead of the head: points of
    // many colours at many depths, so the nearest point decides most pixels, twice over.
    std::mt19937 random(7);
    std::uniform_real_distribution<float> across(-12.0f, 12.0f), deep(-40.0f, -8.0f);
    for (int cloud_index = 0; cloud_index < 2; ++cloud_index) {
        core::PointCloud cloud;
        for (int k = 0; k < 60000; ++k) {
            core::CloudPoint p;
            p.position = glm::vec3(across(random), across(random), deep(random));
            p.rgb = random() & 0xFFFFFFu;
            p.label = static_cast<core::Role>(random() % 3);
            p.height_above_ground_m = float(random() % 100) * 0.1f;
            cloud.points.push_back(p);
        }
        stereo.upload(cloud);
    }
    REQUIRE(stereo.cellCount() > 2);
    viewer::RigPose head;
    head.position = glm::dvec3(1.0, -0.5, 0.0);
    for (const bool attenuate : {false, true}) {
        for (const viewer::ColourMode colour : {viewer::ColourMode::File, viewer::ColourMode::HeightJet}) {
            CAPTURE(attenuate);
            CAPTURE(viewer::colourModeName(colour));
            viewer::ViewStyle style;
            style.colour = colour;
            style.attenuate = attenuate;
            style.point_size_px = attenuate ? 40.0f : 3.0f;  // attenuated: 1.3-5 px here
            std::vector<std::uint8_t> images[2][2];
            std::size_t drawn[2] = {};
            for (int r = 0; r < 2; ++r) {
                style.rasterizer = r == 0 ? viewer::Rasterizer::Points : viewer::Rasterizer::Compute;
                drawn[r] = stereo.draw(head, style, viewer::ViewMode::Free);
                for (int eye = 0; eye < 2; ++eye) images[r][eye] = stereo.readEye(eye);
            }
            CHECK(drawn[0] > 100000);
            CHECK(drawn[1] == drawn[0]);
            for (int eye = 0; eye < 2; ++eye) {
                CAPTURE(eye);
                const auto& a = images[0][eye];
                const auto& b = images[1][eye];
                REQUIRE(a.size() == b.size());
                std::size_t same = 0, close = 0, lit = 0;  // pixels
                const std::size_t pixels = a.size() / 4;
                for (std::size_t i = 0; i < pixels; ++i) {
                    int most = 0;
                    for (int c = 0; c < 4; ++c) most = std::max(most, std::abs(int(a[4 * i + c]) - int(b[4 * i + c])));
                    same += most == 0;
                    close += most <= 2;
                    lit += b[4 * i] + b[4 * i + 1] + b[4 * i + 2] > 90;  // brighter than the background
                }
                // Equal but where two points lie within the depth buffer's step of each other
                // (about 1 mm at 40 m here: GL keeps the first drawn, compute the smaller
                // colour), and where eye-dome lighting sees depths that differ in the last bit.
                CHECK(double(close) / double(pixels) > 0.995);
                CHECK(double(same) / double(pixels) > 0.99);
                CHECK(double(lit) / double(pixels) > 0.3);
            }
        }
    }
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
