// sim/ground.hpp: ground detection for whitening. The paper's five-step iterative RANSAC
// (§III-C, per view, the default) behind the per-view seam (ViewGroundFilter), and the
// terrain-following filters that work on the whole fused cloud (SMRF, CSF) behind the
// whole-cloud seam (CloudGroundFilter). Each filter has its own options struct;
// GroundChoice says which one the generator runs.
#pragma once
#include <core/point_cloud.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

namespace sim {

/// Which ground filter whitens the cloud (`ladarvr generate --ground`).
enum class GroundMethod {
    Ransac,  // paper §III-C: iterative RANSAC per view (the default)
    Smrf,    // simple morphological filter (Pingel et al. 2013) on the fused cloud
    Csf,     // cloth simulation filter (Zhang et al. 2016) on the fused cloud
};
/// "ransac", "smrf" or "csf".
const char* groundMethodName(GroundMethod m);
/// Throws core::Error("<context> '<text>': allowed ransac, smrf, csf").
GroundMethod parseGroundMethod(std::string_view text, std::string_view context);

/// Simple morphological filter (Pingel, Clarke, McBride 2013, "An improved simple
/// morphological filter for the terrain classification of airborne LIDAR data").
/// Defaults are PDAL's filters.smrf defaults.
struct SmrfOptions {
    double cell_m = 1.0;       // cell size of the minimum surface and of the terrain raster
    double slope = 0.15;       // rise over run: a cell is an object when an opening lowers it
                               // by more than slope * radius (m)
    double window_m = 18.0;    // largest opening radius (metres); objects wider than twice
                               // this stay ground
    double threshold_m = 0.5;  // a point is ground within threshold_m + scalar * local slope
    double scalar = 1.25;      // of the fitted terrain (metres per unit slope)
    /// Ours: the terrain raster may hold at most this many cells (memory bound); a cloud
    /// wider than that at cell_m is refused, naming cell_m.
    std::size_t max_cells = std::size_t(1) << 24;
    /// Ours: a cell's lowest height more than this below every height around it (the
    /// lowest of the cells within 2 cells, the next one of its own) is a low outlier and
    /// left out of the surface (multipath, noise under real surveys); 0 = off, as the
    /// generator runs it (`ladarvr ground` sets it).
    double low_outlier_m = 0.0;
    /// Ours: metres per unit of the cloud's heights (sim::inUnits sets it for a survey in
    /// feet): the raster's own fixed heights, given in metres (the ground thickness's
    /// windows), are divided by it. 1 for a cloud in metres.
    double z_unit_m = 1.0;
    /// Ours: after the openings, a connected patch of the surface left ground that stands
    /// more than 2 m above the surface around it on most of its border (a roof wider than
    /// twice the window, a bridge deck) is an object too. Off as the generator runs it
    /// (`ladarvr ground` sets it): it lowered the mean total error on the ISPRS samples.
    bool raised_segments = false;
    /// Ours: the hole filling's relaxation runs exactly this many sweeps; 0 = until the
    /// largest change over the whole raster is under 1 mm, as the generator runs it.
    /// A fixed count (`ladarvr ground` sets kSurveyFillSweeps) makes a filled cell the
    /// same whether the raster is one tile with its buffer or the whole survey.
    int fill_sweeps = 0;
    /// Ours: where the survey is sparser than the raster (fewer than half the cells around
    /// hold a point), the openings leave out the empty cells between the points instead of
    /// seeing them filled: the filled cells between two rows of returns on a step lie below
    /// the upper row, so each of its cells stood as a peak that the smallest openings cut
    /// (sim::sparseEmptyCells says which cells are left out). Off as the generator runs it;
    /// `ladarvr ground` sets it: it lowered the mean total error on the ISPRS samples.
    bool sparse_openings = false;
    /// Ours, measured on the ISPRS samples and not run by default: morphological
    /// (geodesic) reconstruction in SMRF (sim/src/ground_reconstruct.hpp), which gives back
    /// what joins higher ground without a drop (a terrace's upper edge) and not what stands
    /// above everything around it (a roof). 0 = off;
    /// 1 = the object test's openings by reconstruction, those of radius reconstruct_from_m
    ///     to reconstruct_to_m: the erosion reconstructed under the surface
    ///     (reconstruct_steps 0), or the opening dilated that many cells further under it;
    /// 2 = a cell the openings called an object whose h-dome of height reconstruct_h_m is
    ///     at most reconstruct_tol_m is ground again;
    /// 3 = observed cells that the fitted terrain (plus reconstruct_tol_m), reconstructed
    ///     under the surface within reconstruct_steps cells, reaches and that lie at most
    ///     reconstruct_h_m above it are ground too, and the terrain is fitted again;
    /// 4 = as 3, from the ground cells' own levels instead of the terrain;
    /// 5 = a ground cell whose top-hat by reconstruction (the surface less its erosion by
    ///     a disk of reconstruct_steps cells, at least 1, reconstructed under it) exceeds
    ///     reconstruct_h_m is an object.
    int reconstruct = 0;
    double reconstruct_h_m = 2.0;     // 2: the domes' height; 3, 4: the highest rise given back; 5: the top-hat's
    double reconstruct_tol_m = 0.3;   // 2: the largest dome still ground; 3, 4: the seeds' and the reach's slack
    int reconstruct_steps = 0;        // 1, 3, 4: how many cells the reconstruction reaches (0: however far); 5: radius
    double reconstruct_from_m = 0.0;  // 1: openings of a smaller radius (metres) stay plain
    double reconstruct_to_m = 0.0;    // 1: and those of a larger one (0: none)
};

/// Cloth simulation filter (Zhang, Qi, Wan, Wang, Xie, Wang, Yan 2016, "An easy-to-use
/// airborne LiDAR data filtering method based on cloth simulation", Remote Sensing 8(6)
/// 501). Defaults are the paper's (and CloudCompare's plugin's).
struct CsfOptions {
    double cloth_m = 1.0;      // cloth resolution: the spacing of its particles
    int rigidness = 3;         // 1 (steep terrain, a soft cloth) .. 3 (flat terrain, stiff)
    double threshold_m = 0.5;  // class threshold: a point within this of the cloth is ground
    double time_step = 0.65;   // the simulation's time step (dimensionless, gravity 0.2)
    int iterations = 500;      // at most; it stops earlier once the cloth is still
    /// Ours: the raster may hold at most this many cells (as SmrfOptions::max_cells).
    std::size_t max_cells = std::size_t(1) << 24;
    /// Ours: low outliers left out of the surface, as SmrfOptions::low_outlier_m; 0 = off.
    double low_outlier_m = 0.0;
    /// Ours: the length of the cloud's height unit, as SmrfOptions::z_unit_m.
    double z_unit_m = 1.0;
    /// The slope post-processing's step: a hanging particle beside a stopped one joins it
    /// when their lowest heights differ by less than this (the paper's 0.3 m).
    double slope_join_m = 0.3;
};

/// Thresholds of the iterative RANSAC; defaults are the paper's where it gives them.
struct RansacOptions {
    double band_m = 3.0;                // step 1: keep z in [z_min, z_min + band_m] (paper: 3 m)
    double distance_threshold_m = 0.2;  // RANSAC inlier distance (not given by the paper)
    double min_normal_z = 0.9;          // step 3: accept a plane when |normal.z| >= this
    double stop_fraction = 0.01;        // step 5: stop when under this fraction of PC is left
    /// Ours, not the paper's: a horizontal plane joins PG only if it holds at least this
    /// fraction of the band (step 1's PC). Rejects the tank's roof and the horizontal
    /// slabs RANSAC cuts through walls once the ground is gone. 0 = the paper's rule.
    double min_plane_fraction = 0.05;
    int max_planes = 25;           // cap on steps 2-5 (the paper's loop has none)
    int ransac_iterations = 1000;  // SACSegmentation's max iterations per plane
    /// Ours: RANSAC searches the plane on at most this many points of PC (a uniform
    /// sample: PC is shuffled), then every point of PC within distance_threshold_m of
    /// that plane is an inlier. Same planes on big views, ~10x faster. 0 = all of PC.
    int ransac_sample_points = 20000;
};

/// The generator's ground stage: which filter whitens the cloud, and the options of
/// each. `smrf` also serves the check of RANSAC's result against a fitted terrain
/// (GenerateOptions::ground_check), whatever the method.
struct GroundChoice {
    GroundMethod method = GroundMethod::Ransac;
    RansacOptions ransac;
    SmrfOptions smrf;
    CsfOptions csf;
};

/// Throws core::Error("ground: <parameter> = <value>: allowed ...").
void validate(const RansacOptions& o);
void validate(const SmrfOptions& o);
void validate(const CsfOptions& o);
/// Every filter's options (a choice may change later; all must be valid).
void validate(const GroundChoice& o);

/// A per-view filter's counts for one view (RANSAC's §III-C loop).
struct GroundStats {
    std::size_t band_points = 0;    // |PC| at step 1
    std::size_t ground_points = 0;  // |PG|
    int planes_accepted = 0;        // near-horizontal planes added to PG
    int planes_rejected = 0;        // planes removed from PC without joining PG (walls)
    int planes_too_small = 0;       // of those, horizontal but under min_plane_fraction
};

/// Paper §III-C steps 1-5 on one view's points: returns one flag per point, 1 when the
/// point is in PG (ground). PC is shuffled (core::shuffle) with std::mt19937_64(seed) first (PCL's own RNG
/// is fixed-seed), so the result is a pure function of (points, options, seed).
/// Fewer than 3 points in the band: no RANSAC, no ground. Needs validate(o) passed.
std::vector<std::uint8_t> findGround(std::span<const glm::vec3> points, const RansacOptions& o, std::uint64_t seed,
                                     GroundStats* stats = nullptr);

/// A terrain surface sampled on a regular grid (the DTM): cell (i, j) has its centre at
/// (x0_m + i * cell_m, y0_m + j * cell_m) in the cloud's local frame, height z_m[j * nx + i].
struct TerrainGrid {
    double x0_m = 0, y0_m = 0, cell_m = 1;
    int nx = 0, ny = 0;
    std::vector<float> z_m;
    /// How many cells held at least one point (the others are interpolated).
    std::size_t observed_cells = 0;
    /// The ground thickness: the median over the well-sampled cells of the spread (one
    /// sigma) of their lowest heights; noise and misregistered views thicken the ground.
    double ground_sigma_m = 0;
    /// The views' height errors were estimated and are taken off each point before it is
    /// tested (views_corrected of them); ground_sigma_m is then the thickness after that.
    std::size_t views_corrected = 0;
    /// The ground thickness before the views' errors were taken off.
    double ground_sigma_uncorrected_m = 0;

    bool empty() const { return nx == 0 || ny == 0; }
    float at(int i, int j) const { return z_m[std::size_t(j) * std::size_t(nx) + std::size_t(i)]; }
    /// Bilinear height at (x, y); outside the grid, the nearest edge's.
    double heightAt(double x, double y) const;
    /// Gradient magnitude (rise over run) of the surface at (x, y), from the nearest cell.
    double slopeAt(double x, double y) const;
};

/// One run of a whole-cloud filter: add() sees every point once (any order, any
/// batching: the fit depends only on the set of points), fit() builds the terrain, then
/// classify() labels points (thread-safe, const).
class TerrainFit {
  public:
    virtual ~TerrainFit() = default;
    virtual void add(std::span<const core::CloudPoint> points) = 0;
    /// add() on up to `threads` threads where the filter can share the work; the fit is
    /// the same.
    virtual void addAll(std::span<const core::CloudPoint> points, int threads) {
        (void)threads;
        add(points);
    }
    /// Before fit(): how many threads fit() may use where the filter can share its work
    /// (>= 1; 1 by default). The fit is the same whatever the number.
    virtual void setFitThreads(int threads) { (void)threads; }
    /// Throws core::Error naming the parameter when the cloud cannot be gridded.
    virtual void fit() = 0;
    /// After fit(): the fitted surface (empty when no point was added).
    virtual const TerrainGrid& surface() const = 0;
    /// After fit(): true when `p` is ground; `height_m` = p.z - surface height there.
    virtual bool classify(const glm::vec3& p, float& height_m) const = 0;
    /// As above for a point of a view: a filter that estimated each view's height error
    /// (misregistered views of a real sensor) takes it off first.
    virtual bool classify(const core::CloudPoint& p, float& height_m) const { return classify(p.position, height_m); }
    /// Tiles of one survey share its ground thickness. After add(), before fit(): appends
    /// to `out` the samples fit() takes the thickness's median over, those of the cells
    /// whose centre lies in [lo, hi) (x-y); nothing for a filter that measures none.
    virtual void thicknessSamples(const glm::dvec2& lo, const glm::dvec2& hi, std::vector<double>& out) const {
        (void)lo, (void)hi, (void)out;
    }
    /// Before fit(): the ground thickness to use instead of the one measured (the median
    /// of the whole survey's thicknessSamples); < 0 measures it (the default).
    virtual void setGroundThickness(double sigma_m) { (void)sigma_m; }
    /// Before fit(): the raster spans at least the cells whose centres lie in [lo, hi)
    /// (x-y), empty ones included, besides those the points touched. A tile gives the
    /// survey's cells within its buffer, so that its raster ends where one run over the
    /// whole survey has its own, not where the tile's points happen to stop.
    virtual void setExtent(const glm::dvec2& lo, const glm::dvec2& hi) { (void)lo, (void)hi; }
    /// After fit(): appends to `out` the boxes (x-y, lo and hi) of the patches that a step
    /// without a bounded reach tested (SMRF's raised segments) and that come within
    /// `reach_m` of [lo, hi); nothing for a filter without such a step. A tile whose
    /// raster cuts such a patch is fitted again over all of it (sim/ground_tiles.hpp).
    virtual void testedPatches(const glm::dvec2& lo, const glm::dvec2& hi, double reach_m,
                               std::vector<std::pair<glm::dvec2, glm::dvec2>>& out) const {
        (void)lo, (void)hi, (void)reach_m, (void)out;
    }
};

/// A per-view filter (RANSAC): the generator labels each view's points as the view is
/// traced.
class ViewGroundFilter {
  public:
    virtual ~ViewGroundFilter() = default;
    virtual GroundMethod method() const = 0;
    /// One flag per point, 1 = ground; a pure function of the arguments.
    virtual std::vector<std::uint8_t> classifyView(std::span<const glm::vec3> points, std::uint64_t seed,
                                                   GroundStats* stats) const = 0;
};

/// A whole-cloud filter (SMRF, CSF): it sees the fused cloud in two streamed passes
/// (TerrainFit), so it also works when the cloud is spooled.
class CloudGroundFilter {
  public:
    virtual ~CloudGroundFilter() = default;
    virtual GroundMethod method() const = 0;
    /// A fresh run.
    virtual std::unique_ptr<TerrainFit> startCloud() const = 0;
};

/// Whether `m` names a per-view filter (else a whole-cloud one).
bool isPerView(GroundMethod m);
/// The per-view filter `o.method` names, with its options; null when it names a
/// whole-cloud filter. validate(o) must have passed.
std::unique_ptr<const ViewGroundFilter> makeViewFilter(const GroundChoice& o);
/// The whole-cloud filter `o.method` names, with its options; null when it names a
/// per-view filter. validate(o) must have passed.
std::unique_ptr<const CloudGroundFilter> makeCloudFilter(const GroundChoice& o);
/// A whole-cloud SMRF run (also used to check RANSAC's result against the terrain).
std::unique_ptr<TerrainFit> startSmrf(const SmrfOptions& o);

/// A whole-cloud CSF run.
std::unique_ptr<TerrainFit> startCsf(const CsfOptions& o);
/// CSF on points in memory, as findGroundSmrf.
std::vector<std::uint8_t> findGroundCsf(std::span<const glm::vec3> points, const CsfOptions& o,
                                        TerrainGrid* surface = nullptr, std::vector<float>* height_m = nullptr);

/// SMRF on points in memory: one flag per point (1 = ground); `surface` gets the fitted
/// terrain, `height_m` the height of each point above it, when given.
std::vector<std::uint8_t> findGroundSmrf(std::span<const glm::vec3> points, const SmrfOptions& o,
                                         TerrainGrid* surface = nullptr, std::vector<float>* height_m = nullptr);

}  // namespace sim
