// sim/generator.cpp: paper §III-B (one ray per pixel, NoV views on the circular orbit,
// fusion of all views) and §III-C (ground whitening per view, jet colouring by height).
//
// Data flow (see docs/generator.md): views are processed in batches (FusePipeline,
// fuse.cpp, with this file's castBlock casting). For a batch, the rays of every (view,
// block of pixels) task are traced in parallel into per-pixel slots; each view's hits
// are compacted in pixel order, whitened by the iterative RANSAC (per view, in parallel,
// seeded per view) and appended in view order to the fused cloud, which lives in memory
// or, for big runs, in the output itself (binary PCD and PLY, whose records can be
// rewritten) or a spool file next to it (StreamedWrite). Colouring needs the z range of
// the whole fused cloud, so it is a last pass that reads the fused points back and
// rewrites them in the output, or streams them into the io::CloudWriter.
//
// Memory (GenerateOptions::memory_budget_bytes, --memory-mb): before the BVH is built a
// MemoryPlan sizes the buffers against the budget: fewer views per batch first, then a
// view traced in bands of rows (tiles), then fewer threads; a run that cannot fit even
// then is refused. Batches, bands and threads change no output bit.
#include <sim/generator.hpp>

#include "fuse.hpp"
#include "memory_plan.hpp"
#include "parallel.hpp"
#include "terrain_stage.hpp"
#include "true_terrain.hpp"

#include <core/error.hpp>
#include <core/jet.hpp>
#include <core/scene_info.hpp>
#include <io/copc_writer.hpp>
#include <io/point_packing.hpp>
#include <platform/progress.hpp>
#include <platform/scratch_file.hpp>
#include <sim/sensor.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <future>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

namespace sim {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr std::size_t kBatchRays = 1u << 19;    // rays per batch of views (memory bound)
constexpr std::size_t kColourChunk = 1u << 20;  // points per colour/write chunk

std::string mebibytes(std::uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20); }

// The fused cloud on disk, in a platform::ScratchFile in the output's folder, so nothing
// of it outlives the process. Each point is packed (io::PointPacking) with the fields the
// run writes but its colour, and its position, view, label and returns: what the stages
// after the fusion read (ground classification, the kept shares) and what the writer
// writes. A fused point's colour is white (ground, or --white) or not yet made (0): where
// the run writes colours, one byte says which. 22 bytes for the ideal sensor's cloud
// instead of a CloudPoint's 40. `path_` (the output) names it in messages.
class Spool {
  public:
    Spool(std::filesystem::path path, const core::CloudFields& fields)
        : path_(std::move(path)),
          packing_(withoutColour(fields)),
          white_flag_(fields.rgb),
          file_(path_.parent_path().empty() ? std::filesystem::path(".") : path_.parent_path(), path_.string()) {}

    /// Bytes a point takes in the spool.
    std::size_t recordBytes() const { return packing_.size() + (white_flag_ ? 1 : 0); }
    /// Bytes the spool holds in memory while points are appended.
    std::size_t bufferBytes() const { return kBlock * recordBytes(); }

    void append(std::span<const core::CloudPoint> points) {
        const std::size_t size = recordBytes();
        while (!points.empty()) {
            const std::size_t n = std::min(points.size(), kBlock);
            bytes_.resize(n * size);
            pack(points.first(n), bytes_.data());
            appendPacked(bytes_.data(), n);
            points = points.subspan(n);
        }
    }
    /// Packs `points` into `out` (recordBytes() each) as append() spools them; const, so
    /// several threads may pack at once.
    void pack(std::span<const core::CloudPoint> points, unsigned char* out) const {
        const std::size_t size = recordBytes(), packed = packing_.size();
        for (const core::CloudPoint& p : points) {
            packing_.pack(p, out);
            if (white_flag_) {
                if (p.rgb != core::kWhite && p.rgb != 0)
                    throw std::logic_error("generate: a fused point is coloured before the colour pass");
                out[packed] = p.rgb == core::kWhite;
            }
            out += size;
        }
    }
    /// Appends `n` points pack() packed.
    void appendPacked(const unsigned char* records, std::size_t n) {
        const std::size_t size = recordBytes();
        if (const int e = file_.tryAppend(records, n * size); e != 0)
            throw core::Error("output: " + path_.string() + ": cannot write the spool file after " +
                              mebibytes(count_ * size) + " MiB: " + std::strerror(e));
        count_ += n;
    }
    void rewind() {
        if (file_.tryRewind() != 0) throw core::Error("output: " + path_.string() + ": cannot rewind spool file");
    }
    /// Reads up to out.size() points; returns how many.
    std::size_t read(std::span<core::CloudPoint> out) {
        const std::size_t packed = packing_.size();
        return readWith(out, [&](const unsigned char* in, core::CloudPoint& p) {
            p = packing_.unpack(in);  // white, where the run writes no colours
            if (white_flag_) p.rgb = in[packed] ? core::kWhite : 0;
        });
    }
    /// As read(), setting only the points' positions (the rest of `out` is left as it was).
    std::size_t readPositions(std::span<core::CloudPoint> out) {
        return readWith(
            out, [](const unsigned char* in, core::CloudPoint& p) { p.position = io::PointPacking::position(in); });
    }
    std::size_t count() const { return count_; }
    /// Frees the whole pages before the read position, read for the last time: their bytes
    /// need not reach the disk, and their memory serves the output being written. Where the
    /// file system cannot punch holes the bytes stay, which costs only time.
    void discardRead() { file_.discardRead(); }

  private:
    static constexpr std::size_t kBlock = 4096;  // points packed or unpacked at once

    static core::CloudFields withoutColour(core::CloudFields fields) {
        fields.rgb = false;
        return fields;
    }

    template <typename Unpack>
    std::size_t readWith(std::span<core::CloudPoint> out, Unpack unpack) {
        const std::size_t size = recordBytes();
        std::size_t done = 0;
        while (done < out.size()) {
            const std::size_t want = std::min(out.size() - done, kBlock);
            bytes_.resize(want * size);
            const std::size_t n = file_.readUpTo(bytes_.data(), want * size) / size;
            for (std::size_t i = 0; i < n; ++i) unpack(bytes_.data() + i * size, out[done + i]);
            done += n;
            if (n < want) break;
        }
        return done;
    }

    std::filesystem::path path_;
    io::PointPacking packing_;
    bool white_flag_;  // a byte after each packed point: 1 white, 0 not yet coloured
    std::vector<unsigned char> bytes_;
    platform::ScratchFile file_;
    std::size_t count_ = 0;
};

// Pixels of one view that are traced: columns [x0, x1] x rows [y0, y1] (inclusive).
struct PixelRect {
    int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
    bool contains(int px, int py) const { return px >= x0 && px <= x1 && py >= y0 && py <= y1; }
    std::uint64_t count() const {
        return x1 < x0 || y1 < y0 ? 0 : std::uint64_t(x1 - x0 + 1) * std::uint64_t(y1 - y0 + 1);
    }
};

// The pixels of a pinhole at `T_local_sensor` whose rays can meet the box `b` (local
// frame): the box's 8 corners projected with pixelDirection's inverse, padded by one
// pixel plus the float slack of the rays. A corner at or behind the image plane (the
// box reaches the sensor's side) gives the whole image: no skip, never a wrong one.
PixelRect visiblePixels(const OrbitOptions& o, const core::Pose& T_local_sensor, const core::Bounds& b,
                        double extra_margin_rad = 0.0) {
    const PixelRect all{0, o.xres - 1, 0, o.yres - 1};
    if (b.empty()) return PixelRect{};
    const double focal_px = 0.5 * double(o.yres) / std::tan(0.5 * o.fov_deg * std::numbers::pi / 180.0);
    // Rays are built in float from float origins: pad the box by far more than their error.
    const glm::dvec3 t = T_local_sensor.translation;
    const double scale = std::max({glm::length(b.hi - b.lo), glm::length(b.lo - t), glm::length(b.hi - t), 1.0});
    const double pad_m = 1e-4 * scale;
    const glm::dvec3 lo = b.lo - pad_m, hi = b.hi + pad_m;
    const glm::dmat3 R_sensor_local = glm::transpose(T_local_sensor.rotation);
    double u_min = std::numeric_limits<double>::infinity(), u_max = -u_min, v_min = u_min, v_max = -u_min;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        const glm::dvec3 q = R_sensor_local * (p - t);
        if (!(q.z > 1e-6 * scale)) return all;
        // Inverse of pixelDirection: pixel px's ray has x/z = (px + 0.5 - xres/2) / focal.
        const double u = q.x / q.z * focal_px + 0.5 * double(o.xres) - 0.5;
        const double v = q.y / q.z * focal_px + 0.5 * double(o.yres) - 0.5;
        u_min = std::min(u_min, u);
        u_max = std::max(u_max, u);
        v_min = std::min(v_min, v);
        v_max = std::max(v_max, v);
    }
    const double margin_px = 1.0 + 1e-4 * focal_px + extra_margin_rad * focal_px;
    const auto lowPixel = [&](double x, int n) { return int(std::clamp(std::floor(x - margin_px), -1.0, double(n))); };
    const auto highPixel = [&](double x, int n) { return int(std::clamp(std::ceil(x + margin_px), -1.0, double(n))); };
    PixelRect r{std::max(0, lowPixel(u_min, o.xres)), std::min(o.xres - 1, highPixel(u_max, o.xres)),
                std::max(0, lowPixel(v_min, o.yres)), std::min(o.yres - 1, highPixel(v_max, o.yres))};
    if (r.x0 > r.x1 || r.y0 > r.y1) return PixelRect{};
    return r;
}

}  // namespace

void validate(const GenerateOptions& o) {
    validate(o.orbit);
    validate(o.colour);
    validate(o.ground);
    validate(o.sensor);
    if (o.threads < 0 || o.threads > 1024)
        throw core::Error("generate: threads (--threads) = " + std::to_string(o.threads) +
                          ": allowed [0, 1024] (0 = all cores)");
    if (!(std::isfinite(o.drone_speed_mps) && o.drone_speed_mps > 0.0 && o.drone_speed_mps <= 1e4))
        throw core::Error("generate: drone speed (--drone-speed-mps) = " + core::shownNumber(o.drone_speed_mps) +
                          ": allowed (0, 10000] m/s");
    if (o.centre &&
        !(std::abs(o.centre->x) <= core::kMaxWorldCoordinate_m &&
          std::abs(o.centre->y) <= core::kMaxWorldCoordinate_m && std::abs(o.centre->z) <= core::kMaxWorldCoordinate_m))
        throw core::Error("generate: centre (--centre) = " + core::shownNumber(o.centre->x) + "," +
                          core::shownNumber(o.centre->y) + "," + core::shownNumber(o.centre->z) +
                          ": allowed x,y,z in [-" + core::shownNumber(core::kMaxWorldCoordinate_m) + ", " +
                          core::shownNumber(core::kMaxWorldCoordinate_m) + "] world metres");
    if (o.roles.bits == 0 || o.roles.bits > 0b111)
        throw core::Error("generate: roles (--roles): allowed a non-empty subset of ground, environment, target");
    if (o.memory_budget_bytes == 0) throw core::Error("generate: memory_budget_bytes = 0: allowed > 0");
    if (o.copc_node_points < io::kLeastNodeCap || o.copc_node_points > io::kMostNodeCap)
        throw core::Error("generate: node points (--node-points) = " + std::to_string(o.copc_node_points) +
                          ": allowed " + std::to_string(io::kLeastNodeCap) + " to " + std::to_string(io::kMostNodeCap));
}

glm::dvec3 defaultCentre(const core::Scene& scene) {
    core::Bounds all, target, ground;
    for (const core::Mesh& m : scene.meshes) {
        if (m.triangles.empty()) continue;
        for (const glm::uvec3& t : m.triangles)
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 p(m.vertices[t[k]]);
                all.extend(p);
                if (m.role == core::Role::Target) target.extend(p);
                if (m.role == core::Role::Ground) ground.extend(p);
            }
    }
    if (all.empty()) throw core::Error("generate: scene '" + scene.source.string() + "' has no triangles");
    const glm::dvec3 xy = target.empty() ? all.centre() : target.centre();
    const std::optional<double> ground_z = core::groundHeightAt(scene, xy.x, xy.y);
    const double z = ground_z ? *ground_z : ground.empty() ? all.lo.z : ground.lo.z;
    return scene.origin + glm::dvec3(xy.x, xy.y, z);
}

struct Generator::State {
    const core::Scene& scene;
    GenerateOptions options;
    glm::dvec3 centre_world{0.0}, centre_local{0.0};
    std::unique_ptr<RayCaster> caster;
    std::unique_ptr<Sensor> sensor;            // makes each pixel's rays and turns hits into returns
    std::vector<SensorView> sensor_views;      // per view, the pose logged and the pose flown
    std::vector<core::Pose> true_from_placed;  // per view, a placed point to where its ray hit
    std::size_t slots_per_pixel = 1;           // return slots per pixel (Sensor::slotsPerPixel)
    double bvh_seconds = 0.0;
    MemoryPlan plan;                // batches, bands and threads within the budget
    std::uint64_t hits_bound = 0;   // hits all views can give together (traced pixels)
    std::vector<core::Pose> poses;  // per view, T_local_sensor
    std::vector<PixelRect> traced;  // per view, the pixels traced (all without skip_rays)
    // Per (view, row), the columns traced [x0, x1] when the boxes are per mesh (a union of
    // rectangles is no rectangle); empty: `traced` alone. See traceablePixels().
    std::vector<glm::ivec2> row_spans;
    std::vector<std::uint64_t> traced_count;  // per view, rays traced
    std::vector<std::uint32_t> jet;
    // options.ground.method's filter: exactly one of the two, unless the run is white.
    std::unique_ptr<const ViewGroundFilter> view_filter;
    std::unique_ptr<const CloudGroundFilter> cloud_filter;
    // The scene's true terrain over the covered disc, to count the points kept coloured.
    std::unique_ptr<const TrueTerrain> true_terrain;

    State(const core::Scene& s, GenerateOptions o) : scene(s), options(std::move(o)) {}

    // Whether a per-view filter's result is checked on a fitted terrain: only where ground
    // labels cannot measure it (no ground mesh is ray-cast), or where the terrain is wanted.
    bool checkTerrain() const {
        if (options.fit_terrain) return true;
        if (!options.ground_check) return false;
        for (const core::Mesh& m : scene.meshes)
            if (m.role == core::Role::Ground && options.roles.has(m.role)) return false;
        return true;
    }

    // Pixels [begin, end) of `view` (row-major) into their slots: those outside the
    // view's traced rectangle are misses without a ray, the others are cast by row runs.
    void castBlock(int view, std::size_t begin, std::size_t end, const FuseBand& band) const {
        const PixelRect& r = traced[std::size_t(view)];
        const std::size_t xres = std::size_t(options.orbit.xres), yres = std::size_t(options.orbit.yres);
        std::size_t i = begin;
        while (i < end) {
            const std::size_t row = i / xres, row_end = std::min(end, (row + 1) * xres);
            std::size_t a = row_end, b = row_end;  // traced run [a, b) of this row
            if (int(row) >= r.y0 && int(row) <= r.y1) {
                glm::ivec2 span(r.x0, r.x1);
                if (!row_spans.empty()) span = row_spans[std::size_t(view) * yres + row];
                if (span.x <= span.y) {
                    a = std::clamp(row * xres + std::size_t(span.x), i, row_end);
                    b = std::clamp(row * xres + std::size_t(span.y) + 1, i, row_end);
                }
            }
            const std::size_t n = slots_per_pixel;
            for (std::size_t k = i * n; k < a * n; ++k) band.slots[k - band.first * n].range_m = kNoReturn;
            // Paper §III-B: the sensor traces the run [a, b) (16-ray packets of consecutive
            // pixels with packet_rays) and fills its slots.
            if (a < b)
                sensor->trace(*caster, sensor_views[std::size_t(view)], a,
                              std::span(band.dirs + (a - band.first), b - a),
                              std::span(band.slots + (a - band.first) * n, (b - a) * n), options.packet_rays);
            for (std::size_t k = std::max(a, b) * n; k < row_end * n; ++k)
                band.slots[k - band.first * n].range_m = kNoReturn;
            i = row_end;
        }
    }

    // Runs every view and hands the fused points, in (view, row, column) order, to
    // `emit` (FusePipeline, with castBlock casting).
    void fuseViews(const FuseEmit& emit, Workers& pool, GenerateStats& st, std::uint64_t emit_bytes,
                   const FusePacking* packing = nullptr) const;

    // Counts the target and environment points more than kAboveTerrain_m above the true
    // terrain, and those of them left coloured. A point is placed with its view's logged
    // pose while its ray left from the pose flown; its height is judged where the ray
    // really hit (the point carried from the logged pose to the flown one), so a view
    // that a pose error lifts does not count the target's tracks as standing above.
    void countKept(std::span<const core::CloudPoint> points, Workers& pool, GenerateStats& st) const {
        if (options.white || !true_terrain) return;
        const std::size_t chunk = 1u << 16;
        const std::size_t tasks = (points.size() + chunk - 1) / chunk;
        std::vector<std::array<std::uint64_t, 4>> counts(tasks, {0, 0, 0, 0});
        pool.run(tasks, [&](std::size_t task) {
            auto& c = counts[task];
            const std::size_t end = std::min(points.size(), (task + 1) * chunk);
            for (std::size_t i = task * chunk; i < end; ++i) {
                const core::CloudPoint& p = points[i];
                if (p.label == core::Role::Ground || p.view >= true_from_placed.size()) continue;
                const glm::dvec3 hit = true_from_placed[p.view].apply(glm::dvec3(p.position));
                double z = 0;
                if (!true_terrain->heightAt(hit.x, hit.y, z) || hit.z - z <= kAboveTerrain_m) continue;
                const std::size_t k = p.label == core::Role::Target ? 0 : 2;
                c[k] += 1;
                c[k + 1] += p.rgb != core::kWhite;
            }
        });
        for (const auto& c : counts) {
            st.target_above_terrain += c[0];
            st.target_kept_points += c[1];
            st.environment_above_terrain += c[2];
            st.environment_kept_points += c[3];
        }
    }

    // Jet colours for every point that is not white, from the fused z range.
    void colour(std::span<core::CloudPoint> points, Workers& pool, const GenerateStats& st) const {
        if (options.white) return;
        const std::size_t chunk = 1u << 16;
        const std::size_t tasks = (points.size() + chunk - 1) / chunk;
        pool.run(tasks, [&](std::size_t task) {
            const std::size_t end = std::min(points.size(), (task + 1) * chunk);
            for (std::size_t i = task * chunk; i < end; ++i)
                if (points[i].rgb != core::kWhite)
                    points[i].rgb = heightColour(points[i].position.z, st.z_min, st.z_max, jet);
        });
    }
};

void Generator::State::fuseViews(const FuseEmit& emit, Workers& pool, GenerateStats& st, std::uint64_t emit_bytes,
                                 const FusePacking* packing) const {
    FuseSetup setup;
    setup.orbit = options.orbit;
    setup.plan = plan;
    setup.budget_bytes = options.memory_budget_bytes;
    setup.white = options.white;
    setup.progress = options.progress;
    setup.seed = options.seed;
    setup.view_filter = view_filter.get();
    setup.slots_per_pixel = slots_per_pixel;
    setup.rays_per_pixel = sensor->raysPerPixel();
    setup.traced_count = traced_count;
    setup.cast_block = [this](int view, std::size_t begin, std::size_t end, const FuseBand& band) {
        castBlock(view, begin, end, band);
    };
    FusePipeline(setup, pool, st, emit_bytes, packing, emit).run();
}

Generator::Generator(const core::Scene& scene, GenerateOptions options)
    : state_(std::make_unique<State>(scene, std::move(options))) {
    State& s = *state_;
    validate(s.options);
    s.centre_world = s.options.centre ? *s.options.centre : defaultCentre(scene);
    s.centre_local = s.centre_world - scene.origin;
    validatePlacement(s.options.orbit, s.centre_local);
    const OrbitOptions& orbit = s.options.orbit;
    for (int v = 0; v < orbit.views; ++v) s.poses.push_back(sensorPose(orbit, s.centre_local, v));
    s.sensor = std::make_unique<Sensor>(s.options.sensor, orbit, scene, s.options.seed);
    s.slots_per_pixel = s.sensor->slotsPerPixel();
    for (int v = 0; v < orbit.views; ++v) s.sensor_views.push_back(s.sensor->view(v, s.poses[std::size_t(v)]));
    for (const SensorView& v : s.sensor_views) {
        const glm::dmat3 r = v.actual.rotation * glm::transpose(v.nominal.rotation);
        s.true_from_placed.push_back(core::Pose{r, v.actual.translation - r * v.nominal.translation});
    }
    // Rays leave from the pose actually flown, and a beam's sub-rays spread up to half its
    // divergence off the pixel's axis: the traced pixels are found for both.
    const SensorOptions& so = s.options.sensor;
    const double spread_rad = 0.5e-3 * std::max(so.beam_divergence_mrad, so.beam_divergence_y_mrad);
    s.jet = core::jetTable(s.options.colour.entries);
    if (!s.options.white) {
        s.view_filter = makeViewFilter(s.options.ground);
        s.cloud_filter = makeCloudFilter(s.options.ground);
        // The covered disc and a margin for what stands at its edge.
        auto truth = std::make_unique<TrueTerrain>(scene, s.centre_local.x, s.centre_local.y,
                                                   0.5 * coverageDiameter(orbit) + 20.0);
        if (!truth->empty()) s.true_terrain = std::move(truth);
    }
    // Bounds of the triangles to ray-cast, one box per mesh (with --roles
    // target,environment the houses and trees are scattered: one box over all of them
    // would cover the whole footprint). Many meshes, or more (view, row) spans than fit
    // comfortably in the memory budget: one box over all (the same cloud either way).
    constexpr std::size_t kMaxBoxes = 256, kMaxSpanRows = std::size_t(1) << 22;
    std::vector<core::Bounds> boxes;
    core::Bounds cast_bounds;
    for (const core::Mesh& m : scene.meshes) {
        if (!s.options.roles.has(m.role) || m.triangles.empty()) continue;
        core::Bounds b;
        for (const glm::uvec3& t : m.triangles)
            for (int k = 0; k < 3; ++k) b.extend(glm::dvec3(m.vertices[t[k]]));
        boxes.push_back(b);
        cast_bounds.extend(b);
    }
    const std::size_t views = std::size_t(orbit.views), yres = std::size_t(orbit.yres);
    const std::uint64_t budget = s.options.memory_budget_bytes;
    if (boxes.size() > kMaxBoxes || views * yres > kMaxSpanRows || views * yres * sizeof(glm::ivec2) > budget / 8)
        boxes.assign(1, cast_bounds);
    const PixelRect all{0, orbit.xres - 1, 0, orbit.yres - 1};
    const bool spans = s.options.skip_rays && boxes.size() > 1;
    if (spans) s.row_spans.assign(views * yres, glm::ivec2(orbit.xres, -1));
    for (std::size_t v = 0; v < views; ++v) {
        if (!s.options.skip_rays) {
            s.traced.push_back(all);
            s.traced_count.push_back(all.count());
            continue;
        }
        if (!spans) {
            s.traced.push_back(visiblePixels(orbit, s.sensor_views[v].actual, cast_bounds, spread_rad));
            s.traced_count.push_back(s.traced.back().count());
            continue;
        }
        PixelRect hull{orbit.xres, -1, orbit.yres, -1};
        glm::ivec2* row = s.row_spans.data() + v * yres;
        for (const core::Bounds& b : boxes) {
            const PixelRect r = visiblePixels(orbit, s.sensor_views[v].actual, b, spread_rad);
            if (r.count() == 0) continue;
            hull = {std::min(hull.x0, r.x0), std::max(hull.x1, r.x1), std::min(hull.y0, r.y0), std::max(hull.y1, r.y1)};
            for (int y = r.y0; y <= r.y1; ++y) row[y] = glm::ivec2(std::min(row[y].x, r.x0), std::max(row[y].y, r.x1));
        }
        std::uint64_t n = 0;
        for (std::size_t y = 0; y < yres; ++y)
            if (row[y].x <= row[y].y) n += std::uint64_t(row[y].y - row[y].x + 1);
        s.traced.push_back(hull.count() == 0 ? PixelRect{} : hull);
        s.traced_count.push_back(n);
    }

    // The buffers, planned against the budget before the BVH is built.
    MemoryNeeds needs;
    needs.xres = std::uint64_t(orbit.xres);
    needs.yres = std::uint64_t(orbit.yres);
    needs.views = std::uint64_t(orbit.views);
    for (const std::uint64_t n : s.traced_count) {
        needs.view_hits = std::max(needs.view_hits, n * s.slots_per_pixel);
        s.hits_bound += n * s.slots_per_pixel;
    }
    needs.fixed_bytes = views * (sizeof(core::Pose) + sizeof(PixelRect) + sizeof(std::uint64_t)) +
                        s.row_spans.size() * sizeof(glm::ivec2) + s.jet.size() * sizeof(std::uint32_t) +
                        s.sensor->tableBytes();
    needs.white = s.options.white;
    needs.slots_per_pixel = s.slots_per_pixel;
    needs.thread_scratch_bytes = s.sensor->scratchBytes();
    needs.threads = resolveThreads(s.options.threads);
    // Views per batch: about kBatchRays rays, and two views a thread, so that a batch's
    // views can be whitened side by side; but a view of kBatchRays / 2 pixels or more goes
    // alone. Its own blocks keep the workers busy, its hits are whitened and handed on
    // while the next view is cast, and such runs measured faster one view a batch than
    // four, streamed and in memory.
    const std::size_t view_pixels = std::size_t(orbit.xres) * yres;
    needs.batch_views =
        view_pixels >= kBatchRays / 2
            ? 1
            : std::clamp<std::size_t>(std::max<std::size_t>(kBatchRays / view_pixels, 2 * std::size_t(needs.threads)),
                                      1, views);
    needs.budget_bytes = budget;
    s.plan = planMemory(needs);

    const auto t0 = Clock::now();
    s.caster = std::make_unique<RayCaster>(scene, s.options.roles);
    s.bvh_seconds = secondsSince(t0);
}

Generator::~Generator() = default;

namespace {

void initStats(const Generator::State& s, GenerateStats& st) {
    const GenerateOptions& o = s.options;
    st = GenerateStats{};
    st.skipped_zero_area_triangles = s.scene.skipped_triangles;
    st.skipped_nonfinite_triangles = s.scene.skipped_nonfinite_triangles;
    st.drone_radius_m = droneRadius(o.orbit);
    st.length_sensed_m = lengthSensed(o.orbit);
    st.coverage_diameter_m = coverageDiameter(o.orbit);
    st.centre = s.centre_world;
    st.triangles = s.caster->triangleCount();
    st.threads = s.plan.threads;
    st.batch_views = s.plan.batch_views;
    st.band_rows = s.plan.band_rows;
    st.memory_planned_bytes = s.plan.fuse_bytes;
    st.seconds.bvh = s.bvh_seconds;
    st.ground_method = o.ground.method;
}

// The cloud in memory: every view fused into `points` (the terrain stage's pass 1 on the
// way), the terrain fitted, then pass 2 and the colours over all of them.
void fuseFitColour(const Generator::State& s, std::vector<core::CloudPoint>& points, TerrainStage& terrain,
                   Workers& pool, GenerateStats& st) {
    s.fuseViews(
        [&](std::span<const core::CloudPoint> pts, std::span<const unsigned char>) {
            points.insert(points.end(), pts.begin(), pts.end());
            terrain.add(pts);
        },
        pool, st, s.hits_bound * sizeof(core::CloudPoint));
    terrain.fit();
    terrain.classify(points, pool);
    const auto t0 = Clock::now();
    s.colour(points, pool, st);
    s.countKept(points, pool, st);
    st.seconds.colour = secondsSince(t0);
}

void keptShares(GenerateStats& st) {
    if (st.target_above_terrain > 0) st.target_kept = double(st.target_kept_points) / double(st.target_above_terrain);
    if (st.environment_above_terrain > 0)
        st.environment_kept = double(st.environment_kept_points) / double(st.environment_above_terrain);
}

}  // namespace

core::PointCloud Generator::run(GenerateStats* stats) {
    const State& s = *state_;
    const auto t0 = Clock::now();
    GenerateStats st;
    initStats(s, st);
    Workers pool(s.plan.threads);
    core::PointCloud cloud;
    cloud.origin = s.scene.origin;
    cloud.fields = s.sensor->fields();
    // The cloud is the caller's: reserved up to the budget, beyond it grown as needed.
    cloud.points.reserve(
        std::size_t(std::min<std::uint64_t>(s.hits_bound, s.options.memory_budget_bytes / sizeof(core::CloudPoint))));
    TerrainStage terrain(s.cloud_filter.get(), s.options.ground.smrf, s.options.white, s.checkTerrain());
    cloud.fields.height_above_ground = terrain.whitens();
    fuseFitColour(s, cloud.points, terrain, pool, st);
    terrain.finish(st);
    keptShares(st);
    st.seconds.total = s.bvh_seconds + secondsSince(t0);
    if (stats) *stats = st;
    return cloud;
}

static io::LasOptions lasOptions(const core::Scene& scene, const GenerateOptions& o) {
    io::LasOptions las = o.las;  // drone_speed_mps is checked by validate()
    las.view_interval_s = 2.0 * std::numbers::pi * droneRadius(o.orbit) / o.orbit.views / o.drone_speed_mps;
    for (int r = 0; r < core::kRoleCount; ++r) {
        int cls = -1;
        for (const core::Mesh& m : scene.meshes) {
            if (int(m.role) != r || m.asprs_class < 0) continue;
            if (cls >= 0 && cls != m.asprs_class)
                throw core::Error("generate: " + scene.source.string() + ": " +
                                  std::string(core::roleName(core::Role(r))) +
                                  " meshes give different ASPRS classes (" + std::to_string(cls) + ", " +
                                  std::to_string(m.asprs_class) +
                                  "); LAS output holds one class per role, since a point records its role");
            cls = m.asprs_class;
        }
        if (cls >= 0) las.class_of_role[r] = std::uint8_t(cls);
    }
    return las;
}

namespace {

// What the output is written with: its fields, the LAS/LAZ writer's threads and memory,
// COPC's node size and memory.
struct OutputSetup {
    core::CloudFields fields;
    io::LasOptions las;
    io::CopcOptions copc;
};

// The output's fields and its writer's options for a run to `format`; sets st.streamed
// (the fused cloud does not stay in memory). Throws core::Error when COPC output cannot
// have the memory it needs beside the run, or the scene's classes do not fit LAS.
OutputSetup planOutput(const Generator::State& s, io::CloudFormat format, bool whitens, GenerateStats& st) {
    OutputSetup o;
    const bool las =
        format == io::CloudFormat::Las || format == io::CloudFormat::Laz || format == io::CloudFormat::Copc;
    o.fields = s.sensor->fields();
    o.fields.height_above_ground = whitens;
    o.fields.rgb = !(las && s.options.white);  // LAS point format 6: no colours to store
    // The fused cloud stays in memory when it fits beside the fusion's buffers and, for
    // COPC, leaves the writer the least it needs (else it goes through the spool, which
    // holds a chunk of it at a time: the same file).
    const std::uint64_t budget = s.options.memory_budget_bytes;
    const std::uint64_t fused_bytes = s.hits_bound * sizeof(core::CloudPoint);
    const std::uint64_t copc_least =
        format == io::CloudFormat::Copc
            ? io::copcMinimumBytes(s.plan.threads, std::uint32_t(s.options.copc_node_points))  // validated
            : 0;
    st.streamed = s.plan.fuse_bytes + fused_bytes > budget ||
                  s.plan.kept_bytes - s.plan.writer_bytes + fused_bytes + copc_least > budget;
    // LAZ compresses on the workers, once the fusion's buffers are gone, in what the
    // budget leaves beside the cloud (in memory, or the chunk read back from the spool).
    o.las = lasOptions(s.scene, s.options);
    o.las.threads = s.plan.threads;
    const std::uint64_t held = s.plan.kept_bytes - s.plan.writer_bytes +
                               (st.streamed ? s.plan.colour_chunk * sizeof(core::CloudPoint) : fused_bytes);
    o.las.memory_bytes = std::max(s.plan.writer_bytes, budget - std::min(budget, held));
    o.copc.max_node_points = std::uint32_t(s.options.copc_node_points);  // validated
    if (format == io::CloudFormat::Copc) {
        // The COPC writer holds the points until it has built the octree, within what the
        // run leaves it; past that it spills them to scratch files beside the output and
        // builds the octree a part at a time (the same file).
        const std::uint64_t room = budget - std::min(budget, held);
        const std::uint64_t least = io::copcMinimumBytes(s.plan.threads, o.copc.max_node_points);
        if (room < least)
            throw core::Error("generate: COPC output needs " + std::to_string((least >> 20) + 1) + " MiB beside the " +
                              std::to_string(held >> 20) + " MiB the run holds, more than --memory-mb " +
                              std::to_string(budget >> 20) +
                              " leaves; raise --memory-mb, or write .laz and convert it with 'ladarvr index'");
        o.copc.memory_bytes = room;
    }
    return o;
}

// The cloud in memory: fused, fitted and coloured (fuseFitColour), then written.
void writeInMemory(const Generator::State& s, io::CloudWriter& writer, TerrainStage& terrain, Workers& pool,
                   GenerateStats& st) {
    std::vector<core::CloudPoint> points;
    points.reserve(std::size_t(s.hits_bound));
    fuseFitColour(s, points, terrain, pool, st);
    const auto tc = Clock::now();
    for (std::size_t i = 0; i < points.size(); i += kColourChunk)
        writer.append(std::span(points).subspan(i, std::min(kColourChunk, points.size() - i)));
    st.seconds.write = secondsSince(tc);
}

// The fused cloud streamed: fused into the output itself or into a spool (fuse), the
// terrain fitted, the spool's positions shown to a writer that asks to see them first
// (prescan), then read back a chunk at a time, classified and coloured, and appended or
// rewritten (colourBack). Each pass reads one half of the chunk back on a thread of its
// own while the writer takes the other half.
class StreamedWrite {
  public:
    StreamedWrite(const Generator::State& s, const std::filesystem::path& out, io::CloudFormat format,
                  const core::CloudFields& fields, io::CloudWriter& writer, TerrainStage& terrain, Workers& pool,
                  GenerateStats& st)
        : s_(s),
          out_(out),
          format_(format),
          fields_(fields),
          writer_(writer),
          terrain_(terrain),
          pool_(pool),
          st_(st) {}

    void run() {
        fuse();
        terrain_.fit();
        chunk_.resize(s_.plan.colour_chunk);
        overlap_ = chunk_.size() >= 2;
        const std::size_t half = overlap_ ? chunk_.size() / 2 : chunk_.size();
        halves_ = {std::span(chunk_).first(half), std::span(chunk_).last(half)};
        if (spool_) prescan();
        colourBack();
        if (prepared_ != st_.points || writer_.count() != st_.points)
            throw core::Error("output: " + out_.string() + ": the fused points came back short");
    }

  private:
    void fuse();
    void prescan();
    std::size_t prepare(std::size_t h);
    void colourBack();

    const Generator::State& s_;
    const std::filesystem::path& out_;
    io::CloudFormat format_;
    const core::CloudFields& fields_;
    io::CloudWriter& writer_;
    TerrainStage& terrain_;
    Workers& pool_;
    GenerateStats& st_;
    std::optional<Spool> spool_;  // none: the fused points are in the output (st.in_output)
    // The positions' bounds, for a writer that asks to see the points first.
    glm::vec3 lo_{std::numeric_limits<float>::infinity()}, hi_{-std::numeric_limits<float>::infinity()};
    std::vector<core::CloudPoint> chunk_;  // the points read back, in two halves
    bool overlap_ = false;                 // each half read on a thread of its own
    std::array<std::span<core::CloudPoint>, 2> halves_;
    std::uint64_t prepared_ = 0;                 // points read back so far
    std::array<std::uint64_t, 2> firsts_{0, 0};  // the index of each half's first point
};

// Where the output's records can be read back and rewritten (binary PCD and PLY, which
// carry every field the stages after the fusion read: position, view, label and colour),
// the fused points go straight into it and the last pass classifies and colours them
// there: written once, never copied. Otherwise they go through the spool, packed with the
// fields the run writes (white LAS has no colour field, and every point is white, as
// unpacking gives it).
void StreamedWrite::fuse() {
    st_.in_output = writer_.rewritable() && fields_.rgb && fields_.label && fields_.view;
    if (st_.in_output) {
        checkFreeSpace(out_.parent_path(), s_.hits_bound * writer_.recordBytes(), "the output");
    } else {
        spool_.emplace(out_, fields_);
        checkFreeSpace(out_.parent_path(), s_.hits_bound * spool_->recordBytes(), "the spool file of the fused cloud");
    }
    // The workers may pack the points as the spool or the output holds them.
    FusePacking packing;
    if (spool_) {
        packing.bytes_per_point = spool_->recordBytes();
        packing.pack = [this](std::span<const core::CloudPoint> pts, unsigned char* records) {
            spool_->pack(pts, records);
        };
    } else {
        packing.bytes_per_point = writer_.recordBytes();
        packing.pack = [this](std::span<const core::CloudPoint> pts, unsigned char* records) {
            writer_.packRecords(pts, reinterpret_cast<char*>(records));
        };
    }
    s_.fuseViews(
        [this](std::span<const core::CloudPoint> pts, std::span<const unsigned char> packed) {
            if (!packed.empty() && spool_)
                spool_->appendPacked(packed.data(), pts.size());
            else if (!packed.empty())
                writer_.appendRecords(std::span(reinterpret_cast<const char*>(packed.data()), packed.size()));
            else if (spool_)
                spool_->append(pts);
            else
                writer_.append(pts);  // its buffer is in the plan's fuse_bytes
            terrain_.add(pts);
            if (format_ == io::CloudFormat::Copc)
                for (const core::CloudPoint& p : pts) {
                    lo_ = glm::min(lo_, p.position);
                    hi_ = glm::max(hi_, p.position);
                }
        },
        pool_, st_, spool_ ? spool_->bufferBytes() : 0, &packing);
}

// A COPC writer past its bound sorts the points straight into its octree's parts once it
// has seen them: their bounds from the fusion, the spool as often as it asks (their
// positions, which classifying and colouring leave as they are).
void StreamedWrite::prescan() {
    const auto tp = Clock::now();
    core::Bounds positions;
    if (spool_->count() > 0) positions = core::Bounds{glm::dvec3(lo_), glm::dvec3(hi_)};
    const int passes = writer_.prescanPasses(spool_->count(), &positions);
    for (int pass = 0; pass < passes; ++pass) {
        spool_->rewind();
        std::size_t cur = 0, n = spool_->readPositions(halves_[0]);
        while (n > 0) {
            if (!overlap_) {
                writer_.prescan(pass, halves_[0].first(n));
                n = spool_->readPositions(halves_[0]);
                continue;
            }
            std::future<std::size_t> next = std::async(
                std::launch::async, [this, other = cur ^ 1] { return spool_->readPositions(halves_[other]); });
            writer_.prescan(pass, halves_[cur].first(n));
            n = next.get();
            cur ^= 1;
        }
    }
    st_.seconds.write += secondsSince(tp);
    spool_->rewind();
}

// Reads the next points back into half `h` (from the spool, or from the output),
// classifies and colours them; returns how many (0: all were read).
std::size_t StreamedWrite::prepare(std::size_t h) {
    auto tc = Clock::now();
    firsts_[h] = prepared_;
    const std::span<core::CloudPoint> part =
        halves_[h].first(spool_ ? spool_->read(halves_[h]) : writer_.readBack(prepared_, halves_[h]));
    if (spool_) spool_->discardRead();
    prepared_ += part.size();
    st_.seconds.colour += secondsSince(tc);
    terrain_.classify(part, pool_);
    tc = Clock::now();
    s_.colour(part, pool_, st_);
    s_.countKept(part, pool_, st_);
    st_.seconds.colour += secondsSince(tc);
    return part.size();
}

// The last pass: each half of the chunk is read back, classified and coloured on a
// thread of its own while the writer takes the other half (appended, or rewritten where
// it was read).
void StreamedWrite::colourBack() {
    std::size_t cur = 0, n = prepare(0);
    while (n > 0) {
        std::future<std::size_t> next;
        if (overlap_) next = std::async(std::launch::async, [this, other = cur ^ 1] { return prepare(other); });
        const auto tc = Clock::now();
        if (spool_)
            writer_.append(halves_[cur].first(n));
        else
            writer_.rewrite(firsts_[cur], halves_[cur].first(n));
        st_.seconds.write += secondsSince(tc);
        if (overlap_) {
            n = next.get();
            cur ^= 1;
        } else {
            n = prepare(0);
        }
    }
}

}  // namespace

void Generator::run(const std::filesystem::path& out, io::CloudFormat format, GenerateStats* stats,
                    const BeforeCommit& before_commit) {
    const State& s = *state_;
    const auto t0 = Clock::now();
    GenerateStats st;
    initStats(s, st);
    TerrainStage terrain(s.cloud_filter.get(), s.options.ground.smrf, s.options.white, s.checkTerrain());
    const OutputSetup setup = planOutput(s, format, terrain.whitens(), st);
    // Opens the temporary beside `out` now: a bad destination fails before any ray is cast,
    // and a failure later leaves nothing under `out`.
    io::CloudWriter writer(out, format, s.scene.origin, setup.fields, setup.las,
                           format == io::CloudFormat::Copc ? &setup.copc : nullptr);
    Workers pool(s.plan.threads);
    if (!st.streamed)
        writeInMemory(s, writer, terrain, pool, st);
    else
        StreamedWrite(s, out, format, setup.fields, writer, terrain, pool, st).run();
    terrain.finish(st);
    keptShares(st);
    if (before_commit) before_commit(st);
    const auto tc = Clock::now();
    writer.commit();
    st.seconds.write += secondsSince(tc);
    st.seconds.total = s.bvh_seconds + secondsSince(t0);
    if (stats) *stats = st;
}

void Generator::viewRays(int view, std::vector<Ray>& rays) const {
    const State& s = *state_;
    const core::Pose& pose = s.poses.at(std::size_t(view));
    const OrbitOptions& orbit = s.options.orbit;
    rays.resize(std::size_t(orbit.xres) * std::size_t(orbit.yres));
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const glm::dvec3 dir =
            pixelDirection(orbit, double(i % std::size_t(orbit.xres)), double(i / std::size_t(orbit.xres)));
        rays[i].origin = glm::vec3(pose.translation);
        rays[i].direction = glm::vec3(pose.rotation * dir);
        rays[i].t_far = std::numeric_limits<float>::infinity();
    }
}

const RayCaster& Generator::caster() const { return *state_->caster; }
const GenerateOptions& Generator::options() const { return state_->options; }
glm::dvec3 Generator::centreWorld() const { return state_->centre_world; }

core::PointCloud generateCloud(const core::Scene& scene, const GenerateOptions& options, GenerateStats* stats) {
    return Generator(scene, options).run(stats);
}

void generateToFile(const core::Scene& scene, const GenerateOptions& options, const std::filesystem::path& out,
                    io::CloudFormat format, GenerateStats* stats) {
    Generator(scene, options).run(out, format, stats);
}

}  // namespace sim
