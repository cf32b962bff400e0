// viewer/src/source_stream.hpp: the frame loop's side of a point source: polls it once a
// frame, streams what is resident to the GPU within the per-frame upload budget, builds
// the per-node pick indexes on a worker thread once everything is on the GPU (and again,
// reusing the indexes of nodes that stayed, whenever a source that chooses its nodes
// changed what is resident), and tracks when the cloud is whole (for the orbit's centre
// and a script's loaded+N).
#pragma once
#include "point_renderer.hpp"
#include "run_log.hpp"

#include <viewer/pick_index.hpp>
#include <viewer/point_source.hpp>

#include <cstddef>
#include <future>
#include <map>
#include <memory>
#include <string>

namespace viewer {

/// What changed in one update.
struct SourceEvents {
    bool picks_ready = false;  // picks() became available
    std::string load_error;    // the source failed (reported once)
};

class SourceStream {
  public:
    /// Makes the renderer (needs the GL context; throws core::Error on a shader error).
    void start(std::size_t upload_points_per_frame);
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

  private:
    std::size_t budget_ = 0;
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
    std::shared_ptr<const PickSet> picks_;
    std::string error_;
    long loaded_since_frame_ = -1;
    bool centre_changed_ = false, centre_final_ = false;
    bool log_nodes_ = false;  // "first node resident" logged
};

}  // namespace viewer
