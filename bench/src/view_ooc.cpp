// bench/src/view_ooc.cpp: `ladarvr bench view --paths ooc` (view_ooc.hpp), a program, not a
// test.
//
// Each measured run happens in its own child process (fork): the generator's threads stay
// out of the parent, each run gets a fresh EGL context, and the child's peak RSS
// (ru_maxrss) is that run's alone. A child reports its figures as one JSON document on a
// pipe.
#include "view_ooc.hpp"

#include "common.hpp"
#include "synthetic_survey.hpp"

#include <core/error.hpp>
#include <core/roles.hpp>
#include <io/cloud_reader.hpp>
#include <io/scene_file.hpp>
#include <platform/atomic_file.hpp>
#include <render/egl_context.hpp>
#include <render/gl.hpp>
#include <render/orbit_camera.hpp>
#include <sim/generator.hpp>
#include <viewer/cloud_feed.hpp>
#include <viewer/cloud_feed_source.hpp>
#include <viewer/copc_source.hpp>
#include <viewer/mode_controller.hpp>
#include <viewer/node_selection.hpp>
#include <viewer/open_point_source.hpp>
#include <viewer/offscreen_stereo.hpp>
#include <viewer/point_source.hpp>

#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace bench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kFrameRate_hz = 90.0;  // the head paths advance one 90 Hz step per frame
constexpr int kSyntheticBits = 20;      // a synthetic survey's cube: 2^20 mm, about 1 km

/// A head path in the cloud's local frame: the head moves for `moving_frames` frames,
/// then stays at its last pose (the still phase, where full detail is awaited).
struct HeadPath {
    std::string name;
    long moving_frames = 0;
    std::function<viewer::RigPose(long frame)> pose;
};

render::CameraPose lookFrom(const glm::dvec3& eye, const glm::dvec3& at) {
    render::CameraPose p;
    p.eye = eye;
    p.look_at = at;
    const glm::dvec3 d = glm::normalize(at - eye);
    glm::dvec3 up = glm::dvec3(0, 0, 1) - glm::dot(glm::dvec3(0, 0, 1), d) * d;
    p.up = glm::length(up) > 1e-9 ? glm::normalize(up) : glm::dvec3(1, 0, 0);
    return p;
}

/// orbit: the automatic mode's orbit (60 m out, 40 m up) turning 72 degrees in 4 s;
/// fly-in: from the orbit's start to 8 m from the target in 3 s (smoothstep); turn: at the
/// orbit's start, a full turn of the head about the vertical in 1 s.
HeadPath headPath(const std::string& name, const glm::dvec3& centre, const glm::dvec3& target) {
    const render::OrbitCameraOptions orbit;
    const render::CameraPose start = render::orbitPose(orbit, centre, 0.0);
    HeadPath h;
    h.name = name;
    if (name == "orbit") {
        h.moving_frames = 360;
        h.pose = [=](long f) {
            const double a = 2.0 * std::numbers::pi * (double(f) / kFrameRate_hz) / 20.0;
            return viewer::rigFromCamera(render::orbitPose(orbit, centre, a));
        };
    } else if (name == "fly-in") {
        h.moving_frames = 270;
        const glm::dvec3 end = target + 8.0 * glm::normalize(start.eye - target);
        h.pose = [=](long f) {
            const double s = std::clamp(double(f) / 270.0, 0.0, 1.0);
            const double e = s * s * (3.0 - 2.0 * s);
            return viewer::rigFromCamera(lookFrom(start.eye + e * (end - start.eye), target));
        };
    } else if (name == "turn") {
        h.moving_frames = 90;
        const glm::dvec3 d = start.look_at - start.eye;
        h.pose = [=](long f) {
            const double a = 2.0 * std::numbers::pi * std::clamp(double(f) / 90.0, 0.0, 1.0);
            const glm::dvec3 r(std::cos(a) * d.x - std::sin(a) * d.y, std::sin(a) * d.x + std::cos(a) * d.y, d.z);
            return viewer::rigFromCamera(lookFrom(start.eye, start.eye + r));
        };
    } else {
        throw core::Error("bench view: head path '" + name + "' is not one of orbit, fly-in, turn");
    }
    return h;
}

std::vector<std::string> splitList(const std::string& s) {
    std::vector<std::string> out;
    std::size_t a = 0;
    while (a <= s.size()) {
        const std::size_t b = std::min(s.find(',', a), s.size());
        if (b > a) out.push_back(s.substr(a, b - a));
        a = b + 1;
    }
    return out;
}

/// Runs `body` in a child process; returns its JSON report and peak RSS (MiB).
json inChild(const std::function<json()>& body, double& rss_mib) {
    int fds[2];
    if (::pipe(fds) != 0) throw core::Error("bench view: pipe failed");
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) throw core::Error("bench view: fork failed");
    if (pid == 0) {
        ::close(fds[0]);
        json r;
        try {
            r = body();
        } catch (const std::exception& e) {
            r = json{{"error", e.what()}};
        }
        const std::string text = r.dump();
        std::size_t done = 0;
        while (done < text.size()) {
            const ssize_t n = ::write(fds[1], text.data() + done, text.size() - done);
            if (n <= 0) break;
            done += std::size_t(n);
        }
        ::close(fds[1]);
        std::fflush(nullptr);
        ::_exit(0);
    }
    ::close(fds[1]);
    std::string text;
    char buf[65536];
    while (true) {
        const ssize_t n = ::read(fds[0], buf, sizeof buf);
        if (n <= 0) break;
        text.append(buf, std::size_t(n));
    }
    ::close(fds[0]);
    int status = 0;
    struct rusage usage{};
    if (::wait4(pid, &status, 0, &usage) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw core::Error("bench view: a measuring child process failed");
    rss_mib = double(usage.ru_maxrss) / 1024.0;
    return json::parse(text.empty() ? std::string("{\"error\": \"no report\"}") : text);
}

struct Summary {
    double median = NAN, p99 = NAN, max = NAN;
};
Summary summarise(const std::vector<double>& v) {
    if (v.empty()) return {};
    return {bench::median(v), quantile(v, 0.99), *std::max_element(v.begin(), v.end())};
}
json toJson(const Summary& s) { return json{{"median", s.median}, {"p99", s.p99}, {"max", s.max}}; }

/// The second lap per stereo frame (both eyes, twice the per-eye figures): median, p99
/// and their ratio, the goal's terms (p99 within 1.5x the median and under 8 ms).
std::string lapStereo(const json& r) {
    if (!r.contains("lap_gpu_eye_ms") || !r["lap_gpu_eye_ms"]["median"].is_number() ||
        !r["lap_gpu_eye_ms"]["p99"].is_number())
        return "";
    const double median = 2.0 * r["lap_gpu_eye_ms"]["median"].get<double>();
    const double p99 = 2.0 * r["lap_gpu_eye_ms"]["p99"].get<double>();
    return "; second lap per stereo frame " + fmt("%.2f", median) + " / " + fmt("%.2f", p99) + " ms, p99 " +
           (median > 0.0 ? fmt("%.2fx", p99 / median) : std::string("-")) + " the median";
}

/// The second lap's frames of one run as CSV, one row a frame in the lap's order, so the
/// slow frames can be placed along the head path (`--frame-log`).
void writeFrameLog(const fs::path& path, const json& lap) {
    const char* columns[] = {"gpu_eye_ms", "frame_ms", "drawn_eye", "raster_eye_ms", "colour_eye_ms", "resolve_eye_ms"};
    std::string csv = "frame";
    for (const char* c : columns) csv += std::string(",") + c;
    csv += "\n";
    const std::size_t frames = lap["gpu_eye_ms"].size();
    for (std::size_t i = 0; i < frames; ++i) {
        csv += std::to_string(i);
        for (const char* c : columns)
            csv += "," + (i < lap[c].size() ? fmt("%.4f", lap[c][i].get<double>()) : std::string());
        csv += "\n";
    }
    platform::writeFileAtomic(path, csv);
}

/// One head path over `file`, out of core (CopcSource) or in core (the file streamed
/// whole through a CloudFeed, as `view` does with any non-COPC file).
json measurePath(const fs::path& file, bool ooc, const HeadPath& path_world, const OocBenchOptions& o) {
    render::EglContext context;
    viewer::StereoOptions so;
    so.eye_width_px = o.eye_width;
    so.eye_height_px = o.eye_height;
    viewer::OffscreenStereo stereo(so);
    const Clock::time_point t_open = Clock::now();
    glm::dvec3 origin(0.0);
    const std::size_t cache_bytes = std::size_t(o.cache_mb * 1048576.0);
    const std::size_t gpu_bytes = std::size_t(o.gpu_mb * 1048576.0);
    viewer::OpenSourceOptions open;
    open.copc.cache_bytes = cache_bytes;
    open.copc.quiet = true;
    if (!ooc) origin = io::CloudReader(file).origin();  // the loader's frame (its reader reads the same header)
    const viewer::OpenedCloud opened =
        viewer::openPointSource(file, ooc ? viewer::SourcePath::Copc : viewer::SourcePath::Whole, open);
    std::unique_ptr<viewer::CloudFeedSource> stream_source;  // after the feed it reads: destroyed before it
    if (ooc) {
        origin = opened.copc->origin();
        stereo.follow(*opened.copc, gpu_bytes);
    } else {
        stream_source = std::make_unique<viewer::CloudFeedSource>(*opened.feed);
        stereo.follow(*stream_source, gpu_bytes);
    }
    const double open_s = secondsSince(t_open);
    const viewer::PointSource& source = ooc ? static_cast<viewer::PointSource&>(*opened.copc) : *stream_source;

    GLuint query = 0;
    glCreateQueries(GL_TIME_ELAPSED, 1, &query);
    viewer::ViewStyle style;
    style.rasterizer = viewer::parseRasterizer(o.rasterizer);
    stereo.setSubgroupReduction(o.subgroup);
    std::vector<double> select_ms, plan_ms, upload_ms, gpu_eye_ms, frame_ms, loaded, evicted;
    std::vector<double> gpu_upload_eye_ms, gpu_quiet_eye_ms;  // frames that uploaded points / the others
    double first_frame_s = NAN, full_s = NAN, gpu_peak_bytes = 0.0;
    long first_frame = -1, full_frames = -1, still_start = -1;
    std::size_t max_eye = 0, over_budget_frames = 0;
    std::size_t last_loaded = 0, last_evicted = 0;
    Clock::time_point t_still{};
    long f = 0;
    for (;; ++f) {
        const bool moving = f < path_world.moving_frames;
        viewer::RigPose head = path_world.pose(std::min(f, path_world.moving_frames));
        head.position -= origin;
        const Clock::time_point t0 = Clock::now();
        if (!moving && still_start < 0) {
            still_start = f;
            t_still = t0;
        }
        const viewer::OffscreenStereo::StreamStep step = stereo.stream(o.upload_points);
        const Clock::time_point tp = Clock::now();
        stereo.plan(head, o.point_budget, true);
        const double plan = msSince(tp);
        glBeginQuery(GL_TIME_ELAPSED, query);
        stereo.draw(head, style, viewer::ViewMode::Automatic);
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
        glFinish();
        const double frame = msSince(t0);
        const auto drawn = stereo.lastDrawnPerEye();
        max_eye = std::max({max_eye, drawn[0], drawn[1]});
        if (o.point_budget && (drawn[0] > o.point_budget || drawn[1] > o.point_budget)) ++over_budget_frames;
        gpu_peak_bytes = std::max(gpu_peak_bytes, double(stereo.gpuBytesPeak()));
        if (ooc) select_ms.push_back(step.select_ms);
        plan_ms.push_back(plan);
        upload_ms.push_back(step.upload_ms);
        gpu_eye_ms.push_back(double(ns) * 1e-6 / 2.0);
        (step.uploaded_points > 0 ? gpu_upload_eye_ms : gpu_quiet_eye_ms).push_back(double(ns) * 1e-6 / 2.0);
        frame_ms.push_back(frame);
        if (const auto s = source.stats()) {
            loaded.push_back(double(s->nodes_loaded - last_loaded));
            evicted.push_back(double(s->nodes_evicted - last_evicted));
            last_loaded = s->nodes_loaded;
            last_evicted = s->nodes_evicted;
        }
        if (first_frame < 0 && drawn[0] + drawn[1] > 0) {
            first_frame = f + 1;
            first_frame_s = secondsSince(t_open);
        }
        if (moving) continue;
        bool full = false;
        if (ooc) {
            // Full detail: every node the source wants for this still view (its last
            // selection) is resident and on the GPU.
            const std::span<viewer::PointNode* const> wanted = opened.copc->wanted();
            full = stereo.lastView().has_value() && stereo.pendingPoints() == 0 && stereo.gpuNodesRefused() == 0 &&
                   opened.copc->pagesWanted() == 0 &&
                   std::all_of(wanted.begin(), wanted.end(), [](const viewer::PointNode* n) { return n->resident(); });
        } else {
            // Every point the loader delivered is on the GPU (finished() may turn true
            // after this frame's poll, before its last chunk is taken).
            full =
                source.finished() && stereo.pendingPoints() == 0 && stereo.uploadedPoints() >= source.pointsArrived();
        }
        if (full) {
            full_s = secondsSince(t_still);
            full_frames = f - still_start + 1;
            break;
        }
        if (f - still_start >= o.still_frames_max) break;
    }
    // A second lap over the same views once the first has converged: both paths then draw
    // what they hold with nothing left to load, so their frame times compare like for like
    // (the first lap's in-core frames include those before its cloud had arrived).
    // Its GPU time is also split by pass (timestamp queries), and every 8th frame counts
    // the pixels the points cover (eye 1) for the points drawn per pixel.
    std::vector<double> lap_gpu_eye_ms, lap_frame_ms, lap_drawn_eye;
    std::vector<double> lap_raster_ms, lap_colour_ms, lap_resolve_ms, lap_per_pixel;
    stereo.setPassTiming(true);
    for (long g = 0; g <= path_world.moving_frames; ++g) {
        viewer::RigPose head = path_world.pose(g);
        head.position -= origin;
        const Clock::time_point t0 = Clock::now();
        stereo.stream(o.upload_points);
        stereo.plan(head, o.point_budget, true);
        glBeginQuery(GL_TIME_ELAPSED, query);
        stereo.draw(head, style, viewer::ViewMode::Automatic);
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
        glFinish();
        lap_frame_ms.push_back(msSince(t0));
        lap_gpu_eye_ms.push_back(double(ns) * 1e-6 / 2.0);
        const auto drawn = stereo.lastDrawnPerEye();
        lap_drawn_eye.push_back(0.5 * double(drawn[0] + drawn[1]));
        if (const viewer::OffscreenStereo::PassTimes t = stereo.takePassTimes(); t.eyes > 0) {
            lap_raster_ms.push_back(t.raster_ms / t.eyes);
            lap_colour_ms.push_back(t.colour_ms / t.eyes);
            lap_resolve_ms.push_back(t.resolve_ms / t.eyes);
        }
        if (g % 8 == 0)
            if (const std::size_t covered = stereo.coveredPixels(); covered > 0)
                lap_per_pixel.push_back(double(drawn[1]) / double(covered));
    }
    stereo.setPassTiming(false);
    glDeleteQueries(1, &query);
    if (!source.error().empty()) return json{{"error", "the in-core loader failed: " + source.error()}};
    json r;
    r["open_s"] = open_s;
    r["frames"] = f + 1;
    r["first_frame_s"] = first_frame_s;
    r["first_frame"] = first_frame;
    r["full_detail_s"] = full_s;
    r["full_detail_frames"] = full_frames;
    r["gpu_peak_bytes"] = gpu_peak_bytes;
    r["max_drawn_eye"] = max_eye;
    r["over_budget_frames"] = over_budget_frames;
    r["points"] = ooc ? opened.copc->totalPoints() : source.pointsArrived();
    r["nodes"] = ooc ? opened.copc->nodeCount() : 0;
    if (const auto st = source.stats()) r["pages_read"] = st->pages_read;
    r["select_ms"] = toJson(summarise(select_ms));
    r["plan_ms"] = toJson(summarise(plan_ms));
    r["upload_ms"] = toJson(summarise(upload_ms));
    r["gpu_eye_ms"] = toJson(summarise(gpu_eye_ms));
    r["gpu_upload_eye_ms"] = toJson(summarise(gpu_upload_eye_ms));
    r["gpu_quiet_eye_ms"] = toJson(summarise(gpu_quiet_eye_ms));
    r["upload_frames"] = gpu_upload_eye_ms.size();
    r["frame_ms"] = toJson(summarise(frame_ms));
    r["lap_gpu_eye_ms"] = toJson(summarise(lap_gpu_eye_ms));
    r["lap_frame_ms"] = toJson(summarise(lap_frame_ms));
    r["lap_drawn_eye"] = toJson(summarise(lap_drawn_eye));
    r["lap_raster_eye_ms"] = toJson(summarise(lap_raster_ms));
    r["lap_colour_eye_ms"] = toJson(summarise(lap_colour_ms));
    r["lap_resolve_eye_ms"] = toJson(summarise(lap_resolve_ms));
    r["lap_points_per_pixel"] = toJson(summarise(lap_per_pixel));
    if (!o.frame_log.empty())
        r["lap_frames"] = json{{"gpu_eye_ms", lap_gpu_eye_ms},   {"frame_ms", lap_frame_ms},
                               {"drawn_eye", lap_drawn_eye},     {"raster_eye_ms", lap_raster_ms},
                               {"colour_eye_ms", lap_colour_ms}, {"resolve_eye_ms", lap_resolve_ms}};
    r["subgroup"] = o.subgroup && stereo.subgroupAvailable();
    r["loaded_per_frame"] = toJson(summarise(loaded));
    r["evicted_per_frame"] = toJson(summarise(evicted));
    if (const auto s = source.stats()) r["cache_peak_bytes"] = s->resident_bytes_peak;
    r["gl"] = render::glDescription();
    return r;
}

/// A node of the synthetic tree: bounds and a count, never resident.
class SynthNode final : public viewer::PointNode {
  public:
    SynthNode(const core::Bounds& b, std::size_t n) : bounds_(b), count_(n) {}
    const core::Bounds& bounds() const override { return bounds_; }
    std::size_t pointCount() const override { return count_; }
    std::span<viewer::PointNode* const> children() const override { return children_; }
    void request() override {}
    void evict() override {}
    std::shared_ptr<const viewer::NodePoints> points() const override { return nullptr; }
    std::vector<viewer::PointNode*> children_;

  private:
    core::Bounds bounds_;
    std::size_t count_;
};

/// The node selection alone (viewer::selectNodes: traversal, choice within the budget and
/// the evictable list) over a terrain-like octree of `nodes` nodes (each node's four lower
/// octants as children, level by level, 20,000 points a node), for both eyes of a head
/// orbiting it, on this one thread.
json measureSelection(const OocBenchOptions& o) {
    std::vector<std::unique_ptr<SynthNode>> all;
    core::Bounds root;
    root.lo = glm::dvec3(-512.0, -512.0, -512.0);
    root.hi = glm::dvec3(512.0, 512.0, 512.0);
    all.push_back(std::make_unique<SynthNode>(root, 20000));
    for (std::size_t i = 0; all.size() < o.selection_nodes; ++i) {
        SynthNode* parent = all[i].get();
        const core::Bounds& b = parent->bounds();
        const glm::dvec3 half = (b.hi - b.lo) * 0.5;
        for (int k = 0; k < 4 && all.size() < o.selection_nodes; ++k) {
            core::Bounds c;
            c.lo = b.lo + glm::dvec3((k & 1) * half.x, ((k >> 1) & 1) * half.y, 0.0);
            c.hi = c.lo + half;
            all.push_back(std::make_unique<SynthNode>(c, 20000));
            parent->children_.push_back(all.back().get());
        }
    }
    std::vector<viewer::PointNode*> roots = {all.front().get()};
    const viewer::StereoOptions so;
    std::vector<double> ms;
    std::size_t wanted = 0;
    const int frames = 1000;
    for (int f = 0; f < frames + 50; ++f) {
        const double a = 2.0 * std::numbers::pi * f / frames;
        render::CameraPose cam =
            lookFrom(glm::dvec3(700.0 * std::cos(a), 700.0 * std::sin(a), 300.0), glm::dvec3(0.0, 0.0, -400.0));
        const viewer::RigPose head = viewer::rigFromCamera(cam);
        std::vector<render::Frustum> frusta;
        glm::dvec3 mean(0.0);
        for (int e = 0; e < 2; ++e) {
            viewer::RigPose eye = head;
            eye.position = head.apply(glm::dvec3((e == 0 ? -0.5 : 0.5) * so.ipd_m, 0.0, 0.0));
            mean += eye.position * 0.5;
            const glm::dmat4 proj = viewer::projectionFromFov(so.angle_left_rad, so.angle_right_rad, so.angle_up_rad,
                                                              so.angle_down_rad, 0.1, 20000.0);
            frusta.push_back(render::Frustum::fromMatrix(proj * viewer::viewFromPose(eye)));
        }
        const Clock::time_point t0 = Clock::now();
        const viewer::NodeSelection sel =
            viewer::selectNodes(roots, frusta, mean, viewer::SelectionBudget{o.point_budget, 0});
        const double t = msSince(t0);
        if (f >= 50) {
            ms.push_back(t);
            wanted += sel.wanted.size();
        }
    }
    const Summary s = summarise(ms);
    return json{
        {"nodes", all.size()}, {"frames", frames}, {"ms", toJson(s)}, {"wanted_nodes_mean", double(wanted) / frames}};
}

std::string num(const json& j, const char* key, const char* format) {
    if (!j.contains(key) || !j[key].is_number()) return "-";
    const double v = j[key].get<double>();
    return std::isfinite(v) ? fmt(format, v) : "-";
}
std::string summ(const json& j, const char* key, const char* format) {
    if (!j.contains(key) || !j[key].is_object()) return "-";
    const json& s = j[key];
    if (!s["median"].is_number() || !std::isfinite(s["median"].get<double>())) return "-";
    return fmt(format, s["median"].get<double>()) + " / " + fmt(format, s["p99"].get<double>());
}

}  // namespace

void runOocBench(const OocBenchOptions& o, std::FILE* out) {
    if (o.points.empty()) throw core::Error("bench view: --ooc-points is empty");
    for (std::size_t n : o.points)
        if (n < 10000 || n > 4000000000ull)
            throw core::Error("bench view: --ooc-points " + std::to_string(n) + ": allowed 10000..4e9");
    if (!(o.cache_mb >= 1.0 && o.cache_mb <= 1048576.0))
        throw core::Error("bench view: --cache-mb: allowed 1..1048576");
    const std::vector<std::string> path_names = splitList(o.head_paths);
    if (path_names.empty()) throw core::Error("bench view: --head-paths is empty; allowed orbit, fly-in, turn");
    for (const auto& p : path_names) (void)headPath(p, {}, {});

    const Clock::time_point t_all = Clock::now();
    fs::path dir = o.dir;
    bool remove_dir = false;
    if (dir.empty()) {
        dir = fs::temp_directory_path() / ("ladarvr-bench-ooc-" + std::to_string(::getpid()));
        remove_dir = true;
    }
    fs::create_directories(dir);
    const core::Scene scene = io::loadScene(io::demoScenePath());
    const core::Bounds target_local = scene.bounds(core::RoleMask::of({core::Role::Target}));
    const glm::dvec3 target_world = scene.origin + target_local.centre();
    const glm::dvec3 centre_world = scene.origin + scene.bounds().centre();

    std::string md;
    const std::string command = "./ladarvr bench view --paths ooc";
    md += "## Viewer out of core (ladarvr bench view --paths ooc)\n\n";
    md += "Command: `" + command + "` with --ooc-points";
    for (std::size_t i = 0; i < o.points.size(); ++i) md += (i ? "," : " ") + std::to_string(o.points[i]);
    md += " --head-paths " + o.head_paths + " --point-budget " + std::to_string(o.point_budget) + " --cache-mb " +
          fmt("%g", o.cache_mb) + " --gpu-mb " + fmt("%g", o.gpu_mb) + " --eye " + std::to_string(o.eye_width) + "x" +
          std::to_string(o.eye_height) + " --rasterizer " + o.rasterizer + "; machine: " + cpuName() + "; " + utcNow() +
          ".\n\n";
    md +=
        o.synthetic
            ? std::string(
                  "Clouds: synthetic surveys written straight to COPC node by node (bench/src/synthetic_survey.hpp: "
                  "1 km of hills and flat-roofed blocks around the demo scene's origin, 128 x 128 jittered samples of "
                  "the surface per node and level, the deepest level denser to reach each size), because the "
                  "generator's spool and the COPC writer's scratch files for 10^9 points do not fit this disk. ")
            : std::string(
                  "Clouds: the demo scene generated with the paper's orbit at a resolution raised to reach each size, "
                  "written as COPC by the generator (`generate --out X.copc.laz`). ");
    md +=
        "Each head path is drawn by the viewer's offscreen "
        "stereo renderer (both eyes, eye-dome lighting, frustum culling, the point budget) following a "
        "`viewer::CopcSource` (ooc), and again following the same file streamed whole (in-core, today's path for "
        "any non-COPC file), each run in its own process. The head path advances one 90 Hz step per frame "
        "whatever the frame time, then holds still. First frame: from opening the file to the end of the first "
        "frame that drew a point. Full detail: from the first still frame until every node the selection wants "
        "is resident and uploaded and no hierarchy page it reached is unread (ooc), or the whole cloud is on the "
        "GPU (in-core). Nodes: the tree as the source knows it at the end of the path, and the hierarchy pages it "
        "read (a page at a time, as the head reaches them). Select: the source's choice "
        "(traversal, selection, scheduling) per stereo frame; plan: the renderer's per-cell budget; both CPU ms "
        "median / p99. GPU ms per eye: a GL timer query over both eyes, halved. GPU MiB: point bytes uploaded "
        "(20 B a point, within the arena of --gpu-mb). '-' where a figure does not apply or was not reached. "
        "The row's medians cover the first lap (the in-core path draws nothing until its cloud has streamed in); "
        "the ratios below compare a second lap over the same views, once each path has converged.\n\n";
    md +=
        "| points | nodes (pages read) | head path | path | first frame s (frames) | full detail s (frames) | peak RSS "
        "MiB | GPU "
        "MiB peak | max drawn per eye | frames over budget | loaded / evicted nodes per frame (max) | select ms | "
        "plan ms | GPU ms per eye | frame ms | frames |\n";
    md += "|---:|---:|---|---|---|---|---:|---:|---:|---:|---|---|---|---|---|---:|\n";
    std::fprintf(out, "%s", md.c_str());
    std::fflush(out);
    std::string gl;
    std::string ratios, by_frame;
    for (std::size_t n : o.points) {
        sim::GenerateOptions g;
        g.orbit.xres = g.orbit.yres = std::max(1, int(std::lround(std::sqrt(double(n) / double(g.orbit.views)))));
        const fs::path file = o.synthetic
                                  ? dir / ("synthetic_" + std::to_string(n) + ".copc.laz")
                                  : dir / ("demo_" + std::to_string(g.orbit.xres) + "x" + std::to_string(g.orbit.yres) +
                                           "x" + std::to_string(g.orbit.views) + ".copc.laz");
        if (o.synthetic && !fs::exists(file)) {
            std::fprintf(stderr, "bench view: writing the synthetic survey %s\n", file.c_str());
            double rss = 0.0;
            const Clock::time_point t0 = Clock::now();
            const json r = inChild(
                [&] {
                    const SyntheticSurvey s = writeSyntheticSurvey(
                        file, n, scene.origin, kSyntheticBits, int(std::max(1u, std::thread::hardware_concurrency())));
                    return json{{"points", s.points}, {"nodes", s.nodes}};
                },
                rss);
            if (r.contains("error"))
                throw core::Error("bench view: writing " + file.string() + ": " + r["error"].get<std::string>());
            std::fprintf(stderr, "bench view: %zu points in %zu nodes written in %.1f s, peak RSS %.0f MiB\n",
                         r["points"].get<std::size_t>(), r["nodes"].get<std::size_t>(), secondsSince(t0), rss);
        } else if (!fs::exists(file)) {
            std::fprintf(stderr, "bench view: generating %s\n", file.c_str());
            double rss = 0.0;
            const Clock::time_point t0 = Clock::now();
            const json r = inChild(
                [&] {
                    g.memory_budget_bytes = std::size_t(2048) << 20;
                    sim::generateToFile(scene, g, file, io::CloudFormat::Copc);
                    return json{{"ok", true}};
                },
                rss);
            if (r.contains("error"))
                throw core::Error("bench view: generating " + file.string() + ": " + r["error"].get<std::string>());
            std::fprintf(stderr, "bench view: generated in %.1f s, peak RSS %.0f MiB\n", secondsSince(t0), rss);
        }
        for (const std::string& name : path_names) {
            const HeadPath path = headPath(name, centre_world, target_world);
            json rows[2];
            double rss[2] = {0.0, 0.0};
            for (int k = 0; k < 2; ++k) {
                const bool ooc = k == 0;
                if (!ooc && n > o.in_core_max_points) {
                    rows[k] = json{{"error", "skipped: over --in-core-max " + std::to_string(o.in_core_max_points)}};
                    continue;
                }
                std::fprintf(stderr, "bench view: %s, %s, %s\n", file.filename().c_str(), name.c_str(),
                             ooc ? "ooc" : "in-core");
                rows[k] = inChild([&] { return measurePath(file, ooc, path, o); }, rss[k]);
                if (rows[k].contains("lap_frames")) {
                    writeFrameLog(fs::path(o.frame_log) / (file.stem().stem().string() + "_" + name + "_" +
                                                           (ooc ? "ooc" : "in-core") + ".csv"),
                                  rows[k]["lap_frames"]);
                    rows[k].erase("lap_frames");
                }
                if (rows[k].contains("gl")) gl = rows[k]["gl"].get<std::string>();
                std::string line;
                if (rows[k].contains("error")) {
                    line = "| " + std::to_string(n) + " | - | " + name + " | " + (ooc ? "ooc" : "in-core") + " | " +
                           rows[k]["error"].get<std::string>() + " | | | | | | | | | | | |\n";
                } else {
                    const json& r = rows[k];
                    line = "| " + std::to_string(r.value("points", std::size_t{0})) + " | " +
                           (ooc ? std::to_string(r.value("nodes", std::size_t{0})) + " (" +
                                      std::to_string(r.value("pages_read", std::size_t{0})) + ")"
                                : std::string("-")) +
                           " | " + name + " | " + (ooc ? "ooc" : "in-core") + " | " + num(r, "first_frame_s", "%.2f") +
                           " (" + std::to_string(r.value("first_frame", -1L)) + ") | " +
                           num(r, "full_detail_s", "%.2f") + " (" + std::to_string(r.value("full_detail_frames", -1L)) +
                           ") | " + fmt("%.0f", rss[k]) + " | " +
                           fmt("%.0f", r.value("gpu_peak_bytes", 0.0) / 1048576.0) + " | " +
                           std::to_string(r.value("max_drawn_eye", std::size_t{0})) + " | " +
                           std::to_string(r.value("over_budget_frames", std::size_t{0})) + " | " +
                           (ooc ? fmt("%.0f", r["loaded_per_frame"].value("max", 0.0)) + " / " +
                                      fmt("%.0f", r["evicted_per_frame"].value("max", 0.0))
                                : std::string("-")) +
                           " | " + summ(r, "select_ms", "%.3f") + " | " + summ(r, "plan_ms", "%.3f") + " | " +
                           summ(r, "gpu_eye_ms", "%.1f") + " | " + summ(r, "frame_ms", "%.1f") + " | " +
                           std::to_string(r.value("frames", 0L)) + " |\n";
                }
                md += line;
                std::fprintf(out, "%s", line.c_str());
                std::fflush(out);
                if (const json& r = rows[k]; !r.contains("error"))
                    by_frame +=
                        "- " + std::to_string(r.value("points", std::size_t{0})) + " points, " + name + ", " +
                        (ooc ? "ooc" : "in-core") + ": frames that uploaded points (" +
                        std::to_string(r.value("upload_frames", std::size_t{0})) + ") " +
                        summ(r, "gpu_upload_eye_ms", "%.2f") + ", the other frames " +
                        summ(r, "gpu_quiet_eye_ms", "%.2f") + ", the second lap " + summ(r, "lap_gpu_eye_ms", "%.2f") +
                        " (by pass: points " + summ(r, "lap_raster_eye_ms", "%.2f") + ", colour " +
                        summ(r, "lap_colour_eye_ms", "%.2f") + ", resolve " + summ(r, "lap_resolve_eye_ms", "%.2f") +
                        "; points per covered pixel " + summ(r, "lap_points_per_pixel", "%.1f") +
                        (r.value("subgroup", false) ? "; subgroup reduction" : "") + ")" + lapStereo(r) + "\n";
            }
            const auto measured = [](const json& r) {
                return !r.contains("error") && r["first_frame_s"].is_number() && r["frame_ms"]["median"].is_number();
            };
            if (measured(rows[0]) && measured(rows[1])) {
                const auto med = [](const json& r, const char* k) { return r[k]["median"].get<double>(); };
                ratios +=
                    "- " + std::to_string(n) + " points, " + name + ": in-core / ooc: first frame " +
                    fmt("%.2fx", rows[1]["first_frame_s"].get<double>() / rows[0]["first_frame_s"].get<double>()) +
                    ", peak RSS " + fmt("%.2fx", rss[1] / rss[0]) + ", frame ms (median) " +
                    fmt("%.2fx", med(rows[1], "frame_ms") / med(rows[0], "frame_ms")) + "; ooc / in-core frame ms " +
                    fmt("%.2fx", med(rows[0], "frame_ms") / med(rows[1], "frame_ms")) + ".\n";
                if (rows[0]["lap_frame_ms"]["median"].is_number() && rows[1]["lap_frame_ms"]["median"].is_number())
                    ratios += "  - second lap (the same views, nothing left to load): ooc / in-core frame ms " +
                              fmt("%.2fx", med(rows[0], "lap_frame_ms") / med(rows[1], "lap_frame_ms")) + " (" +
                              fmt("%.2f", med(rows[0], "lap_frame_ms")) + " / " +
                              fmt("%.2f", med(rows[1], "lap_frame_ms")) + "), GPU ms per eye " +
                              fmt("%.2fx", med(rows[0], "lap_gpu_eye_ms") / med(rows[1], "lap_gpu_eye_ms")) + " (" +
                              fmt("%.2f", med(rows[0], "lap_gpu_eye_ms")) + " / " +
                              fmt("%.2f", med(rows[1], "lap_gpu_eye_ms")) + "), points drawn per eye (median) " +
                              fmt("%.0f", med(rows[0], "lap_drawn_eye")) + " / " +
                              fmt("%.0f", med(rows[1], "lap_drawn_eye")) + ".\n";
            }
        }
        if (remove_dir) fs::remove(file);
    }
    if (!by_frame.empty()) {
        const std::string head = "\nGPU ms per eye (median / p99) by kind of frame:\n";
        md += head + by_frame;
        std::fprintf(out, "%s%s", head.c_str(), by_frame.c_str());
    }
    if (!ratios.empty()) {
        md += "\nRatios in the same run:\n" + ratios;
        std::fprintf(out, "\nRatios in the same run:\n%s", ratios.c_str());
    }
    double rss = 0.0;
    const json sel = inChild([&] { return measureSelection(o); }, rss);
    std::string sel_md =
        "\nThe node selection alone (`viewer::selectNodes`: the traversal for both eyes, the choice "
        "within the point budget of " +
        std::to_string(o.point_budget) +
        " per eye, the evictable list) on a synthetic terrain-like tree, one thread, a head orbiting "
        "it, " +
        std::to_string(sel.value("frames", 0)) + " frames after 50 of warm-up:\n\n";
    sel_md += "| nodes | wanted nodes (mean) | ms median | ms p99 | ms max |\n|---:|---:|---:|---:|---:|\n";
    if (sel.contains("error")) {
        sel_md += "| - | " + sel["error"].get<std::string>() + " | | | |\n";
    } else {
        sel_md += "| " + std::to_string(sel["nodes"].get<std::size_t>()) + " | " +
                  fmt("%.0f", sel["wanted_nodes_mean"].get<double>()) + " | " +
                  fmt("%.3f", sel["ms"]["median"].get<double>()) + " | " + fmt("%.3f", sel["ms"]["p99"].get<double>()) +
                  " | " + fmt("%.3f", sel["ms"]["max"].get<double>()) + " |\n";
    }
    sel_md += "\nGL: " + gl + ". Whole run " + fmt("%.0f", secondsSince(t_all)) + " s.\n";
    md += sel_md;
    std::fprintf(out, "%s", sel_md.c_str());
    if (remove_dir) fs::remove_all(dir);
    if (!o.md.empty()) replaceMarkdownSection(o.md, "## Viewer out of core (ladarvr bench view --paths ooc)", md);
}

}  // namespace bench
