// viewer/src/points/source_stream.cpp: a point source streamed into the renderer and the picking.
#include "points/source_stream.hpp"

#include <platform/atomic_file.hpp>
#include <platform/cache_folder.hpp>
#include <platform/safe_file.hpp>
#include <render/gl.hpp>
#include <render/point_chunks.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
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
    height_unit_m_ = options.height_unit_m;
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
    measure_budget_points_ = options.measure_budget && options.point_budget_auto;
    measure_rasterizer_ = options.measure_budget && options.rasterizer_auto;
    gpu_name_ = str(GL_RENDERER);
    adaptive_wanted_ = options.adaptive_budget;
    if (measure_budget_points_ || measure_rasterizer_) recallBudget(options, log);
    // While the budget is measured, the adaptive budget waits for its ceiling.
    if (options.adaptive_budget && budget_points_ > 0 && !measure_)
        adaptive_.emplace(adaptiveFloor(budget_points_), budget_points_);
    log.set("adaptive_budget", adaptive_
                                   ? nlohmann::json{{"floor", adaptive_->floor()}, {"ceiling", adaptive_->ceiling()}}
                                   : nlohmann::json(false));
    renderer_ = std::make_unique<PointRenderer>();
    applyBudget();
}

void SourceStream::applyBudget() {
    renderer_->setHeightUnit(height_unit_m_);
    renderer_->setGpuBytes(gpu_bytes_);
    renderer_->setPointBudget(budget_points_);
}

namespace {

constexpr std::size_t kMaxBudgetFileBytes = 64 * 1024;
constexpr const char* kBudgetFormat = "ladarvr view budget";

/// 16 hex digits of a 64-bit FNV-1a hash of `text`.
std::string hashName(const std::string& text) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return hex;
}

/// A remembered choice read back: what the file says, or why it cannot be used.
struct Remembered {
    std::string problem;  // empty: valid
    Rasterizer rasterizer = Rasterizer::Points;
    std::size_t point_budget = 0;
};

Remembered readRemembered(const std::filesystem::path& file, const std::string& gpu) {
    Remembered r;
    try {
        const std::string text = platform::readOwnFile(file, kMaxBudgetFileBytes, "view: budget cache");
        const nlohmann::json j = nlohmann::json::parse(text);
        if (!j.is_object() || j.value("format", "") != kBudgetFormat || j.value("version", 0) != 1)
            r.problem = "not a budget file of this version";
        else if (j.value("gl_renderer", "") != gpu)
            r.problem = "made for another GPU";
        else if (!j.contains("rasterizer") || !j["rasterizer"].is_string() ||
                 (j["rasterizer"] != "points" && j["rasterizer"] != "compute"))
            r.problem = "its rasterizer is not one of points, compute";
        else if (!j.contains("point_budget") || !j["point_budget"].is_number_unsigned() ||
                 j["point_budget"].get<std::size_t>() < BudgetMeasure::kLeastBudget ||
                 j["point_budget"].get<std::size_t>() > BudgetMeasure::kMostBudget)
            r.problem = "its point_budget is not a whole number in [" + std::to_string(BudgetMeasure::kLeastBudget) +
                        ", " + std::to_string(BudgetMeasure::kMostBudget) + "]";
        else {
            r.rasterizer = parseRasterizer(j["rasterizer"].get<std::string>());
            r.point_budget = j["point_budget"].get<std::size_t>();
        }
    } catch (const std::exception& e) {
        r.problem = e.what();
    }
    return r;
}

}  // namespace

bool SourceStream::recallBudget(const ViewerOptions& options, RunLog& log) {
    try {
        const std::filesystem::path folder = platform::userCacheFolder("ladarvr", "view: budget cache");
        platform::makeCacheFolder(folder, "view: budget cache");
        budget_file_ = folder / ("budget-" + hashName(gpu_name_) + ".json");
        if (platform::useCachedFile(budget_file_, "view: budget cache")) {
            const Remembered r = readRemembered(budget_file_, gpu_name_);
            if (r.problem.empty()) {
                if (measure_budget_points_) {
                    budget_points_ = r.point_budget;
                    log.set("point_budget_choice", nlohmann::json{{"from", "remembered"},
                                                                  {"gpu", gpu_name_},
                                                                  {"file", budget_file_.string()},
                                                                  {"point_budget", budget_points_}});
                }
                if (measure_rasterizer_) {
                    rasterizer_ = r.rasterizer;
                    log.set("rasterizer_choice", nlohmann::json{{"from", "remembered"},
                                                                {"gpu", gpu_name_},
                                                                {"rasterizer", rasterizerName(rasterizer_)}});
                }
                log.event("budget remembered for GPU '" + gpu_name_ + "' (" + budget_file_.string() + "): " +
                          rasterizerName(r.rasterizer) + ", " + std::to_string(r.point_budget) + " points per eye");
                return true;
            }
            const std::string line =
                "view: budget cache " + budget_file_.string() + ": " + r.problem + "; measured again";
            log.event(line);
            if (!options.quiet) platform::printMessage("warning", line);
        }
    } catch (const std::exception& e) {  // no cache folder: measured, not remembered
        budget_file_.clear();
        log.event(std::string("budget not remembered: ") + e.what());
    }
    measure_.emplace(rasterizer_, measure_rasterizer_);
    rasterizer_ = measure_->rasterizer();
    return false;
}

void SourceStream::finishMeasure(double frame_budget_ms, long frame, RunLog& log) {
    const BudgetMeasure::Choice c = measure_->choice(frame_budget_ms);
    measure_.reset();
    const auto rate = [&](int r) {
        return c.ms_per_million[r] < 0.0 ? nlohmann::json(nullptr) : nlohmann::json(c.ms_per_million[r]);
    };
    const nlohmann::json rates = {{"points", rate(0)}, {"compute", rate(1)}};
    if (measure_budget_points_) {
        budget_points_ = c.point_budget;
        renderer_->setPointBudget(budget_points_);
        log.set("point_budget_choice", nlohmann::json{{"from", "measured"},
                                                      {"gpu", gpu_name_},
                                                      {"ms_per_million_points", rates},
                                                      {"frame_budget_ms", frame_budget_ms},
                                                      {"point_budget", budget_points_}});
    }
    if (measure_rasterizer_) {
        rasterizer_ = c.rasterizer;
        log.set("rasterizer_choice", nlohmann::json{{"from", "measured"},
                                                    {"gpu", gpu_name_},
                                                    {"ms_per_million_points", rates},
                                                    {"rasterizer", rasterizerName(rasterizer_)}});
    }
    char line[400];
    std::snprintf(line, sizeof line,
                  "budget measured for GPU '%s' by frame %ld: ms per million points drawn: points %.3f, compute "
                  "%.3f (-1: not measured); chose %s, %zu points per eye (%.0f %% of %.2f ms)",
                  gpu_name_.c_str(), frame, c.ms_per_million[0], c.ms_per_million[1], rasterizerName(c.rasterizer),
                  c.point_budget, BudgetMeasure::kShare * 100.0, frame_budget_ms);
    log.event(line);
    if (adaptive_wanted_ && budget_points_ > 0) {
        adaptive_.emplace(adaptiveFloor(budget_points_), budget_points_);
        log.set("adaptive_budget", nlohmann::json{{"floor", adaptive_->floor()}, {"ceiling", adaptive_->ceiling()}});
    }
    if (budget_file_.empty()) return;
    const nlohmann::json file = {{"format", kBudgetFormat},           {"version", 1},
                                 {"gl_renderer", gpu_name_},          {"rasterizer", rasterizerName(c.rasterizer)},
                                 {"point_budget", c.point_budget},    {"ms_per_million_points", rates},
                                 {"frame_budget_ms", frame_budget_ms}};
    try {
        platform::writeFileAtomic(budget_file_, file.dump(2) + "\n");
    } catch (const std::exception& e) {
        log.event(std::string("budget not remembered: ") + e.what());
    }
}

bool SourceStream::frameTimed(double cost_ms, double frame_budget_ms, std::size_t points_drawn, long frame,
                              RunLog& log) {
    if (measure_) {
        const Rasterizer before = rasterizer_;
        measure_->add(points_drawn, cost_ms);
        if (measure_->done())
            finishMeasure(frame_budget_ms, frame, log);
        else
            rasterizer_ = measure_->rasterizer();
        return rasterizer_ != before;
    }
    if (!adaptive_) return false;
    const std::size_t before = adaptive_->budget();
    const std::size_t after = adaptive_->update(cost_ms, frame_budget_ms);
    if (after == before) return false;
    budget_points_ = after;
    renderer_->setPointBudget(budget_points_);
    char line[160];
    std::snprintf(line, sizeof line, "point budget %zu -> %zu at frame %ld (frame %.2f of %.2f ms)", before, after,
                  frame, cost_ms, frame_budget_ms);
    log.event(line);
    return false;
}

nlohmann::json SourceStream::frameFigures() {
    const ArenaStats& a = renderer_->arena();
    nlohmann::json j = {{"point_budget", budget_points_},
                        {"gpu_bytes", a.bytes},
                        {"gpu_nodes", a.nodes},
                        {"gpu_nodes_added", a.frame_nodes_added},
                        {"gpu_nodes_evicted", a.frame_nodes_evicted},
                        {"upload_bytes", a.frame_upload_bytes}};
    // The points of the operator's focus, drawn whatever the budget (lod.hpp's LodFocus).
    if (!renderer_->focus().empty()) j["focus_points"] = renderer_->focusPoints();
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
    cloud_bounds_ = {};
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
    // The cloud's bounds are its drawn points' once there are any (their heights without
    // stray returns, PointRenderer::bodyBounds); before that, a source
    // that chooses its nodes (a COPC hierarchy, known unread) gives its roots', so the
    // orbit is placed on the survey before the first node is chosen: a real survey far
    // from the frame's origin (a COPC file's heights at 3,000 m) would otherwise be
    // outside every frustum and never be asked for.
    if (!renderer_->bounds().empty()) {
        cloud_bounds_ = renderer_->bodyBounds();
        centre_changed_ = !centre_final_;
        if (centre_changed_) centre_final_ = finished && renderer_->pendingPoints() == 0;
    } else if (chooses) {
        core::Bounds roots;
        for (const PointNode* node : source_->roots())
            if (node->pointCount() > 0) roots.extend(node->bounds());
        centre_changed_ =
            !roots.empty() && (cloud_bounds_.empty() || roots.lo != cloud_bounds_.lo || roots.hi != cloud_bounds_.hi);
        if (centre_changed_) cloud_bounds_ = roots;
    }
    return ev;
}

}  // namespace viewer
