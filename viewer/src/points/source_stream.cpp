// viewer/src/points/source_stream.cpp: a point source streamed into the renderer and the picking.
#include "points/source_stream.hpp"

#include <platform/safe_file.hpp>
#include <render/gl.hpp>
#include <render/point_chunks.hpp>

#include <algorithm>
#include <chrono>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

namespace viewer {

void SourceStream::start(const ViewerOptions& options, RunLog& log) {
    budget_ = options.upload_bytes_per_frame
                  ? std::max<std::size_t>(1, options.upload_bytes_per_frame / sizeof(render::GpuPoint))
                  : options.upload_points_per_frame;
    gpu_bytes_ = options.gpu_bytes;
    quiet_ = options.quiet;
    budget_points_ = options.point_budget;
    rasterizer_ = options.style.rasterizer;
    auto str = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "");
    };
    const GpuClass gpu = classifyGpu(str(GL_RENDERER), str(GL_VENDOR));
    if (options.point_budget_auto) {
        budget_points_ = defaultPointBudget(gpu);
        log.set(
            "point_budget_choice",
            nlohmann::json{{"from", "gpu class"}, {"gpu_class", gpuClassName(gpu)}, {"point_budget", budget_points_}});
    } else {
        log.set("point_budget_choice", nlohmann::json{{"from", "option"}, {"point_budget", budget_points_}});
    }
    if (options.rasterizer_auto) {
        rasterizer_ = computeRasterizerByDefault(gpu) ? Rasterizer::Compute : Rasterizer::Points;
        log.set("rasterizer_choice", nlohmann::json{{"from", "gpu class"},
                                                    {"gpu_class", gpuClassName(gpu)},
                                                    {"rasterizer", rasterizerName(rasterizer_)}});
    } else {
        log.set("rasterizer_choice", nlohmann::json{{"from", "option"}, {"rasterizer", rasterizerName(rasterizer_)}});
    }
    if (options.adaptive_budget && budget_points_ > 0) adaptive_.emplace(adaptiveFloor(budget_points_), budget_points_);
    log.set("adaptive_budget", adaptive_
                                   ? nlohmann::json{{"floor", adaptive_->floor()}, {"ceiling", adaptive_->ceiling()}}
                                   : nlohmann::json(false));
    renderer_ = std::make_unique<PointRenderer>();
    applyBudget();
}

void SourceStream::applyBudget() {
    renderer_->setGpuBytes(gpu_bytes_);
    renderer_->setPointBudget(budget_points_);
}

void SourceStream::frameTimed(double cost_ms, double frame_budget_ms, long frame, RunLog& log) {
    if (!adaptive_) return;
    const std::size_t before = adaptive_->budget();
    const std::size_t after = adaptive_->update(cost_ms, frame_budget_ms);
    if (after == before) return;
    budget_points_ = after;
    renderer_->setPointBudget(budget_points_);
    char line[160];
    std::snprintf(line, sizeof line, "point budget %zu -> %zu at frame %ld (frame %.2f of %.2f ms)", before, after,
                  frame, cost_ms, frame_budget_ms);
    log.event(line);
}

nlohmann::json SourceStream::frameFigures() {
    const ArenaStats& a = renderer_->arena();
    nlohmann::json j = {{"point_budget", budget_points_},
                        {"gpu_bytes", a.bytes},
                        {"gpu_nodes", a.nodes},
                        {"gpu_nodes_added", a.frame_nodes_added},
                        {"gpu_nodes_evicted", a.frame_nodes_evicted},
                        {"upload_bytes", a.frame_upload_bytes}};
    if (const std::optional<SourceStats> s = source_->stats()) {
        j["resident_bytes"] = s->resident_bytes;
        j["nodes_loaded"] = s->nodes_loaded - std::min(last_loaded_, s->nodes_loaded);
        j["nodes_evicted"] = s->nodes_evicted - std::min(last_evicted_, s->nodes_evicted);
        last_loaded_ = s->nodes_loaded;
        last_evicted_ = s->nodes_evicted;
    }
    return j;
}

void SourceStream::reset(PointSource& source) {
    building_ = {};  // waits for a build in flight
    rebuilding_ = {};
    node_picks_.clear();
    levels_.clear();
    source_ = &source;
    renderer_ = std::make_unique<PointRenderer>();
    applyBudget();
    last_loaded_ = last_evicted_ = 0;
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
    // Read before the poll: a stream's last chunk can arrive, and the stream end, after the
    // poll took what had arrived; a source that had finished before the poll has every node
    // after it, so the cloud is whole (and indexed for picking) only with all its points.
    const bool finished_before_poll = source_->finished();
    source_->poll();
    if (const std::optional<SourceStats> s = source_->stats()) {
        if (!log_nodes_ && s->nodes_loaded > 0) {
            log_nodes_ = true;
            log.event("first node resident");
        }
    }
    renderer_->stream(*source_, budget_);
    const ArenaStats& arena = renderer_->arena();
    if (const std::optional<SourceStats> s = source_->stats())
        log.set("source", nlohmann::json{{"kind", s->kind},
                                         {"nodes", s->nodes},
                                         {"hierarchy_bytes", s->hierarchy_bytes},
                                         {"pages_read", s->pages_read},
                                         {"pages_unread", s->pages_unread},
                                         {"pages_failed", s->pages_failed},
                                         {"nodes_resident", s->nodes_resident},
                                         {"nodes_loaded", s->nodes_loaded},
                                         {"nodes_evicted", s->nodes_evicted},
                                         {"nodes_failed", s->nodes_failed},
                                         {"wanted_points", s->wanted_points},
                                         {"cache_bytes", s->cache_bytes},
                                         {"resident_bytes", s->resident_bytes},
                                         {"resident_bytes_peak", s->resident_bytes_peak},
                                         {"gpu_bytes_bound", arena.bytes_bound},
                                         {"gpu_bytes", arena.bytes},
                                         {"gpu_bytes_peak", arena.bytes_peak},
                                         {"gpu_nodes", arena.nodes},
                                         {"gpu_nodes_added", arena.nodes_added},
                                         {"gpu_nodes_evicted", arena.nodes_evicted},
                                         {"upload_points_per_frame", budget_}});
    else if (arena.nodes_refused > 0 && arena_warned_.empty() && source_->finished()) {
        // A cloud held whole that the arena cannot hold: said once, the rest is not drawn.
        arena_warned_ = "view: the GPU arena (--gpu-mb, " + std::to_string(arena.bytes_bound) + " bytes) holds " +
                        std::to_string(renderer_->uploadedPoints() + renderer_->pendingPoints()) +
                        " points of the cloud; the rest is not drawn";
        log.event(arena_warned_);
        if (!quiet_) platform::printMessage("warning", arena_warned_);
    }
    const bool finished = finished_before_poll && source_->finished();
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
            if (levels_.empty()) levels_ = nodeLevels(*source_);
            for (const PointNode* node : allNodes(*source_))
                if (auto points = node->points(); points && !points->points.empty()) {
                    same = same && node_picks_.contains(node);
                    const auto level = levels_.find(node);
                    resident.emplace_back(node, std::move(points), level != levels_.end() ? level->second : -1);
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
