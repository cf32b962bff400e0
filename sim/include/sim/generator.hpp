// sim/generator.hpp: the whole Ladar simulation of paper §III: orbit, ray casting, fusion,
// ground whitening and height colouring, into memory or streamed to a cloud file.
#pragma once
#include <core/point_cloud.hpp>
#include <core/scene.hpp>
#include <io/cloud_io.hpp>
#include <io/copc_writer.hpp>
#include <sim/colour.hpp>
#include <sim/ground.hpp>
#include <sim/orbit.hpp>
#include <sim/raycaster.hpp>
#include <sim/sensor.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace sim {

/// Every parameter of `ladarvr generate`; defaults are the paper's (§III-A, §III-C).
struct GenerateOptions {
    OrbitOptions orbit;
    /// C, in WORLD coordinates (metres, z up, like the scene file's positions).
    /// Default: defaultCentre(scene).
    std::optional<glm::dvec3> centre;
    ColourOptions colour;
    GroundChoice ground;  // which filter whitens the ground, and each filter's options
    /// The Ladar's models (docs/sensor.md); the default is the paper's ideal sensor.
    SensorOptions sensor;
    /// Meshes to ray-cast (§IV-B's target-only / no-ground clouds); the others are left
    /// out of the BVH. C is still computed on the whole scene, so clouds of different
    /// roles share one orbit.
    core::RoleMask roles = core::RoleMask::all();
    bool white = false;       // no colouring and no ground filter: every point white
    int threads = 0;          // 0 = every core (oneTBB's default concurrency)
    bool packet_rays = true;  // trace 16-ray packets (rtcIntersect16); false: rtcIntersect1
    /// Per view, trace only the pixels whose rays can meet the bounds of the ray-cast
    /// geometry (the box projected into the image, plus a margin); the others are misses
    /// without a ray. The cloud is the same either way (--no-skip-rays turns it off).
    bool skip_rays = true;
    std::uint64_t seed = 1;  // RANSAC of view v shuffles with mt19937_64(seed ^ v); seeds the sensor's models
    /// Bound on the generator's buffers (not the scene and its BVH): views per batch, rows
    /// per tile and threads are planned to fit (the cloud is the same whatever the plan),
    /// and a run that cannot fit is refused before the BVH is built. File output: the
    /// fused cloud is spooled to a file next to the output when it does not fit too; the
    /// cloud returned by the in-memory run() is the caller's and not counted.
    std::size_t memory_budget_bytes = std::size_t(512) << 20;
    bool progress = false;  // platform::Progress bar over the views (tty only)
    /// With the per-view RANSAC, also fit SMRF's terrain (ground.smrf) to the fused cloud
    /// and count the points on it that RANSAC left coloured (GenerateStats::terrain_*),
    /// when no ground mesh is ray-cast (ground labels then measure RANSAC directly) or
    /// fit_terrain asks for the terrain. Changes no point.
    bool ground_check = true;
    /// Fit the terrain (GenerateStats::terrain) whatever the filter and the labels: for
    /// a DTM export.
    bool fit_terrain = false;
    /// LAS/LAZ output only (docs/formats.md): the classes of the roles (a mesh's 'class'
    /// overrides its role's), and the GPS time: view v is reached at
    /// v x (orbit length / views) / drone_speed_mps (view_interval_s is set from that).
    io::LasOptions las;
    double drone_speed_mps = 10.0;
    /// COPC output only: the most points a node of the octree holds.
    std::int64_t copc_node_points = io::kDefaultMaxNodePoints;
};

/// Validates every field (orbit, colour, ground, threads, centre within
/// core::kMaxWorldCoordinate_m). Throws core::Error naming the parameter and the
/// allowed range. The Generator also checks, once C is known, that every drone position
/// lies within core::kMaxLocalCoordinate_m of the scene's origin (validatePlacement).
void validate(const GenerateOptions& o);

/// The default C, world coordinates: x, y = centre of the target meshes' bounds (of all
/// meshes if there is no target); z = the highest ground-role triangle above or below
/// that point (the ground height there), else the lowest z of the ground meshes, else of
/// the scene. Throws core::Error("generate: scene '<file>' has no triangles").
glm::dvec3 defaultCentre(const core::Scene& scene);

/// Wall-clock seconds of each stage (load is the caller's).
/// `ground` is the ground stage of whichever filter ran (--ground); `ground_check` the
/// SMRF terrain fitted to check the paper's RANSAC (GenerateOptions::ground_check).
struct StageSeconds {
    double bvh = 0, cast = 0, fuse = 0, ground = 0, colour = 0, write = 0, total = 0;
    double ground_check = 0;
};

struct GenerateStats {
    double drone_radius_m = 0, length_sensed_m = 0, coverage_diameter_m = 0;
    glm::dvec3 centre{0.0};                  // C, world coordinates
    std::size_t triangles = 0;               // in the BVH
    int threads = 1;                         // used: the request, clamped to the memory budget
    std::size_t batch_views = 1;             // views traced together
    std::size_t band_rows = 0;               // rows of a view traced per pass (yres: one band)
    std::uint64_t memory_planned_bytes = 0;  // the fusion's buffers as planned (<= the budget)
    std::uint64_t rays = 0, points = 0, misses = 0;
    std::uint64_t rays_traced = 0;           // pixels whose rays were cast (rays minus skipped pixels)
    std::uint64_t sub_rays_traced = 0;       // rays cast counting a beam footprint's sub-rays
    std::uint64_t ground_found = 0;          // whitened by the ground filter (RANSAC: PG over all views)
    std::uint64_t ground_truth = 0;          // points whose mesh has role ground
    std::uint64_t ground_true_positive = 0;  // both
    int planes_accepted = 0, planes_rejected = 0;
    /// Views whose height band (§III-C step 1) held < 3 points: RANSAC was not run.
    std::uint64_t views_without_ransac = 0;
    /// Of the whitening against the labels; empty when undefined (--white, or nothing
    /// whitened / no ground points).
    std::optional<double> ground_precision, ground_recall;
    /// Target and environment points more than 0.5 m above the scene's true terrain (its
    /// ground meshes, rasterised), and of those the ones left coloured; the shares are
    /// empty when undefined (--white, no ground mesh, no such point).
    std::uint64_t target_above_terrain = 0, target_kept_points = 0;
    std::uint64_t environment_above_terrain = 0, environment_kept_points = 0;
    std::optional<double> target_kept, environment_kept;
    /// Triangles the scene loader dropped (core::Scene::skipped_triangles and
    /// skipped_nonfinite_triangles): zero-area ones, and NaN/inf ones with skip_nonfinite.
    std::size_t skipped_zero_area_triangles = 0, skipped_nonfinite_triangles = 0;
    float z_min = 0, z_max = 0;  // height range used by the colour map (local)
    bool streamed = false;       // not held in memory: spooled, or in_output
    bool in_output = false;      // streamed into the output itself and coloured there (binary PCD, PLY)
    /// Each batch whitened and handed on by a thread of its own while the next batch was
    /// traced (the budget held a second batch of hits, and there were two threads or more).
    bool pipelined = false;
    /// Pipelined and streamed, the workers that whitened each view also packed its records
    /// for the spool or the output (the budget held both batches' records beside the rest).
    bool packed_on_workers = false;
    GroundMethod ground_method = GroundMethod::Ransac;
    /// Points near the fitted terrain, and of those the ones left coloured: with --ground
    /// smrf or csf those within 1 m of the filter's terrain; for the check of RANSAC those
    /// within SMRF's threshold of SMRF's terrain.
    std::uint64_t terrain_points = 0, terrain_points_coloured = 0;
    /// The fitted terrain (local frame), when one was fitted.
    std::shared_ptr<const TerrainGrid> terrain;
    StageSeconds seconds;
};

/// One generation run: validates the options, resolves C and builds the BVH at once
/// (timed as the bvh stage), then run() casts every view. The scene must outlive it.
class Generator {
  public:
    /// Throws core::Error for bad options or Embree failures.
    Generator(const core::Scene& scene, GenerateOptions options);
    ~Generator();

    /// The fused, coloured cloud in memory (origin = the scene's origin).
    core::PointCloud run(GenerateStats* stats = nullptr);
    /// Called once the whole cloud is in its temporary, before it is renamed into place,
    /// with the run's figures (the fitted terrain included): the caller writes the run's
    /// other outputs there, so that when one of them fails (a full disk) it throws and
    /// the cloud's temporary is removed: no output lands before all are written.
    using BeforeCommit = std::function<void(const GenerateStats&)>;
    /// Streams the fused, coloured cloud to `out` (atomically, via io::CloudWriter);
    /// the destination is checked before any ray is cast.
    void run(const std::filesystem::path& out, io::CloudFormat format, GenerateStats* stats = nullptr,
             const BeforeCommit& before_commit = {});

    /// The rays the ideal sensor traces for one view (what run() traces with every sensor
    /// model off), in output order (row-major pixels), for baselines and tests. Directions
    /// are unit length, so t is metres.
    void viewRays(int view, std::vector<Ray>& rays) const;
    const RayCaster& caster() const;
    const GenerateOptions& options() const;
    glm::dvec3 centreWorld() const;

    struct State;

  private:
    std::unique_ptr<State> state_;
};

/// Convenience: Generator(scene, options).run(stats).
core::PointCloud generateCloud(const core::Scene& scene, const GenerateOptions& options,
                               GenerateStats* stats = nullptr);
/// Convenience: Generator(scene, options).run(out, format, stats).
void generateToFile(const core::Scene& scene, const GenerateOptions& options, const std::filesystem::path& out,
                    io::CloudFormat format, GenerateStats* stats = nullptr);

}  // namespace sim
