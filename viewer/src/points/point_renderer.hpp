// viewer/src/points/point_renderer.hpp: the viewer's point drawing: the resident nodes of a point
// source (viewer/point_source.hpp) streamed to the GPU in render::PointChunks (the storage
// the metric's splat renderer draws from too), camera-relative positions, file /
// height-jet / white / label / above-ground (the points' own heights or a bound terrain) /
// class / intensity / return colours, pixel or distance-attenuated point size, drawn with GL_POINTS
// or the compute rasterizer, eye-dome lighting, and the mode indicator drawn into every eye
// view.
#pragma once
#include <viewer/mode_controller.hpp>
#include <viewer/lod.hpp>
#include <viewer/motion_prediction.hpp>
#include <viewer/point_source.hpp>
#include <viewer/terrain_feed.hpp>
#include <viewer/viewer.hpp>

#include <core/frames.hpp>
#include <core/height_span.hpp>
#include <render/gl.hpp>
#include <render/point_chunks.hpp>
#include <render/shader.hpp>

#include <chrono>
#include <cstddef>
#include <deque>
#include <memory>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <span>
#include <utility>
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
    glm::dmat4 view{1.0};  // world(local)-to-eye, double
    glm::dmat4 projection{1.0};
    double near_m = 0.1, far_m = 20000.0;
};

/// The cutting volume: only points within radius_m of centre_local are drawn (a shader
/// test per point, so it follows live changes at no upload cost).
struct CutVolume {
    bool enabled = false;
    glm::dvec3 centre_local{0.0};
    double radius_m = 10.0;
};

struct DrawStats {
    std::size_t points_drawn = 0;
    std::size_t chunks_drawn = 0;   // cells drawn
    std::size_t chunks_culled = 0;  // cells with points on the GPU skipped (frustum or budget)
};

/// The GPU arena: the bytes the node buffers take (render::PointChunks::allocatedBytes,
/// exact), its bound and what moved in and out.
struct ArenaStats {
    std::size_t bytes = 0, bytes_bound = 0, bytes_peak = 0;  // bound 0: unlimited
    std::size_t nodes = 0;                                   // on the GPU now
    std::size_t nodes_added = 0, nodes_evicted = 0;          // so far (evicted: for room, still in RAM)
    std::size_t nodes_refused = 0;  // wanted, resident and not on the GPU: no room (last stream())
    std::size_t frame_nodes_added = 0, frame_nodes_evicted = 0, frame_upload_bytes = 0;  // last stream()
};

class PointRenderer {
  public:
    /// Compiles the programs; throws core::Error("shader: ...") (setup path).
    PointRenderer();
    ~PointRenderer();
    PointRenderer(const PointRenderer&) = delete;
    PointRenderer& operator=(const PointRenderer&) = delete;

    /// Follows `source`'s residency: a node evicted from RAM leaves the GPU; the nodes it
    /// wants (a source that chooses: its last selection, most important first; else every
    /// node) that are resident and not on the GPU get a chunk and a place in the upload
    /// queue, in that order. With a GPU bound, a node that does not fit first evicts the
    /// GPU copies of nodes the source does not want now, least recently drawn or wanted
    /// first (they stay in RAM and come back when wanted); if that is not enough it waits.
    /// Then uploads at most `budget_points` queued points, most important node first.
    /// Returns the number uploaded. Never throws.
    std::size_t stream(const PointSource& source, std::size_t budget_points);
    /// Bytes the node buffers may take on the GPU at most (0 = unlimited), never exceeded.
    void setGpuBytes(std::size_t bound);
    const ArenaStats& arena() const { return arena_; }
    /// The points per eye planFrame uses from now on instead of the budget it is handed
    /// (an adaptive or GPU-class budget the frame loop chose); none: the one handed.
    void setPointBudget(std::optional<std::size_t> budget) { point_budget_ = budget; }
    const std::optional<std::size_t>& pointBudget() const { return point_budget_; }
    /// Points on the GPU / waiting in CPU memory.
    std::size_t uploadedPoints() const { return chunks_.uploadedPoints(); }
    std::size_t pendingPoints() const { return pending_points_; }
    /// Bounds (local frame) of everything received so far.
    const core::Bounds& bounds() const { return chunks_.bounds(); }
    /// bounds() with the heights of its body: a few stray returns (birds, clouds, multipath)
    /// parted from the rest by a wide empty gap left out (core::HeightSpan, a gap of at
    /// least core::kStrayGap_m). The height colours span it, and the camera centres on it.
    core::Bounds bodyBounds() const;
    /// Metres per unit of the cloud's heights (its CRS's), for core::kStrayGap_m; before
    /// any upload.
    void setHeightUnit(double metres);

    /// The ground's height under every point for the above-ground colours from now on:
    /// `terrain` (world coordinates) taken into the frame of `origin` (the source's) and
    /// uploaded as a texture the shaders sample bilinearly; the colour range's top becomes
    /// the highest height above it among `source`'s resident points and those uploaded
    /// later. Points less than kGroundThreshold_m above it are ground (white). Never throws.
    void setTerrain(const ViewTerrain& terrain, const glm::dvec3& origin, const PointSource& source);
    bool hasTerrain() const { return terrain_.has_value(); }
    /// The height above the bound terrain of a point at `local` (bilinear, as the shaders
    /// sample it); none without a terrain.
    std::optional<double> heightAboveTerrain(const glm::dvec3& local) const;
    /// The top of the above-ground colours' range: the highest height above ground seen so
    /// far (above the bound terrain when there is one, else the points' own), stray
    /// returns left out as bodyBounds() leaves them out.
    float aboveGroundMax() const { return terrain_ ? terrain_top_m_ : above_ground_top_m_; }
    /// What the streamed cloud can be coloured by (its fields as the source reports them
    /// at the last stream(), and whether a terrain is bound).
    ColourSources colourSources() const;
    /// A point less than this above a bound terrain is ground: the class threshold of the
    /// generator's SMRF and CSF (sim/ground.hpp), in metres (the shaders get it in the
    /// cloud's height unit).
    static constexpr float kGroundThreshold_m = 0.5f;

    /// Picks what this frame draws: cells outside the union of `eyes`' frusta get
    /// nothing (when `cull`); the others share `point_budget` points per eye (0 = unlimited)
    /// by screen-space importance seen from the eyes' mean position, as prefixes of their
    /// LOD order. Both eyes then draw the same points (no binocular flicker). Without a call,
    /// drawEye draws every uploaded point of every cell in its frustum. Never throws.
    void planFrame(std::span<const EyeDraw> eyes, std::size_t point_budget, bool cull = true);
    /// What the operator works on (the pointer's hit, the designation, the cutting volume):
    /// from the next planFrame its cells are drawn whole whatever the point budget and the
    /// other cells share what is left, and the view handed to the source carries it (its
    /// nodes are loaded first).
    void setFocus(LodFocus focus) { focus_ = std::move(focus); }
    const LodFocus& focus() const { return focus_; }
    /// Points the last plan gives the focused cells (within plannedPoints()).
    std::size_t focusPoints() const { return focus_points_; }
    /// Points the last plan draws per eye at most (before each eye's own frustum test).
    std::size_t plannedPoints() const { return planned_points_; }
    /// The eyes and budget of the last planFrame (a point source chooses its nodes by it):
    /// with culling, the eyes' frusta and the same moved by the head's predicted motion over
    /// kSelectionLookahead_s (motion_prediction.hpp), so what comes into view is on its way.
    const std::optional<SourceView>& lastView() const { return last_view_; }
    std::size_t cellCount() const { return chunks_.cells().size(); }

    /// Draws the cloud into `target` (cleared; with the compute rasterizer into the
    /// renderer's own images instead, and `target` is left as it was), then resolves it with
    /// eye-dome lighting (if on) into the framebuffer `out_fbo` at viewport (x, y, w, h), then the mode indicator
    /// (small, near the top edge). Points outside an enabled `cut` are not drawn.
    DrawStats drawEye(const EyeTarget& target, const EyeDraw& eye, const ViewStyle& style, ViewMode mode,
                      GLuint out_fbo, int x, int y, int w, int h, const CutVolume& cut = {}) const;

    /// Whether the compute rasteriser reduces equal pixels within a subgroup before its
    /// atomics (shaders/include/viewer_points_splat.glsl): available where the context has
    /// GL_KHR_shader_subgroup (basic, vote, arithmetic in compute), on unless turned off.
    /// The images are the same bits either way; only the time differs.
    bool subgroupAvailable() const { return splat_subgroup_.id() != 0; }
    void setSubgroupReduction(bool on) { subgroup_on_ = on; }
    bool subgroupReduction() const { return subgroup_on_ && subgroupAvailable(); }

    /// GPU time of the passes of the drawEye calls since the last takePassTimes(), from
    /// timestamp queries around them (only while on: reading them waits for the GPU, which
    /// a benchmark can afford and a frame loop cannot). `raster_ms`: GL_POINTS, or the
    /// compute rasteriser's depth pass; `colour_ms`: its colour pass (0 with GL_POINTS);
    /// `resolve_ms`: eye-dome lighting and the indicator.
    struct PassTimes {
        double raster_ms = 0.0, colour_ms = 0.0, resolve_ms = 0.0;
        int eyes = 0;  // drawEye calls measured
    };
    void setPassTiming(bool on);
    /// Sums the passes' times since the last call (waits for their queries). Never throws.
    PassTimes takePassTimes();

    /// Leaves in `target`'s depth the points' depth of the last drawEye into it, as
    /// GL_POINTS leaves it (1 where no point is): with the compute rasterizer a full-screen
    /// pass writes it from the raster images, which still hold that eye (call it before the
    /// next drawEye); with GL_POINTS it is there already. For an OpenXR depth layer.
    void depthInto(const EyeTarget& target) const;

  private:
    /// A cell drawEye draws this eye: its index and how many of its points.
    struct DrawnCell {
        std::size_t cell = 0, count = 0;
    };
    /// The style's uniforms shared by the points' vertex stage and the compute rasteriser
    /// (shaders/include/viewer_point_style.glsl).
    void setStyleUniforms(const render::Program& program, const ViewStyle& style, const CutVolume& cut) const;
    /// `drawn` through GL_POINTS into the bound target.
    void rasterizePoints(const EyeDraw& eye, std::span<const DrawnCell> drawn, const CutVolume& cut) const;
    /// `drawn` through the two compute passes into the raster images (of at least
    /// `target`'s size), which the eye-dome resolve then reads instead of `target`.
    void rasterizeCompute(const render::Program& splat, const EyeTarget& target, const EyeDraw& eye,
                          std::span<const DrawnCell> drawn, const CutVolume& cut) const;
    /// The jet table (core::jetTable(entries)) as a 1D RGBA8 texture, made on first use
    /// and again when `entries` changes. Never throws (a GL error is logged).
    GLuint jetTexture(int entries) const;
    static constexpr GLuint kJetTextureUnit = 2;  // units 0 and 1: the resolve's inputs
    static constexpr GLuint kTerrainTextureUnit = 3;
    /// A bound terrain in the local frame: cell (i, j) at (x0 + i cell, y0 + j cell).
    struct LocalTerrain {
        double x0 = 0.0, y0 = 0.0, cell = 1.0;
        int nx = 0, ny = 0;
        std::vector<float> z;  // local heights, row j at j * nx
        GLuint texture = 0;
    };
    /// A cell centre's horizontal offset from the bound terrain's grid origin (0 without one).
    glm::vec2 gridOffset(const glm::dvec3& centre) const {
        return terrain_ ? glm::vec2(float(centre.x - terrain_->x0), float(centre.y - terrain_->y0)) : glm::vec2(0.0f);
    }
    /// The highest height above the terrain among `points`, into terrain_max_m_.
    void raiseTerrainMax(std::span<const core::CloudPoint> points);

    struct Pending {
        std::shared_ptr<const NodePoints> node;  // kept until uploaded whole
        std::size_t next = 0;                    // first point not uploaded yet
        std::size_t chunk = 0;                   // the chunk in chunks_
        std::size_t rank = 0;                    // the node's place in the source's wanted order
    };
    /// A node newly resident: its chunk and its place in the upload queue.
    void addNode(const PointNode* node, std::shared_ptr<const NodePoints> points);
    void dropNode(const PointNode* node);
    /// Frees GPU room for `bytes` by evicting the nodes of `evictable`'s chunks from its
    /// front (taking them off it). False if the bound still leaves no room.
    struct Evictable {
        std::size_t chunk = 0;
        const PointNode* node = nullptr;
    };
    bool makeRoom(std::size_t bytes, std::deque<Evictable>& evictable);

    render::Program points_, resolve_, indicator_, splat_, depth_;
    /// The compute rasteriser with the subgroup reduction (no program: the context lacks
    /// GL_KHR_shader_subgroup's basic, vote and arithmetic operations in compute).
    render::Program splat_subgroup_;
    bool subgroup_on_ = true;
    // Pass timing: four timestamps a drawEye (before the points, after the depth pass,
    // after the colour pass, after the resolve), queries reused from a pool.
    bool pass_timing_ = false;
    mutable std::vector<GLuint> pass_queries_;  // the pool
    mutable std::size_t pass_used_ = 0;         // queries issued since the last takePassTimes
    /// The next timestamp query of the pool (made when it runs out), or 0 when not timing.
    GLuint passMark() const;
    render::PointChunks chunks_;
    GLuint empty_vao_ = 0;
    mutable GLuint jet_texture_ = 0;  // jetTexture()'s cache
    mutable int jet_entries_ = 0;
    // The compute rasteriser's nearest depth and colour (r32ui), at least the largest target
    // drawn so far, made on first use; and its per-eye cell table.
    mutable GLuint raster_depth_ = 0, raster_colour_ = 0, raster_cells_ = 0;
    mutable int raster_width_ = 0, raster_height_ = 0;
    mutable bool raster_last_ = false;                          // the last drawEye used the compute rasteriser
    std::unordered_map<const PointNode*, std::size_t> on_gpu_;  // node -> its chunk
    std::vector<long> chunk_used_;                              // per chunk id: tick last wanted or drawn
    std::vector<const PointNode*> chunk_node_;                  // per chunk id: its node (null: free)
    long tick_ = 0;                                             // stream() calls
    ArenaStats arena_;
    std::optional<std::size_t> point_budget_;
    std::deque<HeadSample> heads_;  // the last frames' head poses (selection look-ahead)
    std::chrono::steady_clock::time_point created_ = std::chrono::steady_clock::now();
    std::unordered_set<const PointNode*> no_room_;  // resident, but the GPU had no room
    std::vector<std::size_t> plan_;                 // per cell: points to draw (planFrame)
    bool plan_valid_ = false, plan_cull_ = true;
    std::size_t planned_points_ = 0, focus_points_ = 0;
    LodFocus focus_;
    std::optional<SourceView> last_view_;
    std::deque<Pending> pending_;
    std::size_t pending_points_ = 0;
    float above_ground_max_m_ = 0.0f;  // highest height above ground uploaded (colour range)
    // The heights uploaded, their heights above ground and above terrain_ (for the spans
    // without stray returns), and what those spans gave after the last upload.
    double height_unit_m_ = 1.0;
    core::HeightSpan z_span_{core::kStrayGap_m}, above_ground_span_{core::kStrayGap_m},
        terrain_span_{core::kStrayGap_m};
    core::HeightSpan::Span z_body_, above_ground_body_, terrain_body_;
    float above_ground_top_m_ = 0.0f, terrain_top_m_ = 0.0f;
    /// The bodies, above_ground_top_m_ and terrain_top_m_ from the spans.
    void updateSpans();
    /// The spans take their heights through HeightSpan::addSampled: every height outside
    /// the body found so far, one in kHeightSample inside it.
    static constexpr std::uint64_t kHeightSample = 8;
    core::CloudFields fields_;     // the source's, at the last stream()
    bool from_elsewhere_ = false;  // the source's fromElsewhere(), at the last stream()
    std::optional<LocalTerrain> terrain_;
    float terrain_max_m_ = 0.0f;  // highest height above terrain_ of the points seen
};

}  // namespace viewer
