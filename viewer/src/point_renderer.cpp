// viewer/src/point_renderer.cpp: streamed, camera-relative point drawing with eye-dome
// lighting for the immersive viewer (paper §IV-A; the jet map is the paper's §III-C one,
// core::jetTable, the generator's table). The GLSL lives in shaders/.
#include "point_renderer.hpp"

#include <core/jet.hpp>
#include <render/orbit_camera.hpp>
#include <shaders/shaders.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace viewer {

namespace {

struct GpuPoint {
    float x, y, z;
    std::uint32_t rgb;   // 0xLLRRGGBB (L = label): bytes B, G, R, L -> read as GL_BGRA
    float above_ground_m;   // core::CloudPoint::height_above_ground_m (0 without the field)
};
static_assert(sizeof(GpuPoint) == 20);

// A, U, T, O, M, I, C, F, R, E
constexpr std::array<int, 70> kFont = {
    0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001,   // A
    0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110,   // U
    0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100,   // T
    0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110,   // O
    0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001,   // M
    0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110,   // I
    0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110,   // C
    0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000,   // F
    0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001,   // R
    0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111,   // E
};
constexpr const char* kGlyphs = "AUTOMICFRE";

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
    : points_("viewer points",
              {{GL_VERTEX_SHADER, shaders::viewer_points_vert, shaders::viewer_points_vert_files},
               {GL_FRAGMENT_SHADER, shaders::vertex_colour_frag, shaders::vertex_colour_frag_files}}),
      resolve_("viewer eye-dome resolve",
               {{GL_VERTEX_SHADER, shaders::fullscreen_triangle_vert, shaders::fullscreen_triangle_vert_files},
                {GL_FRAGMENT_SHADER, shaders::eye_dome_resolve_frag, shaders::eye_dome_resolve_frag_files}}),
      indicator_("viewer mode indicator",
                 {{GL_VERTEX_SHADER, shaders::mode_indicator_vert, shaders::mode_indicator_vert_files},
                  {GL_FRAGMENT_SHADER, shaders::mode_indicator_frag, shaders::mode_indicator_frag_files}}) {
    glCreateVertexArrays(1, &vao_);
    glEnableVertexArrayAttrib(vao_, 0);
    glVertexArrayAttribFormat(vao_, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao_, 0, 0);
    glEnableVertexArrayAttrib(vao_, 1);
    glVertexArrayAttribFormat(vao_, 1, GL_BGRA, GL_UNSIGNED_BYTE, GL_TRUE, 12);
    glVertexArrayAttribBinding(vao_, 1, 0);
    glEnableVertexArrayAttrib(vao_, 2);
    glVertexArrayAttribFormat(vao_, 2, 1, GL_FLOAT, GL_FALSE, 16);
    glVertexArrayAttribBinding(vao_, 2, 0);
    glCreateVertexArrays(1, &empty_vao_);
    indicator_.use();
    glUniform1iv(indicator_.uniform("u_font"), 70, kFont.data());
    GL_CHECK(glUseProgram(0));
}

PointRenderer::~PointRenderer() {
    if (jet_texture_) glDeleteTextures(1, &jet_texture_);
    for (auto& c : chunks_)
        if (c.buffer) glDeleteBuffers(1, &c.buffer);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (empty_vao_) glDeleteVertexArrays(1, &empty_vao_);
}

GLuint PointRenderer::jetTexture(int entries) const {
    entries = std::clamp(entries, 2, 256);   // options.cpp validates; never index past it
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

std::size_t PointRenderer::stream(CloudFeed& feed, std::size_t budget_points, std::vector<core::CloudPoint>* keep) {
    for (auto& item : feed.take()) {
        std::vector<core::CloudPoint>& points = item.points;
        if (points.empty()) continue;
        if (keep) keep->insert(keep->end(), points.begin(), points.end());
        // LOD order once per chunk, at arrival: spatial cells, each shuffled (lod.hpp); done
        // by the producer's thread when the feed has it enabled, else here.
        const std::vector<LodCell> lod = item.cells.empty() ? buildLodOrder(points) : std::move(item.cells);
        Chunk chunk;
        chunk.capacity = points.size();
        glCreateBuffers(1, &chunk.buffer);
        glNamedBufferStorage(chunk.buffer, static_cast<GLsizeiptr>(chunk.capacity * sizeof(GpuPoint)),
                             nullptr, GL_DYNAMIC_STORAGE_BIT);
        if (!render::logGl("glNamedBufferStorage (point chunk)", __FILE__, __LINE__)) {
            glDeleteBuffers(1, &chunk.buffer);
            continue;   // out of GPU memory: show what fits
        }
        const std::size_t first_cell = cells_.size();
        for (const LodCell& l : lod) {
            cells_.push_back({chunks_.size(), l.first, l.count, l.bounds.centre(), l.bounds});
            bounds_.extend(l.bounds);
        }
        pending_points_ += points.size();
        pending_.push_back({std::move(points), 0, chunks_.size(), first_cell});
        chunks_.push_back(chunk);
    }
    std::size_t uploaded = 0;
    std::vector<GpuPoint> staging;
    while (!pending_.empty() && uploaded < budget_points) {
        Pending& job = pending_.front();
        Chunk& chunk = chunks_[job.chunk];
        const std::size_t n = std::min(budget_points - uploaded, job.points.size() - job.next);
        staging.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t k = job.next + i;
            while (k >= cells_[job.cell].first + cells_[job.cell].size) ++job.cell;
            const auto& p = job.points[k];
            const glm::dvec3 rel = glm::dvec3(p.position) - cells_[job.cell].centre;
            staging[i] = {float(rel.x), float(rel.y), float(rel.z),
                          (p.rgb & 0xFFFFFFu) | (std::uint32_t(p.label) << 24), p.height_above_ground_m};
            above_ground_max_m_ = std::max(above_ground_max_m_, p.height_above_ground_m);
        }
        glNamedBufferSubData(chunk.buffer, static_cast<GLintptr>(chunk.count * sizeof(GpuPoint)),
                             static_cast<GLsizeiptr>(n * sizeof(GpuPoint)), staging.data());
        chunk.count += n;
        job.next += n;
        uploaded += n;
        pending_points_ -= n;
        if (job.next == job.points.size()) pending_.pop_front();
    }
    uploaded_ += uploaded;
    if (uploaded) render::logGl("glNamedBufferSubData (point chunk)", __FILE__, __LINE__);
    return uploaded;
}

void PointRenderer::planFrame(std::span<const EyeDraw> eyes, std::size_t point_budget, bool cull) {
    plan_cull_ = cull;
    plan_.assign(cells_.size(), 0);
    planned_points_ = 0;
    plan_valid_ = true;
    if (cells_.empty() || eyes.empty()) return;
    std::vector<render::Frustum> frusta;
    glm::dvec3 eye_mean(0.0);
    for (const EyeDraw& e : eyes) {
        frusta.push_back(render::Frustum::fromMatrix(e.projection * e.view));
        eye_mean += glm::dvec3(glm::inverse(e.view)[3]) / double(eyes.size());
    }
    std::vector<core::Bounds> boxes(cells_.size());
    std::vector<std::size_t> sizes(cells_.size());
    for (std::size_t i = 0; i < cells_.size(); ++i) {
        boxes[i] = cells_[i].bounds;
        sizes[i] = available(cells_[i]);
    }
    const std::vector<bool> visible = cull ? visibleInAny(frusta, boxes) : std::vector<bool>(boxes.size(), true);
    std::vector<double> importance(cells_.size(), 0.0);
    for (std::size_t i = 0; i < cells_.size(); ++i)
        if (visible[i]) importance[i] = std::max(screenImportance(boxes[i], eye_mean), 1e-12);
    plan_ = allocateBudget(importance, sizes, point_budget);
    for (std::size_t n : plan_) planned_points_ += n;
}

DrawStats PointRenderer::drawEye(const EyeTarget& target, const EyeDraw& eye, const ViewStyle& style,
                                 ViewMode mode, GLuint out_fbo, int x, int y, int w, int h,
                                 const CutVolume& cut) const {
    DrawStats stats;
    const glm::vec3 background(0.06f, 0.07f, 0.09f);
    // 1. points into the eye target
    glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
    glViewport(0, 0, target.width, target.height);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearColor(background.r, background.g, background.b, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_PROGRAM_POINT_SIZE);
    points_.use();
    glBindVertexArray(vao_);
    glUniformMatrix4fv(points_.uniform("u_projection"), 1, GL_FALSE,
                       &glm::mat4(eye.projection)[0][0]);
    glUniform1f(points_.uniform("u_z_min"), bounds_.empty() ? 0.0f : float(bounds_.lo.z));
    glUniform1f(points_.uniform("u_z_max"), bounds_.empty() ? 1.0f : float(bounds_.hi.z));
    glUniform1i(points_.uniform("u_colour_mode"), static_cast<int>(style.colour));
    glUniform1f(points_.uniform("u_above_ground_max_m"), above_ground_max_m_);
    glBindTextureUnit(kJetTextureUnit, jetTexture(style.jet_entries));
    glUniform1i(points_.uniform("u_jet"), kJetTextureUnit);
    glUniform1f(points_.uniform("u_size_px"), style.point_size_px);
    glUniform1i(points_.uniform("u_attenuate"), style.attenuate ? 1 : 0);
    const GLint u_model_view = points_.uniform("u_model_view");
    const GLint u_chunk_z = points_.uniform("u_chunk_z");
    const GLint u_cut_centre = points_.uniform("u_cut_centre");
    glUniform1f(points_.uniform("u_cut_radius"), cut.enabled ? float(cut.radius_m) : -1.0f);
    const auto frustum = render::Frustum::fromMatrix(eye.projection * eye.view);
    const bool planned = plan_valid_ && plan_.size() == cells_.size();
    const bool cull = !planned || plan_cull_;
    std::size_t bound_chunk = chunks_.size();
    for (std::size_t i = 0; i < cells_.size(); ++i) {
        const Cell& c = cells_[i];
        const std::size_t have = available(c);
        if (have == 0) continue;
        const std::size_t n = planned ? std::min(have, plan_[i]) : have;
        if (n == 0 || (cull && !frustum.intersects(c.bounds))) {
            ++stats.chunks_culled;
            continue;
        }
        const glm::mat4 mv = chunkModelView(eye.view, c.centre);
        glUniformMatrix4fv(u_model_view, 1, GL_FALSE, &mv[0][0]);
        glUniform1f(u_chunk_z, float(c.centre.z));
        if (cut.enabled) {   // relative to the cell's centre, like its points
            const glm::vec3 rel(cut.centre_local - c.centre);
            glUniform3f(u_cut_centre, rel.x, rel.y, rel.z);
        }
        if (bound_chunk != c.chunk) {
            glVertexArrayVertexBuffer(vao_, 0, chunks_[c.chunk].buffer, 0, sizeof(GpuPoint));
            bound_chunk = c.chunk;
        }
        glDrawArrays(GL_POINTS, static_cast<GLint>(c.first), static_cast<GLsizei>(n));
        stats.points_drawn += n;
        ++stats.chunks_drawn;
    }
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
    for (int i = 0; i < length; ++i)
        text[i] = static_cast<int>(std::strchr(kGlyphs, word[i]) - kGlyphs);
    const float cell = std::max(1.0f, std::floor(float(h) / 300.0f));
    const float plate_w = (length * 6 + 1) * cell, plate_h = 9 * cell;
    const float px0 = x + std::floor((w - plate_w) / 2), py0 = y + h - plate_h - std::floor(h * 0.2f);
    auto ndc_x = [&](float p) { return (p - x) / w * 2.0f - 1.0f; };
    auto ndc_y = [&](float p) { return (p - y) / h * 2.0f - 1.0f; };
    indicator_.use();
    glUniform4f(indicator_.uniform("u_rect_ndc"), ndc_x(px0), ndc_y(py0), ndc_x(px0 + plate_w),
                ndc_y(py0 + plate_h));
    const glm::vec3 plate = mode == ViewMode::Automatic ? glm::vec3(0.0f, 0.62f, 0.9f)
                                                        : glm::vec3(1.0f, 0.6f, 0.0f);
    glUniform3f(indicator_.uniform("u_plate"), plate.r, plate.g, plate.b);
    glUniform2f(indicator_.uniform("u_origin_px"), px0, py0);
    glUniform1f(indicator_.uniform("u_cell_px"), cell);
    glUniform1iv(indicator_.uniform("u_text"), 12, text.data());
    glUniform1i(indicator_.uniform("u_length"), length);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
    glUseProgram(0);
    render::logGl("PointRenderer::drawEye", __FILE__, __LINE__);
    return stats;
}

}  // namespace viewer
