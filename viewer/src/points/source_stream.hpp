// viewer/src/points/source_stream.hpp: the frame loop's side of a point source: polls it once a
// frame, streams what is resident to the GPU within the per-frame upload budget, builds
// the per-node pick indexes on a worker thread once everything is on the GPU (and again,
// reusing the indexes of nodes that stayed, whenever a source that chooses its nodes
// changed what is resident), and tracks when the cloud is whole (for the orbit's centre
// and a script's loaded+N). It also holds the point budget the frames draw with: the
// user's, or the GPU class's default, lowered and raised again by the adaptive budget
// (viewer/point_budget.hpp) as frames run late or early.
#pragma once
#include "points/point_renderer.hpp"
#include "run_log.hpp"

#include <viewer/pick_index.hpp>
#include <viewer/point_budget.hpp>
#include <viewer/point_source.hpp>
#include <viewer/viewer.hpp>

#include <cstddef>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace viewer {

/// What changed in one update.
struct SourceEvents {
    bool picks_ready = false;  // picks() became available
    std::string load_error;    // the source failed (reported once)
};

class SourceStream {
  public:
    /// Makes the renderer (needs the GL context; throws core::Error on a shader error) with
    /// `options`' upload budget (--upload-mb as points when given, else --upload-budget),
    /// GPU arena bound and point budget: --point-budget, or when `point_budget_auto` the
    /// GPU class's default (GL_RENDERER / GL_VENDOR), recorded in `log`'s
    /// "point_budget_choice"; the rasterizer likewise (`rasterizer_auto`), in
    /// "rasterizer_choice".
    void start(const ViewerOptions& options, RunLog& log);
    /// The rasterizer start() chose: options.style's, or the GPU class's.
    Rasterizer rasterizer() const { return rasterizer_; }
    /// The point budget per eye frames draw with now (0 = unlimited).
    std::size_t pointBudget() const { return budget_points_; }
    /// After a counted frame: its cost (CPU + GPU ms spent on it) against the frame budget
    /// (ms) and the points it drew (both eyes); with the adaptive budget on, a new budget
    /// is logged as an event and used from the next frame. While the budget is measured
    /// (options.measure_budget), the frame feeds the measure instead, and its end sets the
    /// budget and rasterizer, logged and remembered for this GPU. Returns true when the
    /// rasterizer() for the next frame changed. Never throws.
    /// The budget is being measured (the frame loop then makes sure the GPU's time counts).
    bool measuring() const { return measure_.has_value(); }
    bool frameTimed(double cost_ms, double frame_budget_ms, std::size_t points_drawn, long frame, RunLog& log);
    /// This frame's figures for its run log record: the budget, the GPU arena, the upload,
    /// and for a source with a cache its resident bytes and nodes loaded / evicted since
    /// the last call.
    nlohmann::json frameFigures();
    /// Shows `source` from now on: a fresh renderer and no pick index.
    void reset(PointSource& source);
    /// One frame's streaming; `frame` is the frame count the loaded mark takes. Never throws.
    SourceEvents update(long frame, RunLog& log);

    PointSource& source() const { return *source_; }
    PointRenderer& renderer() { return *renderer_; }
    const PointRenderer& renderer() const { return *renderer_; }
    /// One index per node, null until every point arrived and is on the GPU.
    const std::shared_ptr<const PickSet>& picks() const { return picks_; }
    bool failed() const { return !error_.empty(); }
    /// The frame when the whole cloud was first on the GPU, -1 until then.
    long loadedSinceFrame() const { return loaded_since_frame_; }
    /// The cloud's bounds grew this update (the orbit centres on them) / will not any more.
    bool centreChanged() const { return centre_changed_; }
    bool centreFinal() const { return centre_final_; }
    /// The bounds the orbit centres on: the drawn points' once there are any, before that
    /// the source's roots' (empty until either is known).
    const core::Bounds& cloudBounds() const { return cloud_bounds_; }

  private:
    void applyBudget();
    /// The remembered choice for this GPU applied (true), or the measure started.
    bool recallBudget(const ViewerOptions& options, RunLog& log);
    void finishMeasure(double frame_budget_ms, long frame, RunLog& log);
    std::optional<BudgetMeasure> measure_;
    std::string gpu_name_;                // GL_RENDERER: what the remembered choice is keyed by
    std::filesystem::path budget_file_;   // where it is remembered; empty: nowhere (no cache folder)
    bool measure_budget_points_ = false;  // the measure sets the point budget / the rasterizer
    bool measure_rasterizer_ = false;
    bool adaptive_wanted_ = false;
    std::size_t budget_ = 0;  // points uploaded per frame at most
    std::size_t gpu_bytes_ = 0;
    std::size_t budget_points_ = 0;  // the point budget frames draw with
    Rasterizer rasterizer_ = Rasterizer::Points;
    std::optional<AdaptiveBudget> adaptive_;
    std::size_t last_loaded_ = 0, last_evicted_ = 0;  // the source's counts at the last frameFigures()
    bool quiet_ = false;
    double height_unit_m_ = 1.0;  // metres per unit of the cloud's heights
    std::string arena_warned_;    // the one warning of a full arena, once given
    PointSource* source_ = nullptr;
    std::unique_ptr<PointRenderer> renderer_;
    std::future<std::shared_ptr<const PickSet>> building_;
    /// A source that chooses its nodes: the pick set over its resident nodes, one index per
    /// node (kept while the node stays resident, so a rebuild indexes only the newcomers).
    struct NodePicks {
        std::shared_ptr<const PickSet> set;
        std::map<const PointNode*, std::shared_ptr<const PickIndex>> by_node;
    };
    std::future<NodePicks> rebuilding_;
    std::map<const PointNode*, std::shared_ptr<const PickIndex>> node_picks_;
    /// Each node's octree level, for a source that chooses its nodes (its tree is whole
    /// from the start): made once per source, not once per frame.
    std::map<const PointNode*, int> levels_;
    std::shared_ptr<const PickSet> picks_;
    std::string error_;
    long loaded_since_frame_ = -1;
    bool centre_changed_ = false, centre_final_ = false;
    core::Bounds cloud_bounds_;
    bool log_nodes_ = false;  // "first node resident" logged
};

}  // namespace viewer
