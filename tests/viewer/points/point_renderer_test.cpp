// tests/viewer/points/point_renderer_test.cpp: the viewer's height colours: points of known
// heights drawn headless (EGL) with the "height" colour mode read back as exactly the
// generator's jet colours, core::jetTable entry core::jetIndex (the table sim writes into
// the files), for 64 entries and for 16; the colour, size and cutting-volume checks run
// with both rasterizers (GL_POINTS and compute); the compute rasterizer's subgroup
// reduction leaves its image and depth as they are without it.
#include "points/point_renderer.hpp"

#include <viewer/cloud_feed.hpp>
#include <viewer/cloud_feed_source.hpp>

#include <core/jet.hpp>
#include <core/point_cloud.hpp>
#include <render/egl_context.hpp>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr int kColumns = 12;  // points on a grid of 1 m cells, seen from straight above
constexpr int kPixelsPerMetre = 8;
constexpr int kIndicatorRows = 8;

struct Pixel {
    std::uint8_t r, g, b, a;
};

// A renderer with the whole of `cloud` on the GPU (the feed and source it follows kept).
struct Uploaded {
    viewer::PointRenderer renderer;
    viewer::CloudFeed feed;
    std::unique_ptr<viewer::CloudFeedSource> source;
    explicit Uploaded(const core::PointCloud& cloud) {
        feed.feedCloud(cloud);
        source = std::make_unique<viewer::CloudFeedSource>(feed);
        source->poll();
        renderer.stream(*source, cloud.points.size());
        REQUIRE(renderer.uploadedPoints() == cloud.points.size());
    }
};

// Draws `cloud` from straight above with an orthographic camera (1 m = 8 px, grid cell
// (i, j) centred on pixel (8i + 4, 8j + 4)) and returns the resolved image (the points'
// colours where the style has eye-dome lighting off).
std::vector<Pixel> drawFromAbove(const core::PointCloud& cloud, int rows, const viewer::ViewStyle& style,
                                 const viewer::CutVolume& cut = {}) {
    Uploaded uploaded(cloud);
    viewer::PointRenderer& renderer = uploaded.renderer;
    // Empty rows above the grid keep the mode indicator (drawn near the top) off it.
    const int width = kColumns * kPixelsPerMetre, height = (rows + kIndicatorRows) * kPixelsPerMetre;
    viewer::EyeTarget target, out;
    REQUIRE(target.ensure(width, height));
    REQUIRE(out.ensure(width, height));
    viewer::EyeDraw eye;
    eye.view = glm::lookAt(glm::dvec3(0.0, 0.0, 1000.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
    eye.projection = glm::ortho(-0.5, kColumns - 0.5, -0.5, rows + kIndicatorRows - 0.5, 1.0, 2000.0);
    eye.near_m = 1.0;
    eye.far_m = 2000.0;
    renderer.drawEye(target, eye, style, viewer::ViewMode::Free, out.fbo, 0, 0, width, height, cut);
    std::vector<Pixel> pixels(static_cast<std::size_t>(width) * height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(out.colour, 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(pixels.size() * 4), pixels.data());
    REQUIRE(glGetError() == GL_NO_ERROR);
    target.destroy();
    out.destroy();
    return pixels;
}

// One point per jet entry at the middle of its height bin over [z_min, z_max], plus one
// point at each end of the range (which sets the range the viewer colours over).
void checkHeightColours(int entries, viewer::Rasterizer rasterizer) {
    const double z_min = -3.75, z_max = 21.25;
    std::vector<double> heights = {z_min, z_max};
    for (int bin = 0; bin < entries; ++bin) heights.push_back(z_min + (bin + 0.5) * (z_max - z_min) / entries);
    const int rows = (static_cast<int>(heights.size()) + kColumns - 1) / kColumns;
    core::PointCloud cloud;
    for (std::size_t k = 0; k < heights.size(); ++k) {
        core::CloudPoint p;
        p.position = {float(k % kColumns), float(k / kColumns), float(heights[k])};
        p.rgb = 0x808080u;  // the file's colour, which the height mode must not show
        cloud.points.push_back(p);
    }
    viewer::ViewStyle style;
    style.colour = viewer::ColourMode::HeightJet;
    style.eye_dome = false;
    style.point_size_px = 5.0f;
    style.jet_entries = entries;
    style.rasterizer = rasterizer;
    const std::vector<Pixel> pixels = drawFromAbove(cloud, rows, style);

    const std::vector<std::uint32_t> jet = core::jetTable(entries);
    for (std::size_t k = 0; k < heights.size(); ++k) {
        const int x = int(k % kColumns) * kPixelsPerMetre + 4, y = int(k / kColumns) * kPixelsPerMetre + 4;
        const Pixel got = pixels[static_cast<std::size_t>(y) * kColumns * kPixelsPerMetre + x];
        const std::uint32_t want = jet[core::jetIndex(heights[k], z_min, z_max, entries)];
        CAPTURE(entries);
        CAPTURE(heights[k]);
        CHECK(core::packRgb(got.r, got.g, got.b) == want);
    }
    // The ends of the range are the table's ends: red at the bottom, blue at the top.
    CHECK(core::jetIndex(z_min, z_min, z_max, entries) == entries - 1);
    CHECK(core::jetIndex(z_max, z_min, z_max, entries) == 0);
}

// Points at the same height z on a sloped stand-in, each with a known height above
// ground: the above-ground mode must colour by that height (jet over [0, the highest]),
// not by z, and leave the file's white (whitened ground) white.
void checkAboveGroundColours(viewer::Rasterizer rasterizer) {
    constexpr int entries = 64;
    const float top_m = 12.8f;
    std::vector<float> above = {0.0f, top_m};
    for (int bin = 0; bin < entries; bin += 3) above.push_back((float(bin) + 0.5f) * top_m / entries);
    const std::size_t white_points = 4;
    const std::size_t total = above.size() + white_points;
    const int rows = (static_cast<int>(total) + kColumns - 1) / kColumns;
    core::PointCloud cloud;
    cloud.fields.height_above_ground = true;
    for (std::size_t k = 0; k < total; ++k) {
        core::CloudPoint p;
        // z varies against the height above ground, so colouring by z would give other entries.
        p.position = {float(k % kColumns), float(k / kColumns), 50.0f - float(k)};
        const bool white = k >= above.size();
        p.rgb = white ? core::kWhite : 0x808080u;
        p.height_above_ground_m = white ? 7.0f : above[k];
        cloud.points.push_back(p);
    }
    viewer::ViewStyle style;
    style.colour = viewer::ColourMode::AboveGround;
    style.eye_dome = false;
    style.point_size_px = 5.0f;
    style.jet_entries = entries;
    style.rasterizer = rasterizer;
    const std::vector<Pixel> pixels = drawFromAbove(cloud, rows, style);
    const std::vector<std::uint32_t> jet = core::jetTable(entries);
    for (std::size_t k = 0; k < total; ++k) {
        const int x = int(k % kColumns) * kPixelsPerMetre + 4, y = int(k / kColumns) * kPixelsPerMetre + 4;
        const Pixel got = pixels[static_cast<std::size_t>(y) * kColumns * kPixelsPerMetre + x];
        const std::uint32_t want =
            k >= above.size() ? core::kWhite : jet[core::jetIndex(above[k], 0.0, top_m, entries)];
        CAPTURE(k);
        CHECK(core::packRgb(got.r, got.g, got.b) == want);
    }
    // Nearest the ground is red, as the lowest heights are in the height mode.
    CHECK(core::jetIndex(0.0, 0.0, top_m, entries) == entries - 1);
}

constexpr viewer::Rasterizer kRasterizers[] = {viewer::Rasterizer::Points, viewer::Rasterizer::Compute};

}  // namespace

TEST_CASE("viewer above-ground colours: the jet by height above the terrain, whitened ground white") {
    render::EglContext context;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        checkAboveGroundColours(r);
    }
}

TEST_CASE("viewer height colours are the generator's jet table, entry for entry (64 entries)") {
    render::EglContext context;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        checkHeightColours(64, r);
    }
}

TEST_CASE("viewer height colours follow the table size (16 entries)") {
    render::EglContext context;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        checkHeightColours(16, r);
    }
}

TEST_CASE("viewer file colours pass through byte-exact, with either rasterizer") {
    render::EglContext context;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        core::PointCloud cloud;
        const std::uint32_t colours[3] = {0x00FF0000u, 0x0012AB7Fu, 0x00010203u};
        for (int k = 0; k < 3; ++k) {
            core::CloudPoint p;
            p.position = {float(k), 0.0f, float(k)};
            p.rgb = colours[k];
            cloud.points.push_back(p);
        }
        viewer::ViewStyle style;
        style.eye_dome = false;
        style.point_size_px = 5.0f;
        style.rasterizer = r;
        const std::vector<Pixel> pixels = drawFromAbove(cloud, 1, style);
        for (int k = 0; k < 3; ++k) {
            const Pixel got =
                pixels[static_cast<std::size_t>(4) * kColumns * kPixelsPerMetre + k * kPixelsPerMetre + 4];
            CHECK(core::packRgb(got.r, got.g, got.b) == colours[k]);
        }
    }
}

TEST_CASE("the compute rasterizer leaves the depth GL_POINTS leaves, for the OpenXR depth layer") {
    render::EglContext context;
    // Points at many heights on the grid, seen from above: each pixel's depth is its point's.
    core::PointCloud cloud;
    for (int k = 0; k < kColumns * 3; ++k) {
        core::CloudPoint p;
        p.position = {float(k % kColumns), float(k / kColumns), float((k * 7) % 23) - 11.0f};
        cloud.points.push_back(p);
    }
    const int width = 192, height = 96;
    std::vector<float> depths[2];
    for (int r = 0; r < 2; ++r) {
        Uploaded uploaded(cloud);
        const viewer::PointRenderer& renderer = uploaded.renderer;
        viewer::EyeTarget target, out;
        REQUIRE(target.ensure(width, height));
        REQUIRE(out.ensure(width, height));
        viewer::EyeDraw eye;
        eye.projection = glm::perspective(glm::radians(40.0), double(width) / height, 1.0, 2000.0);
        eye.view = glm::lookAt(glm::dvec3(5.5, 1.0, 30.0), glm::dvec3(5.5, 1.0, 0.0), glm::dvec3(0.0, 1.0, 0.0));
        eye.near_m = 1.0;
        eye.far_m = 2000.0;
        viewer::ViewStyle style;
        style.point_size_px = 3.0f;
        style.rasterizer = kRasterizers[r];
        renderer.drawEye(target, eye, style, viewer::ViewMode::Free, out.fbo, 0, 0, width, height);
        renderer.depthInto(target);
        depths[r].resize(std::size_t(width) * height);
        glGetTextureImage(target.depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(depths[r].size() * sizeof(float)),
                          depths[r].data());
        REQUIRE(glGetError() == GL_NO_ERROR);
        target.destroy();
        out.destroy();
    }
    std::size_t points = 0, empty = 0, differ = 0;
    for (std::size_t i = 0; i < depths[0].size(); ++i) {
        points += depths[0][i] < 1.0f;
        empty += depths[0][i] == 1.0f;
        differ += std::abs(depths[0][i] - depths[1][i]) > 1e-6f;
    }
    CHECK(points > std::size_t(kColumns * 3 * 4));  // every point covers pixels
    CHECK(empty > points);
    CHECK(differ == 0);
}

TEST_CASE("the cutting volume hides the points beyond its radius, in 3D, with either rasterizer") {
    render::EglContext context;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        // A row of 12 points 1 m apart at z = 0, and a second row 2.5 m up at y = 1. The cut
        // centre reaches the shader relative to each cell's centre, like the points.
        core::PointCloud cloud;
        cloud.origin = glm::dvec3(1.0e6, -2.0e6, 300.0);
        for (int k = 0; k < kColumns; ++k)
            for (int row = 0; row < 2; ++row) {
                core::CloudPoint p;
                p.position = {float(k), float(row), row == 0 ? 0.0f : 2.5f};
                p.rgb = 0x00FFFFFFu;
                cloud.points.push_back(p);
            }
        viewer::ViewStyle style;
        style.eye_dome = false;
        style.point_size_px = 5.0f;
        style.rasterizer = r;
        viewer::CutVolume cut;
        cut.enabled = true;
        cut.centre_local = glm::dvec3(5.0, 0.0, 0.0);
        cut.radius_m = 2.2;
        const std::vector<Pixel> pixels = drawFromAbove(cloud, 2, style, cut);
        auto lit = [&](int k, int row) {
            const Pixel p = pixels[static_cast<std::size_t>(row * kPixelsPerMetre + 4) * kColumns * kPixelsPerMetre +
                                   k * kPixelsPerMetre + 4];
            return p.r > 200;
        };
        for (int k = 0; k < kColumns; ++k) {
            CAPTURE(k);
            // Row 0: within 2.2 m of x = 5 are x = 3..7.
            CHECK(lit(k, 0) == (k >= 3 && k <= 7));
            // Row 1 is 1 m across and 2.5 m up: sqrt(dx^2 + 1 + 6.25) <= 2.2 holds for none.
            CHECK_FALSE(lit(k, 1));
        }
        // Without the cut, every point is drawn.
        const std::vector<Pixel> all = drawFromAbove(cloud, 2, style);
        for (int k = 0; k < kColumns; ++k)
            CHECK(all[static_cast<std::size_t>(kPixelsPerMetre + 4) * kColumns * kPixelsPerMetre + k * kPixelsPerMetre +
                      4]
                      .r > 200);
    }
}

namespace {

// A resident node of `count` points on a line, as a source that chooses its nodes holds it.
class ArenaNode final : public viewer::PointNode {
  public:
    explicit ArenaNode(std::size_t count, float x) {
        auto p = std::make_shared<viewer::NodePoints>();
        for (std::size_t i = 0; i < count; ++i) {
            core::CloudPoint c;
            c.position = {x, float(i) * 0.01f, 0.0f};
            p->points.push_back(c);
        }
        p->cells = viewer::buildLodOrder(p->points);
        points_ = p;
        bounds_.lo = glm::dvec3(x, 0.0, 0.0);
        bounds_.hi = glm::dvec3(x + 1.0, double(count) * 0.01, 1.0);
    }
    const core::Bounds& bounds() const override { return bounds_; }
    std::size_t pointCount() const override { return points_ ? points_->points.size() : 0; }
    std::span<viewer::PointNode* const> children() const override { return {}; }
    void request() override {}
    void evict() override { points_.reset(); }
    std::shared_ptr<const viewer::NodePoints> points() const override { return points_; }
    core::Bounds bounds_;
    std::shared_ptr<const viewer::NodePoints> points_;
};

// A source that chooses: its wanted list is what the test sets.
class ArenaSource final : public viewer::PointSource {
  public:
    std::size_t poll() override { return 0; }
    std::span<viewer::PointNode* const> roots() const override { return roots_; }
    glm::dvec3 origin() const override { return glm::dvec3(0.0); }
    core::CloudFields fields() const override { return {}; }
    bool finished() const override { return true; }
    std::string error() const override { return {}; }
    std::size_t pointsArrived() const override { return 0; }
    std::optional<viewer::SourceStats> stats() const override { return viewer::SourceStats{}; }
    std::span<viewer::PointNode* const> wanted() const override { return wanted_; }
    std::vector<viewer::PointNode*> roots_, wanted_;
};

}  // namespace

TEST_CASE("the GPU arena keeps within its bound, uploads the most important first, evicts the least recently used") {
    render::EglContext context;
    constexpr std::size_t kBytes = sizeof(render::GpuPoint);
    ArenaNode a(100, 0.0f), b(200, 2.0f), c(300, 4.0f), d(400, 6.0f);
    ArenaSource source;
    source.roots_ = {&a, &b, &c, &d};
    {  // Uploads follow the wanted order: with 300 points per frame, C (wanted first) comes whole.
        viewer::PointRenderer renderer;
        source.wanted_ = {&c, &a};
        CHECK(renderer.stream(source, 300) == 300);
        const auto kept = c.points_;
        c.evict();  // C leaves RAM, so it leaves the GPU: nothing of A was uploaded yet
        CHECK(renderer.stream(source, 0) == 0);
        CHECK(renderer.uploadedPoints() == 0);
        CHECK(renderer.pendingPoints() == 100);
        c.points_ = kept;
    }
    viewer::PointRenderer renderer;
    const std::size_t bound = 650 * kBytes;
    renderer.setGpuBytes(bound);
    source.wanted_ = {&a, &b, &c, &d};
    renderer.stream(source, 100000);
    // A, B, C fit (600 points); D does not and waits.
    CHECK(renderer.arena().bytes == 600 * kBytes);
    CHECK(renderer.arena().nodes == 3);
    CHECK(renderer.arena().nodes_refused == 1);
    CHECK(renderer.uploadedPoints() == 600);
    // D wanted with A: the unwanted B and C leave, least recently used first (a tie: the
    // earlier chunk), until D fits: both must go (100 + 400 + 300 > 650).
    source.wanted_ = {&d, &a};
    renderer.stream(source, 100000);
    CHECK(renderer.arena().bytes == 500 * kBytes);
    CHECK(renderer.arena().frame_nodes_evicted == 2);
    CHECK(renderer.arena().frame_nodes_added == 1);
    CHECK(renderer.uploadedPoints() == 500);
    // A frame that wants nothing but draws A (only A in view): A was used more recently
    // than D. Then B is wanted again and comes back from RAM; of the unwanted A and D, D
    // (least recently used, though the later chunk) leaves for it: 100 + 200 fits.
    source.wanted_ = {};
    renderer.stream(source, 100000);
    viewer::EyeDraw eye;
    eye.view = glm::lookAt(glm::dvec3(0.5, 0.5, 10.0), glm::dvec3(0.5, 0.5, 0.0), glm::dvec3(0.0, 1.0, 0.0));
    eye.projection = glm::perspective(glm::radians(10.0), 1.0, 1.0, 1000.0);
    renderer.planFrame(std::span<const viewer::EyeDraw>(&eye, 1), 0);
    CHECK(renderer.plannedPoints() == 100);
    source.wanted_ = {&b};
    renderer.stream(source, 100000);
    CHECK(renderer.arena().bytes == 300 * kBytes);
    CHECK(renderer.uploadedPoints() == 300);
    CHECK(renderer.arena().nodes_evicted == 3);
    CHECK(renderer.arena().nodes_added == 5);
    // Whatever is wanted, the bound holds.
    std::vector<viewer::PointNode*> all = {&a, &b, &c, &d};
    for (int round = 0; round < 24; ++round) {
        source.wanted_.clear();
        for (int k = 0; k < 4; ++k)
            if ((round * 7 + k * 3) % 5 < 2) source.wanted_.push_back(all[std::size_t(k)]);
        std::reverse(source.wanted_.begin(), source.wanted_.end());
        renderer.stream(source, 150);
        CHECK(renderer.arena().bytes <= bound);
        CHECK(renderer.arena().bytes_peak <= bound);
    }
}

TEST_CASE("the point budget set on the renderer replaces the one planFrame is handed") {
    render::EglContext context;
    ArenaNode a(5000, 0.0f);
    ArenaSource source;
    source.roots_ = source.wanted_ = {&a};
    viewer::PointRenderer renderer;
    renderer.stream(source, 100000);
    viewer::EyeDraw eye;
    eye.view = glm::lookAt(glm::dvec3(0.5, 25.0, 100.0), glm::dvec3(0.5, 25.0, 0.0), glm::dvec3(0.0, 1.0, 0.0));
    eye.projection = glm::perspective(glm::radians(60.0), 1.0, 1.0, 1000.0);
    renderer.planFrame(std::span<const viewer::EyeDraw>(&eye, 1), 3000);
    CHECK(renderer.plannedPoints() <= 3000);
    CHECK(renderer.plannedPoints() > 1200);
    renderer.setPointBudget(1200);
    renderer.planFrame(std::span<const viewer::EyeDraw>(&eye, 1), 3000);
    CHECK(renderer.plannedPoints() <= 1200);
    CHECK(renderer.plannedPoints() > 0);
    REQUIRE(renderer.lastView());
    CHECK(renderer.lastView()->point_budget == 1200);
    renderer.setGpuBytes(123456);
    renderer.planFrame(std::span<const viewer::EyeDraw>(&eye, 1), 3000);
    CHECK(renderer.lastView()->gpu_bytes == 123456);
}

TEST_CASE("the compute rasterizer's subgroup reduction leaves the same image and depth, bit for bit") {
    render::EglContext context;
    // Many points a pixel: a 4 x 4 m patch of 120,000 points seen from 400 m, on 5 heights
    // (ties of depth between points of different colours), in random colours.
    core::PointCloud cloud;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> xy(-2.0f, 2.0f);
    std::uniform_int_distribution<int> level(0, 4), byte(0, 255);
    for (int k = 0; k < 120000; ++k) {
        core::CloudPoint p;
        p.position = {xy(rng), xy(rng), 0.25f * float(level(rng))};
        p.rgb = core::packRgb(std::uint8_t(byte(rng)), std::uint8_t(byte(rng)), std::uint8_t(byte(rng)));
        cloud.points.push_back(p);
    }
    const int width = 160, height = 120;
    Uploaded uploaded(cloud);
    viewer::PointRenderer& renderer = uploaded.renderer;
    if (!renderer.subgroupAvailable()) {
        const auto* renderer_name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        const std::string gpu = renderer_name ? renderer_name : "this GPU";
        MESSAGE(gpu, " has no GL_KHR_shader_subgroup in compute: the plain path alone is drawn");
    }
    for (float size_px : {1.0f, 3.0f}) {
        std::vector<std::uint8_t> colours[2];
        std::vector<float> depths[2];
        for (int r = 0; r < 2; ++r) {
            renderer.setSubgroupReduction(r == 1);
            viewer::EyeTarget target, out;
            REQUIRE(target.ensure(width, height));
            REQUIRE(out.ensure(width, height));
            viewer::EyeDraw eye;
            eye.projection = glm::perspective(glm::radians(2.0), double(width) / height, 1.0, 2000.0);
            eye.view = glm::lookAt(glm::dvec3(0.3, 0.2, 400.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
            eye.near_m = 1.0;
            eye.far_m = 2000.0;
            viewer::ViewStyle style;
            style.point_size_px = size_px;
            style.rasterizer = viewer::Rasterizer::Compute;
            renderer.drawEye(target, eye, style, viewer::ViewMode::Free, out.fbo, 0, 0, width, height);
            renderer.depthInto(target);
            colours[r].resize(std::size_t(width) * height * 4);
            depths[r].resize(std::size_t(width) * height);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glGetTextureImage(out.colour, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(colours[r].size()), colours[r].data());
            glGetTextureImage(target.depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(depths[r].size() * sizeof(float)),
                              depths[r].data());
            REQUIRE(glGetError() == GL_NO_ERROR);
            target.destroy();
            out.destroy();
        }
        CAPTURE(size_px);
        const auto covered = std::count_if(depths[0].begin(), depths[0].end(), [](float d) { return d < 1.0f; });
        CHECK(covered > 1000);  // the patch covers many pixels, each of many points
        CHECK(colours[0] == colours[1]);
        CHECK(std::memcmp(depths[0].data(), depths[1].data(), depths[0].size() * sizeof(float)) == 0);
    }
    CHECK(renderer.subgroupReduction() == renderer.subgroupAvailable());
}
