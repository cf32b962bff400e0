// viewer/src/source_stream.cpp: a point source streamed into the renderer and the picking.
#include "source_stream.hpp"

#include <chrono>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace viewer {

void SourceStream::start(std::size_t upload_points_per_frame) {
    budget_ = upload_points_per_frame;
    renderer_ = std::make_unique<PointRenderer>();
}

void SourceStream::reset(PointSource& source) {
    building_ = {};  // waits for a build in flight
    rebuilding_ = {};
    node_picks_.clear();
    source_ = &source;
    renderer_ = std::make_unique<PointRenderer>();
    picks_.reset();
    error_.clear();
    loaded_since_frame_ = -1;
    log_nodes_ = false;
    centre_changed_ = centre_final_ = false;
}

SourceEvents SourceStream::update(long frame, RunLog& log) {
    SourceEvents ev;
    // A source that chooses its nodes sees the view the renderer planned last (one frame
    // behind: the frame draws what is resident and never waits for the choice).
    if (const std::optional<SourceView>& view = renderer_->lastView()) source_->select(*view);
    source_->poll();
    if (const std::optional<SourceStats> s = source_->stats()) {
        if (!log_nodes_ && s->nodes_loaded > 0) {
            log_nodes_ = true;
            log.event("first node resident");
        }
        log.set("source", nlohmann::json{{"kind", s->kind},
                                         {"nodes", s->nodes},
                                         {"nodes_resident", s->nodes_resident},
                                         {"nodes_loaded", s->nodes_loaded},
                                         {"nodes_evicted", s->nodes_evicted},
                                         {"nodes_failed", s->nodes_failed},
                                         {"wanted_points", s->wanted_points},
                                         {"cache_bytes", s->cache_bytes},
                                         {"resident_bytes", s->resident_bytes},
                                         {"resident_bytes_peak", s->resident_bytes_peak}});
    }
    renderer_->stream(*source_, budget_);
    const bool finished = source_->finished();
    const bool whole = finished && source_->error().empty() && renderer_->pendingPoints() == 0;
    const bool chooses = source_->stats().has_value();  // see below
    if (!chooses && !building_.valid() && !picks_ && whole && source_->pointsArrived() > 0) {
        std::vector<std::shared_ptr<const NodePoints>> nodes;
        for (const PointNode* node : allNodes(*source_))
            if (auto points = node->points(); points && !points->points.empty()) nodes.push_back(std::move(points));
        building_ = std::async(std::launch::async, [nodes = std::move(nodes)] {
            auto set = std::make_shared<PickSet>();
            for (const auto& n : nodes) set->add(std::make_shared<const PickIndex>(n->points));
            return std::shared_ptr<const PickSet>(std::move(set));
        });
    }
    if (building_.valid() && building_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        picks_ = building_.get();
        ev.picks_ready = true;
        log.event("picking ready: " + std::to_string(picks_->size()) + " points indexed");
    }
    // A source that chooses its nodes changes what is resident as the view moves: the
    // picks follow it once the renderer has caught up (the pointer searches what is drawn).
    if (chooses) {
        if (rebuilding_.valid() && rebuilding_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
            NodePicks r = rebuilding_.get();
            if (!picks_)
                log.event("picking ready: " + std::to_string(r.set->size()) + " points indexed in " +
                          std::to_string(r.set->nodes()) + " resident nodes");
            picks_ = std::move(r.set);
            node_picks_ = std::move(r.by_node);
            ev.picks_ready = true;
        }
        if (!rebuilding_.valid() && renderer_->pendingPoints() == 0) {
            std::vector<std::tuple<const PointNode*, std::shared_ptr<const NodePoints>, int>> resident;
            bool same = true;
            const std::map<const PointNode*, int> levels = nodeLevels(*source_);
            for (const PointNode* node : allNodes(*source_))
                if (auto points = node->points(); points && !points->points.empty()) {
                    same = same && node_picks_.contains(node);
                    resident.emplace_back(node, std::move(points), levels.at(node));
                }
            if (!same || resident.size() != node_picks_.size())
                rebuilding_ = std::async(std::launch::async, [resident = std::move(resident), old = node_picks_] {
                    NodePicks r;
                    auto set = std::make_shared<PickSet>();
                    for (const auto& [node, points, level] : resident) {
                        const auto it = old.find(node);
                        auto index = it != old.end() ? it->second : std::make_shared<const PickIndex>(points->points);
                        set->add(index, level);  // the hit says which level it came from
                        r.by_node.emplace(node, std::move(index));
                    }
                    r.set = std::move(set);
                    return r;
                });
        }
    }
    if (finished && !source_->error().empty() && error_.empty()) {
        error_ = source_->error();
        log.event("load error: " + error_);
        ev.load_error = error_;
    }
    if (loaded_since_frame_ < 0 && whole) loaded_since_frame_ = frame;
    centre_changed_ = !centre_final_ && !renderer_->bounds().empty();
    if (centre_changed_) centre_final_ = finished && renderer_->pendingPoints() == 0;
    return ev;
}

}  // namespace viewer
