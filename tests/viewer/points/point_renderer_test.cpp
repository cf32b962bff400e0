// tests/viewer/points/point_renderer_test.cpp: the viewer's height colours: points of known
// heights drawn headless (EGL) with the "height" colour mode read back as exactly the
// generator's jet colours, core::jetTable entry core::jetIndex (the table sim writes into
// the files), for 64 entries and for 16; the colour, size and cutting-volume checks run
// with both rasterizers (GL_POINTS and compute); the compute rasterizer's subgroup
// reduction leaves its image and depth as they are without it. Above-ground colours over a
// terrain handed to the renderer (a slope with a box on it: the ground white, the box by its
// height above the slope), and the class, intensity and return colours of a LAS file
// written as another producer writes it.
#include "points/point_renderer.hpp"

#include <viewer/cloud_feed.hpp>
#include <viewer/cloud_feed_source.hpp>

#include <test_files.hpp>

#include <core/jet.hpp>
#include <core/point_cloud.hpp>
#include <io/cloud_io.hpp>
#include <render/egl_context.hpp>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
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
        upload(cloud.points.size());
    }
    /// The points of a file, read as `view` reads it (CloudFeed::feedFile).
    Uploaded(const std::filesystem::path& file, std::size_t points) {
        feed.feedFile(file);
        REQUIRE(feed.error().empty());
        upload(points);
    }
    void upload(std::size_t points) {
        source = std::make_unique<viewer::CloudFeedSource>(feed);
        source->poll();
        renderer.stream(*source, points);
        REQUIRE(renderer.uploadedPoints() == points);
    }
};

// Draws `cloud` from straight above with an orthographic camera (1 m = 8 px, grid cell
// (i, j) centred on pixel (8i + 4, 8j + 4)) and returns the resolved image (the points'
// colours where the style has eye-dome lighting off).
// `shift`: where the cloud's local (0, 0, 0) lies in the source's local frame (a file's
// reader chooses its own origin).
std::vector<Pixel> drawUploaded(Uploaded& uploaded, int rows, const viewer::ViewStyle& style,
                                const viewer::CutVolume& cut = {}, const glm::dvec3& shift = glm::dvec3(0.0)) {
    viewer::PointRenderer& renderer = uploaded.renderer;
    // Empty rows above the grid keep the mode indicator (drawn near the top) off it.
    const int width = kColumns * kPixelsPerMetre, height = (rows + kIndicatorRows) * kPixelsPerMetre;
    viewer::EyeTarget target, out;
    REQUIRE(target.ensure(width, height));
    REQUIRE(out.ensure(width, height));
    viewer::EyeDraw eye;
    eye.view = glm::lookAt(shift + glm::dvec3(0.0, 0.0, 1000.0), shift, glm::dvec3(0.0, 1.0, 0.0));
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

std::vector<Pixel> drawFromAbove(const core::PointCloud& cloud, int rows, const viewer::ViewStyle& style,
                                 const viewer::CutVolume& cut = {}) {
    Uploaded uploaded(cloud);
    return drawUploaded(uploaded, rows, style, cut);
}

// The colour of grid cell (i, j)'s centre pixel in a drawFromAbove image.
std::uint32_t cellColour(const std::vector<Pixel>& pixels, int i, int j) {
    const Pixel p = pixels[static_cast<std::size_t>(j * kPixelsPerMetre + 4) * kColumns * kPixelsPerMetre +
                           static_cast<std::size_t>(i * kPixelsPerMetre + 4)];
    return core::packRgb(p.r, p.g, p.b);
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
// not by z, and show the last four, the ground, white. In a generated cloud they are the
// whitened points (white, at any height); in another producer's file (`ladarvr ground`'s
// output of a survey without colours, which reads white throughout) its class 2 (the label
// ground), white at any height, while its other points take the jet, white colour or not.
void checkAboveGroundColours(viewer::Rasterizer rasterizer, bool from_elsewhere) {
    constexpr int entries = 64;
    const float top_m = 12.8f;
    std::vector<float> above = {0.0f, top_m};
    for (int bin = 0; bin < entries; bin += 3) above.push_back((float(bin) + 0.5f) * top_m / entries);
    const std::vector<float> ground_above =
        from_elsewhere ? std::vector<float>{-0.4f, 0.0f, 0.3f, 1.2f} : std::vector<float>{7.0f, 7.0f, 7.0f, 7.0f};
    const std::size_t total = above.size() + ground_above.size();
    const int rows = (static_cast<int>(total) + kColumns - 1) / kColumns;
    core::PointCloud cloud;
    cloud.fields.height_above_ground = true;
    if (from_elsewhere) {
        cloud.fields.rgb = false;
        cloud.foreign.emplace();
    }
    for (std::size_t k = 0; k < total; ++k) {
        core::CloudPoint p;
        // z varies against the height above ground, so colouring by z would give other entries.
        p.position = {float(k % kColumns), float(k / kColumns), 50.0f - float(k)};
        const bool ground = k >= above.size();
        if (from_elsewhere)
            p.label = ground ? core::Role::Ground : core::Role::Environment;
        else
            p.rgb = ground ? core::kWhite : 0x808080u;
        p.height_above_ground_m = ground ? ground_above[k - above.size()] : above[k];
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

// A cloud far from the world's origin on a slope (z = 0.8 x + 0.3 y) with a box standing on
// it, and the slope as a terrain in world coordinates: a coarse grid (2 m cells, offset by
// 1 m from the points) the shaders must interpolate between its cells.
constexpr int kSlopeRows = 4;
const glm::dvec3 kSlopeOrigin(512000.0, 4100000.0, 230.0);
double slopeZ(double x, double y) { return 0.8 * x + 0.3 * y; }
// The box's cells and their heights above the slope.
struct BoxCell {
    int i, j;
    float above_m;
};
constexpr BoxCell kBox[] = {{5, 1, 4.0f}, {6, 1, 2.03f}, {5, 2, 3.1f}, {6, 2, 1.2f}};

core::PointCloud slopeWithBox() {
    core::PointCloud cloud;
    cloud.origin = kSlopeOrigin;
    for (int j = 0; j < kSlopeRows; ++j)
        for (int i = 0; i < kColumns; ++i) {
            core::CloudPoint p;
            float above = 0.0f;
            for (const BoxCell& b : kBox)
                if (b.i == i && b.j == j) above = b.above_m;
            p.position = {float(i), float(j), float(slopeZ(i, j)) + above};
            p.rgb = 0x808080u;
            cloud.points.push_back(p);
        }
    return cloud;
}

viewer::ViewTerrain slopeTerrain() {
    viewer::ViewTerrain t;
    t.x0 = kSlopeOrigin.x - 1.0;
    t.y0 = kSlopeOrigin.y - 1.0;
    t.cell = 2.0;
    t.nx = 8;
    t.ny = 4;
    for (int j = 0; j < t.ny; ++j)
        for (int i = 0; i < t.nx; ++i) t.z.push_back(float(kSlopeOrigin.z + slopeZ(-1.0 + 2.0 * i, -1.0 + 2.0 * j)));
    t.source = "the test's slope";
    return t;
}

bool isBox(int i, int j) {
    return std::any_of(std::begin(kBox), std::end(kBox), [&](const BoxCell& b) { return b.i == i && b.j == j; });
}
bool reddish(std::uint32_t rgb) { return (rgb >> 16) >= 128 && ((rgb >> 8) & 0xFFu) < 100 && (rgb & 0xFFu) < 100; }

}  // namespace

TEST_CASE("viewer above-ground colours: the jet by height above the terrain, whitened ground white") {
    render::EglContext context;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        checkAboveGroundColours(r, false);
    }
}

TEST_CASE("viewer above-ground colours of another producer's file: its class 2 white, the rest by height") {
    render::EglContext context;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        checkAboveGroundColours(r, true);
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

TEST_CASE("file colours of a cloud without colours: another producer's shows heights, ours (generate --white) white") {
    render::EglContext context;
    for (const bool from_elsewhere : {false, true}) {
        CAPTURE(from_elsewhere);
        core::PointCloud cloud;
        cloud.fields.rgb = false;  // every point reads white
        if (from_elsewhere) cloud.foreign.emplace();
        for (int k = 0; k < kColumns; ++k) {
            core::CloudPoint p;
            p.position = {float(k), 0.0f, float(k)};
            cloud.points.push_back(p);
        }
        viewer::ViewStyle style;
        style.eye_dome = false;
        style.point_size_px = 5.0f;
        const std::vector<Pixel> pixels = drawFromAbove(cloud, 1, style);
        int white = 0;
        for (int k = 0; k < kColumns; ++k) white += cellColour(pixels, k, 0) == core::kWhite;
        CHECK(white == (from_elsewhere ? 0 : kColumns));
        CHECK(reddish(cellColour(pixels, 0, 0)) == from_elsewhere);  // the lowest point, by height
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

TEST_CASE("above-ground colours from a terrain: the ground on a slope white, a box on it by its height above it") {
    render::EglContext context;
    constexpr int entries = 64;
    const core::PointCloud cloud = slopeWithBox();
    const std::vector<std::uint32_t> jet = core::jetTable(entries);
    std::vector<std::vector<Pixel>> images;
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        viewer::ViewStyle style;
        style.eye_dome = false;
        style.point_size_px = 5.0f;
        style.jet_entries = entries;
        style.rasterizer = r;
        Uploaded uploaded(cloud);
        // The height colours make the low end of the slope red, as they make nothing else.
        style.colour = viewer::ColourMode::HeightJet;
        const std::vector<Pixel> height = drawUploaded(uploaded, kSlopeRows, style);
        int red_ground = 0;
        for (int j = 0; j < kSlopeRows; ++j)
            for (int i = 0; i < kColumns; ++i) red_ground += !isBox(i, j) && reddish(cellColour(height, i, j));
        CHECK(red_ground > 0);
        // Before the terrain comes, above-ground on a cloud without heights shows the heights.
        style.colour = viewer::ColourMode::AboveGround;
        CHECK(drawUploaded(uploaded, kSlopeRows, style).size() == height.size());
        CHECK(cellColour(drawUploaded(uploaded, kSlopeRows, style), 0, 0) == cellColour(height, 0, 0));
        CHECK_FALSE(uploaded.renderer.hasTerrain());

        uploaded.renderer.setTerrain(slopeTerrain(), uploaded.source->origin(), *uploaded.source);
        REQUIRE(uploaded.renderer.hasTerrain());
        CHECK(uploaded.renderer.aboveGroundMax() == doctest::Approx(4.0).epsilon(1e-5));
        const std::optional<double> at_box = uploaded.renderer.heightAboveTerrain({5.0, 1.0, slopeZ(5, 1) + 4.0});
        REQUIRE(at_box);
        CHECK(*at_box == doctest::Approx(4.0).epsilon(1e-6));
        const std::vector<Pixel> above = drawUploaded(uploaded, kSlopeRows, style);
        int white_ground = 0, ground = 0;
        for (int j = 0; j < kSlopeRows; ++j)
            for (int i = 0; i < kColumns; ++i) {
                if (isBox(i, j)) continue;
                ++ground;
                white_ground += cellColour(above, i, j) == core::kWhite;
                CHECK_FALSE(reddish(cellColour(above, i, j)));
            }
        CHECK(white_ground == ground);
        for (const BoxCell& b : kBox) {
            CAPTURE(b.above_m);
            CHECK(cellColour(above, b.i, b.j) == jet[core::jetIndex(b.above_m, 0.0, 4.0, entries)]);
        }
        images.push_back(above);
    }
    // Both rasterizers give the same picture.
    REQUIRE(images.size() == 2);
    CHECK(std::memcmp(images[0].data(), images[1].data(), images[0].size() * sizeof(Pixel)) == 0);
}

TEST_CASE("above-ground colours in US survey feet: the ground is what lies within 0.5 m (1.64 ft) of the terrain") {
    render::EglContext context;
    // The slope, with one point 1 unit above it: 1 m is above the ground threshold, 1 ft
    // (0.30 m) is not.
    core::PointCloud cloud = slopeWithBox();
    const int i = 2, j = 1;
    cloud.points[std::size_t(j * kColumns + i)].position.z += 1.0f;
    viewer::ViewStyle style;
    style.eye_dome = false;
    style.point_size_px = 5.0f;
    style.colour = viewer::ColourMode::AboveGround;
    for (const double unit_m : {1.0, 0.3048006}) {
        CAPTURE(unit_m);
        Uploaded uploaded(cloud);
        uploaded.renderer.setHeightUnit(unit_m);
        uploaded.renderer.setTerrain(slopeTerrain(), uploaded.source->origin(), *uploaded.source);
        REQUIRE(uploaded.renderer.hasTerrain());
        const std::vector<Pixel> above = drawUploaded(uploaded, kSlopeRows, style);
        CHECK((cellColour(above, i, j) == core::kWhite) == (unit_m < 1.0));
        CHECK(cellColour(above, 0, 0) == core::kWhite);
        CHECK(cellColour(above, kBox[0].i, kBox[0].j) != core::kWhite);
    }
}

namespace {

// A LAS file as another producer writes it (point format 1: no colours, no label of ours):
// one row of points with ASPRS classes, intensities 0, 100, ..., 1100 and returns.
constexpr std::uint8_t kClasses[kColumns] = {2, 5, 6, 2, 5, 6, 9, 7, 18, 1, 3, 4};
constexpr std::uint8_t kReturn[4][2] = {{1, 1}, {1, 3}, {2, 3}, {3, 3}};  // number, of returns
const glm::dvec3 kSurveyOrigin(300000.0, 5000000.0, 100.0);

std::filesystem::path writeSurvey(const std::filesystem::path& dir) {
    core::PointCloud cloud;
    cloud.origin = kSurveyOrigin;
    cloud.fields = core::CloudFields{};
    cloud.fields.rgb = cloud.fields.label = cloud.fields.view = cloud.fields.range = false;
    cloud.fields.intensity = cloud.fields.returns = true;
    cloud.foreign.emplace();
    cloud.foreign->header.point_format = 1;
    for (int i = 0; i < kColumns; ++i) {
        core::CloudPoint p;
        p.position = {float(i), 0.0f, 0.25f * float(i)};
        p.intensity = std::uint16_t(100 * i);
        p.return_number = kReturn[i % 4][0];
        p.returns = kReturn[i % 4][1];
        cloud.points.push_back(p);
        core::ForeignPoint f;
        f.classification = kClasses[i];
        const auto* bytes = reinterpret_cast<const unsigned char*>(&f);
        cloud.foreign->records.insert(cloud.foreign->records.end(), bytes, bytes + sizeof f);
    }
    const std::filesystem::path file = dir / "survey.las";
    io::writeCloud(file, cloud, io::CloudFormat::Las);
    return file;
}

// docs/viewer.md's palette, as the screen shows it.
std::uint32_t classColour(std::uint8_t c) {
    switch (c) {
        case 2: return core::packRgb(153, 102, 51);
        case 3: return core::packRgb(150, 220, 110);
        case 4: return core::packRgb(60, 180, 60);
        case 5: return core::packRgb(0, 115, 0);
        case 6: return core::packRgb(230, 100, 40);
        case 9: return core::packRgb(40, 100, 230);
        case 7:
        case 18: return core::packRgb(255, 0, 255);
        default: return core::packRgb(153, 153, 153);
    }
}

std::uint32_t returnColour(int number, int returns) {
    if (returns == 1) return core::packRgb(255, 215, 0);
    if (number == 1) return core::packRgb(0, 205, 75);
    if (number == returns) return core::packRgb(230, 40, 40);
    return core::packRgb(65, 115, 255);
}

}  // namespace

TEST_CASE("a survey's classes, intensities and returns in their colour modes, the same with either rasterizer") {
    render::EglContext context;
    test_support::TempDir dir("viewer_class_colours");
    const std::filesystem::path file = writeSurvey(dir.path);
    std::vector<Pixel> first[3];
    for (const viewer::Rasterizer r : kRasterizers) {
        CAPTURE(viewer::rasterizerName(r));
        Uploaded uploaded(file, kColumns);
        const viewer::ColourSources sources = uploaded.renderer.colourSources();
        CHECK_FALSE(sources.height_above_ground);
        CHECK((sources.intensity && sources.returns));
        viewer::ViewStyle style;
        style.eye_dome = false;
        style.point_size_px = 5.0f;
        style.rasterizer = r;
        const viewer::ColourMode modes[3] = {viewer::ColourMode::Class, viewer::ColourMode::Intensity,
                                             viewer::ColourMode::Return};
        for (int m = 0; m < 3; ++m) {
            style.colour = modes[m];
            const std::vector<Pixel> image =
                drawUploaded(uploaded, 1, style, {}, kSurveyOrigin - uploaded.source->origin());
            for (int i = 0; i < kColumns; ++i) {
                CAPTURE(viewer::colourModeName(modes[m]));
                CAPTURE(i);
                const std::uint32_t got = cellColour(image, i, 0);
                if (m == 0) CHECK(got == classColour(kClasses[i]));
                // The 2nd and 98th percentiles of 0, 100, ..., 1100 are 0 and 1000.
                const auto grey = std::uint8_t(std::lround(std::min(1.0, 100.0 * i / 1000.0) * 255.0));
                if (m == 1) CHECK(got == core::packRgb(grey, grey, grey));
                if (m == 2) CHECK(got == returnColour(kReturn[i % 4][0], kReturn[i % 4][1]));
            }
            if (r == viewer::Rasterizer::Points)
                first[m] = image;
            else
                CHECK(std::memcmp(first[m].data(), image.data(), image.size() * sizeof(Pixel)) == 0);
        }
    }
}

TEST_CASE("a cloud of ours shows its labels as the classes our LAS writer gives them") {
    render::EglContext context;
    core::PointCloud cloud;
    const core::Role roles[3] = {core::Role::Ground, core::Role::Environment, core::Role::Target};
    for (int i = 0; i < 3; ++i) {
        core::CloudPoint p;
        p.position = {float(i), 0.0f, 0.0f};
        p.label = roles[i];
        cloud.points.push_back(p);
    }
    for (const bool heights : {false, true}) {  // packed attributes, or heights above ground
        CAPTURE(heights);
        cloud.fields.height_above_ground = heights;
        viewer::ViewStyle style;
        style.eye_dome = false;
        style.point_size_px = 5.0f;
        style.colour = viewer::ColourMode::Class;
        const std::vector<Pixel> image = drawFromAbove(cloud, 1, style);
        CHECK(cellColour(image, 0, 0) == classColour(2));
        CHECK(cellColour(image, 1, 0) == classColour(1));
        CHECK(cellColour(image, 2, 0) == classColour(64));
    }
}
