// viewer/src/points/point_renderer.cpp: streamed, camera-relative point drawing with eye-dome
// lighting for the immersive viewer (paper §IV-A; the jet map is the paper's §III-C one,
// core::jetTable, the generator's table). The GLSL lives in shaders/.
#include "points/point_renderer.hpp"
#include "ui/panel_layout.hpp"

#include <viewer/node_selection.hpp>

#include <core/error.hpp>
#include <core/jet.hpp>
#include <render/orbit_camera.hpp>
#include <shaders/shaders.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace viewer {

namespace {

// A, U, T, O, M, I, C, F, R, E
constexpr std::array<int, 70> kFont = {
    0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001,  // A
    0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110,  // U
    0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100,  // T
    0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110,  // O
    0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001,  // M
    0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110,  // I
    0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110,  // C
    0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000,  // F
    0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001,  // R
    0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111,  // E
};
constexpr const char* kGlyphs = "AUTOMICFRE";

// GL_KHR_shader_subgroup's queries (not in the GL 4.5 core loader).
constexpr GLenum kSubgroupSupportedStages = 0x9533, kSubgroupSupportedFeatures = 0x9534;
constexpr GLint kComputeStageBit = 0x20;
constexpr GLint kSubgroupBasic = 0x1, kSubgroupVote = 0x2, kSubgroupArithmetic = 0x4;

/// Whether the context runs subgroup basic, vote and arithmetic operations in compute.
bool subgroupsInCompute() {
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    bool found = false;
    for (GLint i = 0; i < n && !found; ++i) {
        const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
        found = e && std::strcmp(e, "GL_KHR_shader_subgroup") == 0;
    }
    if (!found) return false;
    GLint stages = 0, features = 0;
    glGetIntegerv(kSubgroupSupportedStages, &stages);
    glGetIntegerv(kSubgroupSupportedFeatures, &features);
    const GLint need = kSubgroupBasic | kSubgroupVote | kSubgroupArithmetic;
    return (stages & kComputeStageBit) != 0 && (features & need) == need;
}

}  // namespace

// --- EyeTarget ----------------------------------------------------------------------------
bool EyeTarget::ensure(int w, int h) {
    if (fbo != 0 && w == width && h == height) return true;
    destroy();
    width = w;
    height = h;
    glCreateTextures(GL_TEXTURE_2D, 1, &colour);
    glTextureStorage2D(colour, 1, GL_RGBA8, w, h);
    glCreateTextures(GL_TEXTURE_2D, 1, &depth);
    glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT32F, w, h);
    for (GLuint t : {colour, depth}) {
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, colour, 0);
    glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depth, 0);
    const bool complete = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    return render::logGl("EyeTarget::ensure", __FILE__, __LINE__) && complete;
}

void EyeTarget::destroy() {
    if (fbo) glDeleteFramebuffers(1, &fbo);
    if (colour) glDeleteTextures(1, &colour);
    if (depth) glDeleteTextures(1, &depth);
    fbo = colour = depth = 0;
    width = height = 0;
}

// --- PointRenderer ------------------------------------------------------------------------
PointRenderer::PointRenderer()
    : points_("viewer points", {{GL_VERTEX_SHADER, shaders::viewer_points_vert, shaders::viewer_points_vert_files},
                                {GL_FRAGMENT_SHADER, shaders::vertex_colour_frag, shaders::vertex_colour_frag_files}}),
      resolve_("viewer eye-dome resolve",
               {{GL_VERTEX_SHADER, shaders::fullscreen_triangle_vert, shaders::fullscreen_triangle_vert_files},
                {GL_FRAGMENT_SHADER, shaders::eye_dome_resolve_frag, shaders::eye_dome_resolve_frag_files}}),
      indicator_("viewer mode indicator",
                 {{GL_VERTEX_SHADER, shaders::mode_indicator_vert, shaders::mode_indicator_vert_files},
                  {GL_FRAGMENT_SHADER, shaders::mode_indicator_frag, shaders::mode_indicator_frag_files}}),
      splat_("viewer compute rasteriser",
             {{GL_COMPUTE_SHADER, shaders::viewer_points_splat_comp, shaders::viewer_points_splat_comp_files}}),
      depth_("viewer compute rasteriser depth",
             {{GL_VERTEX_SHADER, shaders::fullscreen_triangle_vert, shaders::fullscreen_triangle_vert_files},
              {GL_FRAGMENT_SHADER, shaders::viewer_points_depth_frag, shaders::viewer_points_depth_frag_files}}) {
    if (subgroupsInCompute()) {
        try {
            splat_subgroup_ = render::Program("viewer compute rasteriser (subgroups)",
                                              {{GL_COMPUTE_SHADER, shaders::viewer_points_splat_subgroup_comp,
                                                shaders::viewer_points_splat_subgroup_comp_files}});
        } catch (const core::Error&) {
            // A driver that lists the extension and still refuses the program: the plain one.
            splat_subgroup_ = render::Program();
        }
    }
    glCreateVertexArrays(1, &empty_vao_);
    indicator_.use();
    glUniform1iv(indicator_.uniform("u_font"), 70, kFont.data());
    GL_CHECK(glUseProgram(0));
}

PointRenderer::~PointRenderer() {
    if (jet_texture_) glDeleteTextures(1, &jet_texture_);
    if (terrain_ && terrain_->texture) glDeleteTextures(1, &terrain_->texture);
    if (raster_depth_) glDeleteTextures(1, &raster_depth_);
    if (raster_colour_) glDeleteTextures(1, &raster_colour_);
    if (raster_cells_) glDeleteBuffers(1, &raster_cells_);
    if (empty_vao_) glDeleteVertexArrays(1, &empty_vao_);
    if (!pass_queries_.empty()) glDeleteQueries(GLsizei(pass_queries_.size()), pass_queries_.data());
}

void PointRenderer::setPassTiming(bool on) {
    pass_timing_ = on;
    pass_used_ = 0;
}

GLuint PointRenderer::passMark() const {
    if (!pass_timing_) return 0;
    if (pass_used_ == pass_queries_.size()) {
        GLuint q = 0;
        glGenQueries(1, &q);
        pass_queries_.push_back(q);
    }
    const GLuint q = pass_queries_[pass_used_++];
    glQueryCounter(q, GL_TIMESTAMP);
    return q;
}

PointRenderer::PassTimes PointRenderer::takePassTimes() {
    PassTimes t;
    const std::size_t used = pass_used_ - pass_used_ % 4;
    for (std::size_t e = 0; e + 4 <= used; e += 4) {
        GLuint64 ns[4] = {0, 0, 0, 0};
        for (int k = 0; k < 4; ++k) glGetQueryObjectui64v(pass_queries_[e + std::size_t(k)], GL_QUERY_RESULT, &ns[k]);
        t.raster_ms += double(ns[1] - ns[0]) * 1e-6;
        t.colour_ms += double(ns[2] - ns[1]) * 1e-6;
        t.resolve_ms += double(ns[3] - ns[2]) * 1e-6;
        ++t.eyes;
    }
    pass_used_ = 0;
    render::logGl("PointRenderer::takePassTimes", __FILE__, __LINE__);
    return t;
}

GLuint PointRenderer::jetTexture(int entries) const {
    entries = std::clamp(entries, 2, 256);  // options.cpp validates; never index past it
    if (jet_texture_ && jet_entries_ == entries) return jet_texture_;
    if (jet_texture_) glDeleteTextures(1, &jet_texture_);
    // Texel i = core::jetTable entry i. 0x00RRGGBB is stored as bytes B, G, R, 0, read as
    // GL_BGRA like the points' own colours, so a jet colour reaches the screen byte-exact.
    const std::vector<std::uint32_t> table = core::jetTable(entries);
    glCreateTextures(GL_TEXTURE_1D, 1, &jet_texture_);
    glTextureStorage1D(jet_texture_, 1, GL_RGBA8, entries);
    glTextureSubImage1D(jet_texture_, 0, 0, entries, GL_BGRA, GL_UNSIGNED_BYTE, table.data());
    glTextureParameteri(jet_texture_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(jet_texture_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    jet_entries_ = entries;
    render::logGl("PointRenderer::jetTexture", __FILE__, __LINE__);
    return jet_texture_;
}

void PointRenderer::setGpuBytes(std::size_t bound) { arena_.bytes_bound = bound; }

void PointRenderer::addNode(const PointNode* node, std::shared_ptr<const NodePoints> points) {
    std::vector<render::CellRange> cells;
    cells.reserve(points->cells.size());
    for (const LodCell& l : points->cells) cells.push_back({l.first, l.count, l.bounds});
    const auto chunk = chunks_.addChunk(points->points.size(), cells);
    if (!chunk) {  // out of GPU memory: show what fits, and do not ask again each frame
        no_room_.insert(node);
        return;
    }
    on_gpu_[node] = *chunk;
    if (chunk_used_.size() <= *chunk) {
        chunk_used_.resize(*chunk + 1, 0);
        chunk_node_.resize(*chunk + 1, nullptr);
    }
    chunk_used_[*chunk] = tick_;
    chunk_node_[*chunk] = node;
    ++arena_.nodes_added;
    ++arena_.frame_nodes_added;
    arena_.bytes = chunks_.allocatedBytes();
    arena_.bytes_peak = std::max(arena_.bytes_peak, arena_.bytes);
    pending_points_ += points->points.size();
    pending_.push_back({std::move(points), 0, *chunk, 0});
}

void PointRenderer::dropNode(const PointNode* node) {
    const std::size_t chunk = on_gpu_.at(node);
    for (auto it = pending_.begin(); it != pending_.end();)
        if (it->chunk == chunk) {
            pending_points_ -= it->node->points.size() - it->next;
            it = pending_.erase(it);
        } else {
            ++it;
        }
    chunks_.removeChunk(chunk);
    chunk_node_[chunk] = nullptr;
    on_gpu_.erase(node);
    arena_.bytes = chunks_.allocatedBytes();
    plan_valid_ = false;
}

bool PointRenderer::makeRoom(std::size_t bytes, std::deque<Evictable>& evictable) {
    const std::size_t bound = arena_.bytes_bound;
    while (bound != 0 && chunks_.allocatedBytes() + bytes > bound && bytes <= bound && !evictable.empty()) {
        const auto [c, node] = evictable.front();
        evictable.pop_front();
        if (chunk_node_[c] != node) continue;  // gone already (its id may hold a newcomer)
        dropNode(node);
        ++arena_.nodes_evicted;
        ++arena_.frame_nodes_evicted;
    }
    return bound == 0 || chunks_.allocatedBytes() + bytes <= bound;
}

std::size_t PointRenderer::stream(const PointSource& source, std::size_t budget_points) {
    ++tick_;
    fields_ = source.fields();
    from_elsewhere_ = source.fromElsewhere();
    arena_.frame_nodes_added = arena_.frame_nodes_evicted = arena_.frame_upload_bytes = 0;
    arena_.nodes_refused = 0;
    // Nodes that left RAM leave the GPU (in chunk order: the same run drops the same way).
    for (std::size_t c = 0; c < chunk_node_.size(); ++c)
        if (chunk_node_[c] && !chunk_node_[c]->resident()) dropNode(chunk_node_[c]);
    const bool chooses = source.stats().has_value();
    const std::span<PointNode* const> chosen = source.wanted();
    const std::vector<PointNode*> order =
        chooses ? std::vector<PointNode*>(chosen.begin(), chosen.end()) : allNodes(source);
    const std::unordered_set<const PointNode*> wanted(order.begin(), order.end());
    std::unordered_map<const PointNode*, std::size_t> rank;
    if (chooses)
        for (std::size_t i = 0; i < order.size(); ++i) rank.emplace(order[i], i);
    // The chunks of nodes not wanted now, least recently used first (a tie: the earlier
    // chunk): what makes room when a wanted node does not fit.
    std::deque<Evictable> evictable;
    if (arena_.bytes_bound != 0) {
        for (std::size_t c = 0; c < chunk_node_.size(); ++c)
            if (chunk_node_[c] && !wanted.contains(chunk_node_[c])) evictable.push_back({c, chunk_node_[c]});
        std::sort(evictable.begin(), evictable.end(), [&](const Evictable& a, const Evictable& b) {
            return chunk_used_[a.chunk] != chunk_used_[b.chunk] ? chunk_used_[a.chunk] < chunk_used_[b.chunk]
                                                                : a.chunk < b.chunk;
        });
    }
    for (PointNode* node : order) {
        std::shared_ptr<const NodePoints> points = node->points();
        if (!points) {
            no_room_.erase(node);
            continue;
        }
        if (const auto it = on_gpu_.find(node); it != on_gpu_.end()) {
            chunk_used_[it->second] = tick_;
            continue;
        }
        if (points->points.empty() || no_room_.contains(node)) continue;
        if (!makeRoom(gpuBytes(points->points.size()), evictable)) {
            ++arena_.nodes_refused;
            continue;
        }
        addNode(node, std::move(points));
    }
    if (chooses) {  // the upload queue follows the latest wanted order, most important first
        for (Pending& p : pending_) {
            const auto it = rank.find(chunk_node_[p.chunk]);
            p.rank = it == rank.end() ? SIZE_MAX : it->second;
        }
        std::stable_sort(pending_.begin(), pending_.end(),
                         [](const Pending& a, const Pending& b) { return a.rank < b.rank; });
    }
    arena_.nodes = on_gpu_.size();
    arena_.bytes = chunks_.allocatedBytes();
    std::size_t uploaded = 0;
    while (!pending_.empty() && uploaded < budget_points) {
        Pending& job = pending_.front();
        const std::vector<core::CloudPoint>& points = job.node->points;
        const std::size_t n = std::min(budget_points - uploaded, points.size() - job.next);
        const std::span<const core::CloudPoint> part(points.data() + job.next, n);
        if (fields_.height_above_ground)  // else the slot holds the packed attributes
            for (const core::CloudPoint& p : part) {
                above_ground_max_m_ = std::max(above_ground_max_m_, p.height_above_ground_m);
                above_ground_span_.addSampled(p.height_above_ground_m, kHeightSample);
            }
        for (const core::CloudPoint& p : part) z_span_.addSampled(p.position.z, kHeightSample);
        if (terrain_) raiseTerrainMax(part);
        chunks_.upload(job.chunk, part);
        job.next += n;
        uploaded += n;
        pending_points_ -= n;
        if (job.next == points.size()) pending_.pop_front();
    }
    if (uploaded) updateSpans();
    arena_.frame_upload_bytes = uploaded * sizeof(render::GpuPoint);
    if (uploaded) render::logGl("glNamedBufferSubData (point chunk)", __FILE__, __LINE__);
    return uploaded;
}

namespace {

/// The bound terrain's height at local (x, y): bilinear between the four nearest cells'
/// centres, the edge cells' heights beyond the grid (shaders/include/viewer_point_style.glsl's
/// terrainHeight, in double).
template <class Terrain>
double terrainHeightAt(const Terrain& t, double x, double y) {
    const double gx = std::clamp((x - t.x0) / t.cell, 0.0, double(t.nx - 1));
    const double gy = std::clamp((y - t.y0) / t.cell, 0.0, double(t.ny - 1));
    const int i0 = int(std::floor(gx)), j0 = int(std::floor(gy));
    const int i1 = std::min(i0 + 1, t.nx - 1), j1 = std::min(j0 + 1, t.ny - 1);
    const double fx = gx - i0, fy = gy - j0;
    auto z = [&](int i, int j) { return double(t.z[std::size_t(j) * std::size_t(t.nx) + std::size_t(i)]); };
    const double lo = z(i0, j0) + (z(i1, j0) - z(i0, j0)) * fx;
    const double hi = z(i0, j1) + (z(i1, j1) - z(i0, j1)) * fx;
    return lo + (hi - lo) * fy;
}

}  // namespace

void PointRenderer::setTerrain(const ViewTerrain& terrain, const glm::dvec3& origin, const PointSource& source) {
    if (terrain.empty() || !(terrain.cell > 0.0)) return;
    if (terrain_ && terrain_->texture) glDeleteTextures(1, &terrain_->texture);
    // A grid wider than the GPU's largest texture keeps every k-th cell (a coarser terrain
    // rather than none).
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    max_size = std::max(max_size, 1);
    const int step = (std::max(terrain.nx, terrain.ny) + max_size - 1) / max_size;
    LocalTerrain t;
    t.x0 = terrain.x0 - origin.x;
    t.y0 = terrain.y0 - origin.y;
    t.cell = terrain.cell * step;
    t.nx = (terrain.nx + step - 1) / step;
    t.ny = (terrain.ny + step - 1) / step;
    t.z.resize(std::size_t(t.nx) * std::size_t(t.ny));
    for (int j = 0; j < t.ny; ++j)
        for (int i = 0; i < t.nx; ++i)
            t.z[std::size_t(j) * std::size_t(t.nx) + std::size_t(i)] = float(
                double(terrain.z[std::size_t(j * step) * std::size_t(terrain.nx) + std::size_t(i * step)]) - origin.z);
    glCreateTextures(GL_TEXTURE_2D, 1, &t.texture);
    glTextureStorage2D(t.texture, 1, GL_R32F, t.nx, t.ny);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(t.texture, 0, 0, 0, t.nx, t.ny, GL_RED, GL_FLOAT, t.z.data());
    glTextureParameteri(t.texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    render::logGl("PointRenderer::setTerrain", __FILE__, __LINE__);
    terrain_ = std::move(t);
    terrain_max_m_ = 0.0f;
    terrain_span_ = core::HeightSpan(core::kStrayGap_m / height_unit_m_);
    terrain_body_ = {};
    for (const PointNode* node : allNodes(source))
        if (const std::shared_ptr<const NodePoints> points = node->points()) raiseTerrainMax(points->points);
    updateSpans();
}

void PointRenderer::setHeightUnit(double metres) {
    if (!(std::isfinite(metres) && metres > 0.0)) metres = 1.0;
    height_unit_m_ = metres;
    const core::HeightSpan fresh(core::kStrayGap_m / metres);
    z_span_ = above_ground_span_ = terrain_span_ = fresh;
    z_body_ = above_ground_body_ = terrain_body_ = {};
}

void PointRenderer::updateSpans() {
    z_body_ = z_span_.span();
    above_ground_body_ = above_ground_span_.span();
    terrain_body_ = terrain_span_.span();
    above_ground_top_m_ = core::topWithoutStrays(above_ground_body_, above_ground_max_m_);
    terrain_top_m_ = core::topWithoutStrays(terrain_body_, terrain_max_m_);
}

core::Bounds PointRenderer::bodyBounds() const {
    core::Bounds b = chunks_.bounds();
    if (b.empty()) return b;
    if (z_body_.strays_low) b.lo.z = z_body_.lo;
    if (z_body_.strays_high) b.hi.z = z_body_.hi;
    return b;
}

std::optional<double> PointRenderer::heightAboveTerrain(const glm::dvec3& local) const {
    if (!terrain_) return std::nullopt;
    return local.z - terrainHeightAt(*terrain_, local.x, local.y);
}

void PointRenderer::raiseTerrainMax(std::span<const core::CloudPoint> points) {
    for (const core::CloudPoint& p : points) {
        const float h = float(double(p.position.z) - terrainHeightAt(*terrain_, p.position.x, p.position.y));
        terrain_max_m_ = std::max(terrain_max_m_, h);
        terrain_span_.addSampled(h, kHeightSample);
    }
}

ColourSources PointRenderer::colourSources() const {
    // A cloud we generated (our labels, not another producer's file) that stores no colours
    // is white by intent (`generate --white` as LAS): its file colours stay white.
    const bool ours = fields_.label && !from_elsewhere_;
    return {fields_.height_above_ground, terrain_.has_value(), fields_.intensity, fields_.returns, fields_.rgb || ours};
}

void PointRenderer::planFrame(std::span<const EyeDraw> eyes, std::size_t point_budget, bool cull) {
    if (point_budget_) point_budget = *point_budget_;
    const auto& cells = chunks_.cells();
    plan_cull_ = cull;
    plan_.assign(cells.size(), 0);
    planned_points_ = focus_points_ = 0;
    plan_valid_ = true;
    if (eyes.empty()) return;
    std::vector<render::Frustum> frusta;
    glm::dvec3 eye_mean(0.0);
    for (const EyeDraw& e : eyes) {
        frusta.push_back(render::Frustum::fromMatrix(e.projection * e.view));
        eye_mean += glm::dvec3(glm::inverse(e.view)[3]) / double(eyes.size());
    }
    // The head's pose this frame (the eyes' mean position, the first eye's orientation) and
    // its motion over the last few frames: the source selects for where it is heading too.
    constexpr std::size_t kHeadHistory = 6;
    const double t_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - created_).count();
    HeadSample head = headOfView(eyes[0].view, t_s);
    head.position = eye_mean;
    heads_.push_back(head);
    if (heads_.size() > kHeadHistory) heads_.pop_front();
    std::vector<render::Frustum> selection;
    if (cull) {
        std::vector<glm::dmat4> views, projections;
        for (const EyeDraw& e : eyes) {
            views.push_back(e.view);
            projections.push_back(e.projection);
        }
        const std::vector<HeadSample> history(heads_.begin(), heads_.end());
        selection = widenedFrusta(views, projections, predictedMotion(history, kSelectionLookahead_s));
    }
    last_view_ = SourceView{std::move(selection), eye_mean, point_budget, arena_.bytes_bound, focus_};
    if (cells.empty()) return;
    std::vector<core::Bounds> boxes(cells.size());
    std::vector<std::size_t> sizes(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) {
        boxes[i] = cells[i].bounds;
        sizes[i] = chunks_.available(i);
    }
    const std::vector<bool> visible = cull ? visibleInAny(frusta, boxes) : std::vector<bool>(boxes.size(), true);
    std::vector<double> importance(cells.size(), 0.0);
    std::vector<bool> focused(cells.size(), false);
    for (std::size_t i = 0; i < cells.size(); ++i) {
        if (visible[i]) importance[i] = std::max(screenImportance(boxes[i], eye_mean), 1e-12);
        focused[i] = visible[i] && focus_.touches(boxes[i]);
    }
    plan_ = allocateFocusedBudget(importance, sizes, focused, point_budget);
    for (std::size_t i = 0; i < plan_.size(); ++i) {
        planned_points_ += plan_[i];
        if (focused[i]) focus_points_ += plan_[i];
        if (plan_[i] > 0) chunk_used_[cells[i].chunk] = tick_;  // drawn: recently used
    }
}

void PointRenderer::setStyleUniforms(const render::Program& program, const ViewStyle& style,
                                     const CutVolume& cut) const {
    program.use();
    const core::Bounds bounds = bodyBounds();
    glUniform1f(program.uniform("u_z_min"), bounds.empty() ? 0.0f : float(bounds.lo.z));
    glUniform1f(program.uniform("u_z_max"), bounds.empty() ? 1.0f : float(bounds.hi.z));
    glUniform1i(program.uniform("u_colour_mode"), static_cast<int>(shownColourMode(style.colour, colourSources())));
    glUniform1f(program.uniform("u_above_ground_max_m"), aboveGroundMax());
    glUniform1i(program.uniform("u_attributes"), fields_.height_above_ground ? 0 : 1);
    glUniform1i(program.uniform("u_ground_by_label"), fields_.height_above_ground && from_elsewhere_ ? 1 : 0);
    glUniform1i(program.uniform("u_terrain_on"), terrain_ ? 1 : 0);
    glUniform1f(program.uniform("u_terrain_cell"), terrain_ ? float(terrain_->cell) : 1.0f);
    // In the cloud's height unit, as the terrain and the heights are (US survey feet: 1.64).
    glUniform1f(program.uniform("u_ground_threshold_m"), float(kGroundThreshold_m / height_unit_m_));
    glUniform1i(program.uniform("u_terrain"), kTerrainTextureUnit);
    if (terrain_) glBindTextureUnit(kTerrainTextureUnit, terrain_->texture);
    glBindTextureUnit(kJetTextureUnit, jetTexture(style.jet_entries));
    glUniform1i(program.uniform("u_jet"), kJetTextureUnit);
    glUniform1f(program.uniform("u_size_px"), style.point_size_px);
    glUniform1i(program.uniform("u_attenuate"), style.attenuate ? 1 : 0);
    glUniform1f(program.uniform("u_cut_radius"), cut.enabled ? float(cut.radius_m) : -1.0f);
}

void PointRenderer::rasterizePoints(const EyeDraw& eye, std::span<const DrawnCell> drawn, const CutVolume& cut) const {
    glEnable(GL_PROGRAM_POINT_SIZE);
    glBindVertexArray(chunks_.vao());
    glUniformMatrix4fv(points_.uniform("u_projection"), 1, GL_FALSE, &glm::mat4(eye.projection)[0][0]);
    const GLint u_model_view = points_.uniform("u_model_view");
    const GLint u_chunk_z = points_.uniform("u_chunk_z");
    const GLint u_cut_centre = points_.uniform("u_cut_centre");
    const GLint u_chunk_grid = points_.uniform("u_chunk_grid_m");
    const auto& cells = chunks_.cells();
    std::size_t bound_chunk = SIZE_MAX;
    for (const DrawnCell& d : drawn) {
        const render::PointChunks::Cell& c = cells[d.cell];
        const glm::mat4 mv = chunkModelView(eye.view, c.centre);
        glUniformMatrix4fv(u_model_view, 1, GL_FALSE, &mv[0][0]);
        glUniform1f(u_chunk_z, float(c.centre.z));
        const glm::vec2 grid = gridOffset(c.centre);
        glUniform2f(u_chunk_grid, grid.x, grid.y);
        if (cut.enabled) {  // relative to the cell's centre, like its points
            const glm::vec3 rel(cut.centre_local - c.centre);
            glUniform3f(u_cut_centre, rel.x, rel.y, rel.z);
        }
        chunks_.drawCell(d.cell, d.count, bound_chunk);
    }
}

void PointRenderer::rasterizeCompute(const render::Program& splat, const EyeTarget& target, const EyeDraw& eye,
                                     std::span<const DrawnCell> drawn, const CutVolume& cut) const {
    if (target.width > raster_width_ || target.height > raster_height_) {
        if (raster_depth_) glDeleteTextures(1, &raster_depth_);
        if (raster_colour_) glDeleteTextures(1, &raster_colour_);
        raster_width_ = std::max(raster_width_, target.width);
        raster_height_ = std::max(raster_height_, target.height);
        for (GLuint* t : {&raster_depth_, &raster_colour_}) {
            glCreateTextures(GL_TEXTURE_2D, 1, t);
            glTextureStorage2D(*t, 1, GL_R32UI, raster_width_, raster_height_);
        }
        if (!raster_cells_) glCreateBuffers(1, &raster_cells_);
    }
    // The last eye's passes and resolve are done with the images before they are cleared.
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    // Both start at the largest value: each pass keeps an atomic minimum.
    const GLuint empty = 0xFFFFFFFFu;
    glClearTexImage(raster_depth_, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &empty);
    glClearTexImage(raster_colour_, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &empty);
    // The cell table, each chunk's drawn cells together (cells of a chunk are contiguous).
    struct GpuCell {
        float model_view[16];
        float cut_centre[4];
        std::uint32_t range[4];
        float grid[4];
    };
    static_assert(sizeof(GpuCell) == 112);
    struct Group {
        std::size_t chunk = 0, first = 0, cells = 0, points = 0;
    };
    const auto& cells = chunks_.cells();
    std::vector<GpuCell> table;
    std::vector<Group> groups;
    table.reserve(drawn.size());
    for (const DrawnCell& d : drawn) {
        const render::PointChunks::Cell& c = cells[d.cell];
        if (groups.empty() || groups.back().chunk != c.chunk) groups.push_back({c.chunk, table.size(), 0, 0});
        Group& g = groups.back();
        GpuCell gc{};
        const glm::mat4 mv = chunkModelView(eye.view, c.centre);
        std::memcpy(gc.model_view, &mv[0][0], sizeof gc.model_view);
        const glm::vec3 rel(cut.centre_local - c.centre);
        gc.cut_centre[0] = rel.x;
        gc.cut_centre[1] = rel.y;
        gc.cut_centre[2] = rel.z;
        gc.cut_centre[3] = float(c.centre.z);
        gc.range[0] = static_cast<std::uint32_t>(c.first);
        gc.range[1] = static_cast<std::uint32_t>(d.count);
        gc.range[2] = static_cast<std::uint32_t>(g.points);
        const glm::vec2 grid = gridOffset(c.centre);
        gc.grid[0] = grid.x;
        gc.grid[1] = grid.y;
        table.push_back(gc);
        ++g.cells;
        g.points += d.count;
    }
    if (!table.empty()) {
        glNamedBufferData(raster_cells_, static_cast<GLsizeiptr>(table.size() * sizeof(GpuCell)), table.data(),
                          GL_STREAM_DRAW);
        glUniformMatrix4fv(splat.uniform("u_projection"), 1, GL_FALSE, &glm::mat4(eye.projection)[0][0]);
        glUniform2f(splat.uniform("u_image_size"), float(target.width), float(target.height));
        glBindImageTexture(0, raster_depth_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
        glBindImageTexture(1, raster_colour_, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, raster_cells_);
        const GLint u_pass = splat.uniform("u_pass"), u_cell_first = splat.uniform("u_cell_first");
        const GLint u_cell_count = splat.uniform("u_cell_count"), u_total = splat.uniform("u_total");
        constexpr std::size_t kGroupSize = 128, kMaxGroups = 4096;  // grid-stride beyond
        for (int pass = 0; pass < 2; ++pass) {
            glUniform1i(u_pass, pass);
            for (const Group& g : groups) {
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, chunks_.buffer(g.chunk));
                glUniform1ui(u_cell_first, static_cast<GLuint>(g.first));
                glUniform1ui(u_cell_count, static_cast<GLuint>(g.cells));
                glUniform1ui(u_total, static_cast<GLuint>(g.points));
                glDispatchCompute(static_cast<GLuint>(std::min(kMaxGroups, (g.points + kGroupSize - 1) / kGroupSize)),
                                  1, 1);
            }
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            if (pass == 0) passMark();  // the depth pass ends
        }
    } else {
        passMark();
    }
}

void PointRenderer::depthInto(const EyeTarget& target) const {
    if (!raster_last_ || !raster_depth_) return;
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glViewport(0, 0, target.width, target.height);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    depth_.use();
    glBindImageTexture(0, raster_depth_, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glBindVertexArray(empty_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(0);
    glUseProgram(0);
    render::logGl("PointRenderer::depthInto", __FILE__, __LINE__);
}

DrawStats PointRenderer::drawEye(const EyeTarget& target, const EyeDraw& eye, const ViewStyle& style, ViewMode mode,
                                 GLuint out_fbo, int x, int y, int w, int h, const CutVolume& cut) const {
    DrawStats stats;
    const glm::vec3 background(0.06f, 0.07f, 0.09f);
    // 1. points into the eye target (GL_POINTS) or the compute rasteriser's images
    const bool compute = style.rasterizer == Rasterizer::Compute;
    raster_last_ = compute;
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    if (!compute) {
        glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
        glViewport(0, 0, target.width, target.height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glClearColor(background.r, background.g, background.b, 1.0f);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    const auto frustum = render::Frustum::fromMatrix(eye.projection * eye.view);
    const auto& cells = chunks_.cells();
    const bool planned = plan_valid_ && plan_.size() == cells.size();
    const bool cull = !planned || plan_cull_;
    std::vector<DrawnCell> drawn;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const std::size_t have = chunks_.available(i);
        if (have == 0) continue;
        const std::size_t n = planned ? std::min(have, plan_[i]) : have;
        if (n == 0 || (cull && !frustum.intersects(cells[i].bounds))) {
            ++stats.chunks_culled;
            continue;
        }
        drawn.push_back({i, n});
        stats.points_drawn += n;
        ++stats.chunks_drawn;
    }
    passMark();  // the points start
    if (compute) {
        const render::Program& splat = subgroupReduction() ? splat_subgroup_ : splat_;
        setStyleUniforms(splat, style, cut);
        rasterizeCompute(splat, target, eye, drawn, cut);
    } else {
        setStyleUniforms(points_, style, cut);
        rasterizePoints(eye, drawn, cut);
        passMark();  // no colour pass: it takes no time
    }
    passMark();  // the colour pass ends
    // 2. resolve (eye-dome lighting) into the output
    glBindFramebuffer(GL_FRAMEBUFFER, out_fbo);
    glViewport(x, y, w, h);
    glDisable(GL_DEPTH_TEST);
    resolve_.use();
    glBindVertexArray(empty_vao_);
    glBindTextureUnit(0, target.colour);
    glBindTextureUnit(1, target.depth);
    glUniform1i(resolve_.uniform("u_colour"), 0);
    glUniform1i(resolve_.uniform("u_depth"), 1);
    glUniform1i(resolve_.uniform("u_from_images"), compute ? 1 : 0);
    glUniform2i(resolve_.uniform("u_size"), target.width, target.height);
    if (compute) {
        glBindImageTexture(0, raster_depth_, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
        glBindImageTexture(1, raster_colour_, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    }
    glUniform4f(resolve_.uniform("u_viewport"), float(x), float(y), float(w), float(h));
    glUniform1i(resolve_.uniform("u_edl"), style.eye_dome ? 1 : 0);
    glUniform1f(resolve_.uniform("u_strength"), style.edl_strength);
    glUniform1f(resolve_.uniform("u_near"), float(eye.near_m));
    glUniform1f(resolve_.uniform("u_far"), float(eye.far_m));
    glUniform3f(resolve_.uniform("u_background"), background.r, background.g, background.b);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    // 3. the mode indicator, small near the top edge (visible in the HMD and the mirror,
    // away from the middle of the view where the target often is)
    const char* word = mode == ViewMode::Automatic ? "AUTOMATIC" : "FREE";
    std::array<int, 12> text{};
    const int length = static_cast<int>(std::strlen(word));
    for (int i = 0; i < length; ++i) text[i] = static_cast<int>(std::strchr(kGlyphs, word[i]) - kGlyphs);
    const PixelRect plate_rect = modePlateRect(w, h, length);  // the panels keep off it
    const float cell = plate_rect.h / 9.0f, plate_w = plate_rect.w, plate_h = plate_rect.h;
    const float px0 = float(x) + plate_rect.x, py0 = float(y + h) - plate_rect.y - plate_h;
    auto ndc_x = [&](float p) { return (p - x) / w * 2.0f - 1.0f; };
    auto ndc_y = [&](float p) { return (p - y) / h * 2.0f - 1.0f; };
    indicator_.use();
    glUniform4f(indicator_.uniform("u_rect_ndc"), ndc_x(px0), ndc_y(py0), ndc_x(px0 + plate_w), ndc_y(py0 + plate_h));
    const glm::vec3 plate = mode == ViewMode::Automatic ? glm::vec3(0.0f, 0.62f, 0.9f) : glm::vec3(1.0f, 0.6f, 0.0f);
    glUniform3f(indicator_.uniform("u_plate"), plate.r, plate.g, plate.b);
    glUniform2f(indicator_.uniform("u_origin_px"), px0, py0);
    glUniform1f(indicator_.uniform("u_cell_px"), cell);
    glUniform1iv(indicator_.uniform("u_text"), 12, text.data());
    glUniform1i(indicator_.uniform("u_length"), length);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
    glUseProgram(0);
    passMark();  // the resolve and the indicator end
    render::logGl("PointRenderer::drawEye", __FILE__, __LINE__);
    return stats;
}

}  // namespace viewer
