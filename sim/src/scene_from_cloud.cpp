// sim/src/scene_from_cloud.cpp: see sim/scene_from_cloud.hpp. The survey is read in
// chunks: pass 1 measures its bounds and counts its class-2 points, an optional pass
// feeds the ground filter's TerrainFit, the next puts each ground point into the terrain
// grid's node nearest it, and the last each other point into its voxel. The vehicle's
// placement is scene_from_cloud_vehicle.cpp; the files, scene_from_cloud_write.cpp.
#include "ground_label.hpp"
#include "scene_from_cloud_internal.hpp"

#include <core/error.hpp>
#include <io/cloud_reader.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <memory>
#include <unordered_set>

namespace sim {

namespace {

constexpr const char* kWhere = "scene from-cloud";
// The widest survey taken: the voxels' indices (32-bit) then stay far from overflowing.
constexpr double kMaxExtent_m = 1e6;

std::string number(double v) { return core::shownNumber(v); }

struct VoxelKeyHash {
    std::size_t operator()(const std::array<std::int32_t, 3>& k) const {
        std::uint64_t h = std::uint32_t(k[0]);
        h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k[1]);
        h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k[2]);
        return std::size_t(h ^ (h >> 29));
    }
};
using VoxelSet = std::unordered_set<std::array<std::int32_t, 3>, VoxelKeyHash>;

// A point of the reader (local to `origin`, in the file's units) in the scene's local
// frame, metres.
glm::dvec3 toLocal(const glm::vec3& p, const glm::dvec3& origin, const CoordinateUnits& u, const glm::dvec3& offset) {
    const glm::dvec3 world = origin + glm::dvec3(p);
    return glm::dvec3(world.x * u.horizontal_m, world.y * u.horizontal_m, world.z * u.vertical_m) - offset;
}

struct Survey {
    glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{std::numeric_limits<double>::lowest()};
    std::size_t points = 0, class2 = 0;
    std::string warning;
};

// Pass 1: the bounds (metres) and the class-2 count.
Survey measure(const std::filesystem::path& file, const CoordinateUnits& u,
               const std::function<void(std::size_t)>& progress) {
    Survey s;
    io::CloudReader reader(file);
    const glm::dvec3 origin = reader.origin();
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
        for (const core::CloudPoint& p : chunk) {
            const glm::dvec3 m = toLocal(p.position, origin, u, glm::dvec3(0.0));
            s.lo = glm::min(s.lo, m);
            s.hi = glm::max(s.hi, m);
            s.class2 += p.label == core::Role::Ground;
        }
        s.points += chunk.size();
        progress(chunk.size());
    });
    s.warning = reader.warning();
    return s;
}

// The filter's pass: every point, in the local frame (metres), into its TerrainFit.
std::unique_ptr<TerrainFit> fitFilter(const std::filesystem::path& file, const CoordinateUnits& u,
                                      const glm::dvec3& offset, const SceneFromCloudOptions& o,
                                      const std::function<void(std::size_t)>& progress) {
    std::unique_ptr<TerrainFit> fit = startFit(o.ground, o.max_cells);
    io::CloudReader reader(file);
    const glm::dvec3 origin = reader.origin();
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
        for (core::CloudPoint& p : chunk) p.position = glm::vec3(toLocal(p.position, origin, u, offset));
        fit->add(chunk);
        progress(chunk.size());
    });
    fit->fit();
    return fit;
}

// The grid's spacing: the option, else 1.5 times the ground points' mean spacing over the
// survey's extent, rounded up to 0.5 m, within [1, 10] m.
double chooseCell(const SceneFromCloudOptions& o, const Survey& s, std::size_t ground_guess) {
    if (o.cell_m > 0) return o.cell_m;
    const double area = std::max(1.0, (s.hi.x - s.lo.x) * (s.hi.y - s.lo.y));
    const double spacing = std::sqrt(area / double(std::max<std::size_t>(ground_guess, 1)));
    return std::clamp(std::ceil(3.0 * spacing) / 2.0, 1.0, 10.0);
}

TerrainMesh startGrid(const glm::dvec3& lo, const glm::dvec3& hi, double cell, std::size_t max_cells) {
    TerrainMesh t;
    t.cell_m = cell;
    t.x0_m = std::floor(lo.x / cell) * cell;
    t.y0_m = std::floor(lo.y / cell) * cell;
    const double nx = std::round((hi.x - t.x0_m) / cell) + 1.0, ny = std::round((hi.y - t.y0_m) / cell) + 1.0;
    if (nx * ny > double(max_cells))
        throw core::Error(std::string(kWhere) + ": the terrain grid would have " + number(nx) + " x " + number(ny) +
                          " nodes at --cell-m " + number(cell) + "; allowed at most " + number(double(max_cells)) +
                          " nodes: raise --cell-m");
    t.nx = std::max(2, int(nx));
    t.ny = std::max(2, int(ny));
    return t;
}

// Every node without ground points gets the mean of its filled neighbours, nearest ones
// first (a breadth-first sweep from the observed nodes): a building's footprint takes the
// ground around it.
void fillEmpty(TerrainMesh& t, const std::vector<std::uint32_t>& counts) {
    std::vector<std::uint8_t> filled(counts.size());
    std::deque<std::size_t> queue;
    for (std::size_t n = 0; n < counts.size(); ++n)
        if (counts[n] > 0) {
            filled[n] = 1;
            queue.push_back(n);
        }
    std::vector<std::uint8_t> queued = filled;
    while (!queue.empty()) {
        const std::size_t n = queue.front();
        queue.pop_front();
        const int i = int(n % std::size_t(t.nx)), j = int(n / std::size_t(t.nx));
        double sum = 0;
        int k = 0;
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                const int a = i + di, b = j + dj;
                if ((di == 0 && dj == 0) || a < 0 || b < 0 || a >= t.nx || b >= t.ny) continue;
                const std::size_t m = std::size_t(b) * std::size_t(t.nx) + std::size_t(a);
                if (filled[m]) {
                    sum += t.z_m[m];
                    ++k;
                } else if (!queued[m]) {
                    queued[m] = 1;
                    queue.push_back(m);
                }
            }
        if (!filled[n]) {
            t.z_m[n] = float(sum / k);  // queued by a filled neighbour, so k >= 1
            filled[n] = 1;
        }
    }
}

// A voxel index of each occupied voxel at twice the edge: floor(i / 2) (an arithmetic shift).
VoxelSet coarser(const VoxelSet& set) {
    VoxelSet out;
    out.reserve(set.size());
    for (const auto& k : set) out.insert({k[0] >> 1, k[1] >> 1, k[2] >> 1});
    return out;
}

struct GroundTest {
    const TerrainFit* fit = nullptr;  // null: the file's class 2
    bool operator()(const core::CloudPoint& p) const {
        if (!fit) return p.label == core::Role::Ground;
        float height_m = 0;
        return fit->classify(p, height_m);
    }
};

// Calls fn(point) for every point of the survey in the local frame (metres; its
// position moved there), chunk by chunk.
void forEachLocal(const SceneFromCloud& s, const std::function<void(core::CloudPoint&)>& fn,
                  const std::function<void(std::size_t)>& progress) {
    io::CloudReader reader(s.survey);
    const glm::dvec3 origin = reader.origin();
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
        for (core::CloudPoint& p : chunk) {
            p.position = glm::vec3(toLocal(p.position, origin, s.units, s.offset_m));
            fn(p);
        }
        progress(chunk.size());
    });
}

// The ground pass: each ground point into the grid's node nearest it; the nodes' means,
// the empty ones filled.
void binGround(SceneFromCloud& s, const GroundTest& is_ground, const std::function<void(std::size_t)>& progress) {
    TerrainMesh& t = s.terrain;
    std::vector<double> sums(std::size_t(t.nx) * std::size_t(t.ny), 0.0);
    std::vector<std::uint32_t> counts(sums.size(), 0);
    forEachLocal(
        s,
        [&](core::CloudPoint& p) {
            if (!is_ground(p)) return;
            const int i = std::clamp(int(std::lround((p.position.x - t.x0_m) / t.cell_m)), 0, t.nx - 1);
            const int j = std::clamp(int(std::lround((p.position.y - t.y0_m) / t.cell_m)), 0, t.ny - 1);
            const std::size_t n = std::size_t(j) * std::size_t(t.nx) + std::size_t(i);
            sums[n] += p.position.z;
            ++counts[n];
            ++s.ground_points;
        },
        progress);
    if (s.ground_points == 0)
        throw core::Error(std::string(kWhere) + ": " + s.survey.string() + ": no ground points (" + s.ground_from +
                          "); allowed a survey with ground: try --ground-from filter");
    t.z_m.assign(sums.size(), 0.0f);
    for (std::size_t n = 0; n < sums.size(); ++n)
        if (counts[n] > 0) {
            t.z_m[n] = float(sums[n] / counts[n]);
            ++t.observed_nodes;
        }
    fillEmpty(t, counts);
}

// The boxes' pass: every other point into its voxel, unless it lies more than
// kSurveyLowOutlier_m below the terrain or more than max_height_m above it (noise,
// birds, multipath: a floating box would stand in the sensor's way).
void binOthers(SceneFromCloud& s, const SceneFromCloudOptions& o, const GroundTest& is_ground,
               const std::function<void(std::size_t)>& progress) {
    VoxelSet voxels;
    double voxel = o.voxel_m;
    forEachLocal(
        s,
        [&](core::CloudPoint& p) {
            if (is_ground(p)) return;
            const glm::dvec3 m(p.position);
            const double above = m.z - s.terrain.heightAt(m.x, m.y);
            if (above < -kSurveyLowOutlier_m || above > o.max_height_m) {
                ++(above < 0 ? s.dropped_low : s.dropped_high);
                return;
            }
            voxels.insert({std::int32_t(std::floor(m.x / voxel)), std::int32_t(std::floor(m.y / voxel)),
                           std::int32_t(std::floor(m.z / voxel))});
            while (voxels.size() > o.max_boxes) {
                if (!o.coarsen)
                    throw core::Error(std::string(kWhere) + ": " + s.survey.string() + ": more than " +
                                      number(double(o.max_boxes)) + " boxes at --voxel-m " + number(voxel) +
                                      "; allowed at most --max-boxes " + number(double(o.max_boxes)) +
                                      ": raise --voxel-m or --max-boxes, or give --coarsen");
                voxels = coarser(voxels);
                voxel *= 2.0;
            }
        },
        progress);
    s.voxel_m = voxel;
    s.boxes.assign(voxels.begin(), voxels.end());
    std::sort(s.boxes.begin(), s.boxes.end());
}

}  // namespace

void validate(const SceneFromCloudOptions& o) {
    auto fail = [](const std::string& what) { throw core::Error(std::string(kWhere) + ": " + what); };
    if (!(o.voxel_m > 0.05 && o.voxel_m <= 100.0))
        fail("--voxel-m is " + number(o.voxel_m) + "; allowed (0.05, 100] metres");
    if (!(o.cell_m == 0.0 || (o.cell_m >= 0.1 && o.cell_m <= 100.0)))
        fail("--cell-m is " + number(o.cell_m) + "; allowed 0 (from the point spacing) or [0.1, 100] metres");
    if (o.max_boxes < 1 || o.max_boxes > 50000000)
        fail("--max-boxes is " + number(double(o.max_boxes)) + "; allowed 1..50000000");
    const VehiclePlacement& v = o.vehicle;
    if (!(o.max_height_m > 0.0 && o.max_height_m <= 10000.0))
        fail("--max-height-m is " + number(o.max_height_m) + "; allowed (0, 10000] metres");
    if (!(v.max_slope >= 0.0 && v.max_slope <= 1.0))
        fail("--max-slope is " + number(v.max_slope) + "; allowed [0, 1] (rise over run)");
    if (!(v.max_roughness_m >= 0.0 && v.max_roughness_m <= 10.0))
        fail("--max-roughness-m is " + number(v.max_roughness_m) + "; allowed [0, 10] metres");
    if (!(v.clearance_m >= 0.0 && v.clearance_m <= 100.0))
        fail("--clearance-m is " + number(v.clearance_m) + "; allowed [0, 100] metres");
    if (v.yaw_deg && !(std::isfinite(*v.yaw_deg) && std::abs(*v.yaw_deg) <= 360.0))
        fail("--yaw-deg is " + number(*v.yaw_deg) + "; allowed [-360, 360]");
    if (v.at_world && !(std::abs(v.at_world->x) <= 1e9 && std::abs(v.at_world->y) <= 1e9))
        fail("--vehicle-at is outside [-1e9, 1e9] metres");
    validate(o.ground);
}

double TerrainMesh::heightAt(double x, double y) const {
    const double fx = std::clamp((x - x0_m) / cell_m, 0.0, double(nx - 1));
    const double fy = std::clamp((y - y0_m) / cell_m, 0.0, double(ny - 1));
    const int i = std::min(int(fx), nx - 2), j = std::min(int(fy), ny - 2);
    const double u = fx - i, v = fy - j;
    const double z00 = at(i, j), z10 = at(i + 1, j), z01 = at(i, j + 1), z11 = at(i + 1, j + 1);
    if (u >= v) return z00 + u * (z10 - z00) + v * (z11 - z10);  // triangle (i,j) (i+1,j) (i+1,j+1)
    return z00 + v * (z01 - z00) + u * (z11 - z01);              // triangle (i,j) (i+1,j+1) (i,j+1)
}

SceneFromCloud buildSceneFromCloud(const std::filesystem::path& survey, const SceneFromCloudOptions& o,
                                   const std::function<void(std::size_t)>& progress) {
    SceneFromCloud s;
    s.survey = survey;
    s.units = readCoordinateUnits(survey, kWhere);
    const Survey m = measure(survey, s.units, progress);
    s.reader_warning = m.warning;
    s.points = m.points;
    if (m.points == 0)
        throw core::Error(std::string(kWhere) + ": " + survey.string() +
                          ": the cloud has no points; allowed a survey with points");
    if (m.hi.x - m.lo.x > kMaxExtent_m || m.hi.y - m.lo.y > kMaxExtent_m)
        throw core::Error(std::string(kWhere) + ": " + survey.string() + ": the survey is " + number(m.hi.x - m.lo.x) +
                          " m x " + number(m.hi.y - m.lo.y) + " m; allowed at most " + number(kMaxExtent_m) +
                          " m across (cut it into tiles)");
    s.offset_m =
        glm::dvec3(std::round(0.5 * (m.lo.x + m.hi.x)), std::round(0.5 * (m.lo.y + m.hi.y)), std::floor(m.lo.z));

    const bool classes = o.ground_source == SceneGroundSource::Classes ||
                         (o.ground_source == SceneGroundSource::Auto && m.class2 * 100 >= m.points);
    if (o.ground_source == SceneGroundSource::Classes && m.class2 == 0)
        throw core::Error(std::string(kWhere) + ": " + survey.string() +
                          ": --ground-from classes: the file has no class-2 (ground) points; allowed auto or filter");
    std::unique_ptr<TerrainFit> fit;
    if (!classes) fit = fitFilter(survey, s.units, s.offset_m, o, progress);
    s.ground_from = classes ? "class 2" : describe(o.ground);

    const double cell = chooseCell(o, m, classes ? m.class2 : m.points / 2);
    s.terrain = startGrid(m.lo - s.offset_m, m.hi - s.offset_m, cell, o.max_cells);
    s.voxel_requested_m = o.voxel_m;
    binGround(s, GroundTest{fit.get()}, progress);
    binOthers(s, o, GroundTest{fit.get()}, progress);
    if (!o.vehicle.mesh.empty()) s.vehicle = detail::placeVehicle(s.terrain, s.boxes, s.voxel_m, s.offset_m, o.vehicle);
    return s;
}

}  // namespace sim
