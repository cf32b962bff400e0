// tests/viewer/points/focus_lod_test.cpp: what the operator works on is never coarse. A
// ground of grey points with a red target block at its centre, written as COPC in small
// nodes, is viewed through the viewer's renderer (offscreen stereo, EGL) under a point
// budget far below the cloud. With the block designated (the focus around it), the block's
// red pixels are at least 0.9 of those of the same view of the cloud held whole in core;
// without the focus the same budget leaves it coarse (the test's own check that the
// budget bites). The source is polled until its choice is all on the GPU (its event), no
// timing.
#include <viewer/copc_source.hpp>
#include <viewer/lod.hpp>
#include <viewer/offscreen_stereo.hpp>

#include "test_files.hpp"

#include <io/copc_writer.hpp>
#include <render/egl_context.hpp>

#include <doctest/doctest.h>

#include <cstdint>
#include <thread>
#include <vector>

using namespace viewer;

namespace {

constexpr double kBlockX_m = 4.0, kBlockY_m = 2.0, kBlockZ_m = 3.0;  // half sizes: an 8 x 4 x 3 m block

/// A 160 x 160 m ground (0.25 m apart, grey, label ground) and an 8 x 4 x 3 m block's top
/// and sides (0.05 m apart, red, label target) centred on the origin.
core::PointCloud groundAndBlock() {
    core::PointCloud cloud;
    cloud.origin = glm::dvec3(1.0e6, 2.0e6, 50.0);
    for (int j = 0; j < 640; ++j)
        for (int i = 0; i < 640; ++i) {
            core::CloudPoint p;
            p.position = glm::vec3(-80.0f + 0.25f * float(i), -80.0f + 0.25f * float(j), 0.0f);
            p.rgb = core::packRgb(120, 120, 120);
            p.label = core::Role::Ground;
            cloud.points.push_back(p);
        }
    const auto add = [&](float x, float y, float z) {
        core::CloudPoint p;
        p.position = glm::vec3(x, y, z);
        p.rgb = core::packRgb(255, 0, 0);
        p.label = core::Role::Target;
        cloud.points.push_back(p);
    };
    const float step = 0.05f;
    for (float x = -kBlockX_m; x <= kBlockX_m; x += step)
        for (float y = -kBlockY_m; y <= kBlockY_m; y += step) add(x, y, float(kBlockZ_m));
    for (float z = 0.0f; z <= kBlockZ_m; z += step) {
        for (float x = -kBlockX_m; x <= kBlockX_m; x += step) {
            add(x, float(-kBlockY_m), z);
            add(x, float(kBlockY_m), z);
        }
        for (float y = -kBlockY_m; y <= kBlockY_m; y += step) {
            add(float(-kBlockX_m), y, z);
            add(float(kBlockX_m), y, z);
        }
    }
    return cloud;
}

/// Red pixels of both eyes (the block; the ground is grey and the background dark).
std::size_t redPixels(const OffscreenStereo& stereo) {
    std::size_t n = 0;
    for (int eye = 0; eye < 2; ++eye) {
        const std::vector<std::uint8_t> rgba = stereo.readEye(eye);
        for (std::size_t i = 0; i + 3 < rgba.size(); i += 4)
            if (rgba[i] > 100 && rgba[i + 1] < 60 && rgba[i + 2] < 60) ++n;
    }
    return n;
}

/// A head 15 m above the ground, 12 m above the block, looking straight down (the identity pose gazes -z).
RigPose above() {
    RigPose head;
    head.position = glm::dvec3(2.0, 1.0, 15.0);
    return head;
}

/// Points of one pixel: each point shows as itself, so a coarse level shows as gaps.
ViewStyle style() {
    ViewStyle s;
    s.point_size_px = 1.0f;
    return s;
}

StereoOptions eyes() {
    StereoOptions o;
    o.eye_width_px = o.eye_height_px = 320;
    return o;
}

/// Plans and streams as the frame loop does until the source's choice for this view is
/// all on the GPU (every wanted node resident, no page left, nothing pending), then
/// draws; returns the red pixels.
std::size_t viewCopc(const std::filesystem::path& file, const glm::dvec3& cloud_origin, std::size_t budget,
                     LodFocus focus) {
    CopcSourceOptions o;
    o.workers = 1;
    o.quiet = true;
    CopcSource source(file, o);
    OffscreenStereo stereo(eyes());
    stereo.follow(source);
    // The file's local frame has its own origin (the header's offsets): the same world
    // places as the cloud's.
    const glm::dvec3 shift = cloud_origin - source.origin();
    for (FocusSphere& f : focus.spheres) f.centre_local += shift;
    stereo.setFocus(focus);
    RigPose head = above();
    head.position += shift;
    bool settled = false;
    for (long round = 0; round < 10000000 && !settled; ++round) {
        stereo.plan(head, budget, true);
        stereo.stream(1u << 20);
        bool all = !source.wanted().empty();
        for (const PointNode* n : source.wanted()) all = all && (n->resident() || n->pointCount() == 0);
        settled = all && source.finished() && source.pagesWanted() == 0 && stereo.pendingPoints() == 0;
        if (!settled) std::this_thread::yield();
    }
    REQUIRE(settled);
    stereo.plan(head, budget, true);
    stereo.draw(head, style(), ViewMode::Free);
    return redPixels(stereo);
}

}  // namespace

TEST_CASE("focus level of detail: a designated target under a low budget is drawn as in core") {
    render::EglContext context;
    test_support::TempDir dir("focus_lod");
    const core::PointCloud cloud = groundAndBlock();
    const std::filesystem::path file = dir.path / "block.copc.laz";
    io::CopcOptions copc;
    copc.max_node_points = 4000;  // several levels: the block's leaves lie deep
    io::writeCopc(file, cloud, {}, copc);

    // In core, every point: the reference.
    std::size_t reference = 0;
    {
        OffscreenStereo stereo(eyes());
        stereo.upload(cloud);
        stereo.plan(above(), 0, true);
        stereo.draw(above(), style(), ViewMode::Free);
        reference = redPixels(stereo);
    }
    REQUIRE(reference > 2000);

    const std::size_t budget = 20000;  // a twentieth of the cloud
    LodFocus designation;
    designation.spheres.push_back({glm::dvec3(0.0, 0.0, kBlockZ_m / 2), kDesignationFocusRadius_m});
    const std::size_t coarse = viewCopc(file, cloud.origin, budget, {});
    const std::size_t focused = viewCopc(file, cloud.origin, budget, designation);
    CAPTURE(reference);
    CAPTURE(coarse);
    CAPTURE(focused);
    CHECK(double(coarse) < 0.9 * double(reference));  // the budget alone leaves the block coarse
    CHECK(double(focused) >= 0.9 * double(reference));
}
