// sim/src/ground_raster.hpp: what the raster-based whole-cloud filters (SMRF, CSF)
// share: the lowest points of each cell gathered in pass 1 (sparse tiles, any order), the
// noise-robust ground level of each cell made from them, the ground thickness, the
// terrain raster, hole filling, and pass 2's test against a per-cell tolerance.
#pragma once
#include <sim/ground.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

namespace sim {

/// A cell of the minimum surface that no point fell in.
inline constexpr float kNoPoint = std::numeric_limits<float>::infinity();

/// How many of a cell's lowest heights pass 1 keeps.
inline constexpr int kCellLowest = 16;
/// A point within this many ground thicknesses (the spread of the lowest layer, one
/// sigma) of the terrain is ground whatever the filter's threshold: two-sided, 2.5 sigma
/// keeps 98.8 % of Gaussian ground.
inline constexpr double kThicknessSigmas = 2.5;

/// A cell's level is taken from its lowest heights up to this many ground thicknesses
/// (plus kLevelWindow_m) above its third lowest.
inline constexpr double kLevelWindowSigmas = 6.0, kLevelWindow_m = 0.02;
/// The thickness is measured in the cells whose lowest heights look like ground: at least
/// kThicknessMinPoints of them within kThicknessWindow_m of the third lowest, the spread
/// taken over those only. A cell of an object's side or a trunk has fewer; without this a
/// sparse cloud, whose only well-sampled cells are its objects, read as metres thick.
inline constexpr double kThicknessWindow_m = 1.0;
inline constexpr int kThicknessMinPoints = 8;

/// Below this ground thickness a cell's level is its lowest height (the filters' own
/// minimum surface) unless the views are corrected (kRegisterViews_m): a thin ground
/// needs no centre estimate, and the spread the estimate sees there comes from the
/// terrain's slope within the cell, not from noise.
inline constexpr double kThinGround_m = 0.1;

/// From this ground thickness on, the views are registered (when there are several) and
/// the levels taken again from the corrected heights. It lies below kThinGround_m: the
/// lowest of a dense cell lies ever further below its ground, and a Ladar's ground
/// 0.09 m thick sampled at 280 points a square metre put the minimum 0.27 m low and left
/// 4 % of the ground above the 0.5 m threshold. Not lower: the ideal sensor's spread
/// within a cell, which comes from the slope, reaches 0.077 m on the forest's 26 %
/// slopes, and its clouds are those of the filters as published.
inline constexpr double kRegisterViews_m = 0.08;

/// The standard normal quantile (inverse CDF) at p in (0, 1): Abramowitz and Stegun
/// 26.2.23, absolute error under 4.5e-4.
double normalQuantile(double p);

/// The ground level of one cell and the spread of its lowest layer from its `m` lowest
/// heights (`low`, ascending) out of `n` points: the k-th lowest of n Gaussian heights
/// lies near mu + sigma * normalQuantile((k - 0.375) / (n + 0.25)) (Blom's plotting
/// positions). `slope_sigma_m` gets the least-squares slope of the heights on those
/// quantiles (the cell's spread); with `sigma_m` >= 0 the level is the median over the
/// m heights of low[k] - sigma_m * quantile (the lowest one alone cannot drag it down).
struct CellLowest {
    double level_m;
    double slope_sigma_m;
};
CellLowest cellLevel(const float* low, int m, std::uint32_t n, double sigma_m);

/// out[i] = the minimum (`take_max` false) or the maximum of in[i - r .. i + r], the
/// window clipped to [0, n); `in` and `out` do not overlap. O(n) whatever r (van Herk and
/// Gil-Werman blocks); `scratch` is resized to 3 (n + 2r) values and reused by the caller.
void runningExtreme(const float* in, float* out, int n, int r, bool take_max, std::vector<float>& scratch);

/// Fills the cells of `z` (nx x ny, row-major) whose `known` is 0: rings of cells next to
/// filled ones take the mean of their filled 8-neighbours, then successive
/// over-relaxation moves the filled values towards the mean of their 4-neighbours (a
/// membrane held by the known cells). `sweeps` 0: until the largest change anywhere is
/// under 1 mm (at most 100 sweeps); > 0: exactly that many, so that a cell's value does
/// not hang on how far the raster reaches (SmrfOptions::fill_sweeps). Deterministic:
/// `threads` > 1 shares those fixed sweeps among threads, each a sweep behind the other,
/// with the same bits as one thread (the settling mode runs on one). Nothing known: `z`
/// is left alone.
void inpaint(std::vector<float>& z, const std::vector<std::uint8_t>& known, int nx, int ny, int sweeps = 0,
             int threads = 1);

/// Low outliers: how many of each cell's lowest heights to skip. `low[c]` points at cell
/// c's heights (ascending), `m[c]` their number (0: no point); w x h cells, row-major. A
/// cell's lowest kept height is an outlier when it lies more than `gap_m` below the 20 %
/// quantile of the lowest kept heights of the other cells within 5 cells that keep one
/// (at least 8 of them). Rounds repeat, each deciding every cell on the counts the round
/// began with (so the result does not depend on the visiting order), until nothing
/// changes or 4 rounds; a cell whose every height is an outlier gets m[c].
std::vector<int> lowOutliers(const std::vector<const float*>& low, const std::vector<int>& m, int w, int h,
                             double gap_m);

/// The empty cells that the openings of a sparse survey leave out
/// (SmrfOptions::sparse_openings): those (not `known`) with a known cell among their 8
/// neighbours, where fewer than half of the 5 x 5 cells around them (as far as the raster
/// reaches) are known. There the empty cells lie between the points' rows, and the filled
/// surface would make each known cell a peak or a pit of its own; deeper inside a gap, or
/// in a dense survey, the cells are filled as inpaint() fills them. One flag per cell.
std::vector<std::uint8_t> sparseEmptyCells(const std::vector<std::uint8_t>& known, int nx, int ny);

/// The sides of a raster beyond which the survey goes on (its cut edges).
struct CutSides {
    bool low_x = false, low_y = false, high_x = false, high_y = false;
};

/// Whether a hole of an nx x ny raster (cells not `observed`, joined through their four
/// neighbours, as inpaint's relaxation joins them) runs from a side in `cut` into the
/// cells [i0, i1] x [j0, j1] (inclusive; an empty range reaches none). Memory: a flag and
/// at most one index per cell.
bool holeReaches(const std::vector<bool>& observed, int nx, int ny, const CutSides& cut, double i0, double i1,
                 double j0, double j1);

class RasterFit : public TerrainFit {
  public:
    /// `cell_option` names the cell size in errors, e.g. "smrf cell_m (--smrf-cell-m)".
    RasterFit(double cell_m, std::size_t max_cells, const char* cell_option);
    // It holds pointers into its own tables (the last tile, the last view block).
    RasterFit(const RasterFit&) = delete;
    RasterFit& operator=(const RasterFit&) = delete;
    void add(std::span<const core::CloudPoint> points) override;
    /// add() with the points shared among `threads` threads, each gathering into a raster
    /// of its own, merged after: the fit depends only on the set of points, so it is the
    /// same as add()'s.
    void addAll(std::span<const core::CloudPoint> points, int threads) override;
    void setFitThreads(int threads) override { threads_ = std::max(1, threads); }
    void thicknessSamples(const glm::dvec2& lo, const glm::dvec2& hi, std::vector<double>& out) const override;
    void setGroundThickness(double sigma_m) override { fixed_sigma_m_ = sigma_m; }
    void setExtent(const glm::dvec2& lo, const glm::dvec2& hi) override;
    /// Builds the ground-level surface over the cells the points touched (each cell's
    /// level from its lowest heights, cellLevel(), with the ground thickness estimated
    /// over all cells), then fitTerrain().
    void fit() override;
    const TerrainGrid& surface() const override { return grid_; }
    /// After fit(): one flag per cell of surface() (row-major), set where the cell held a
    /// point its level was taken from; the others were filled (inpaint).
    const std::vector<bool>& observedCells() const { return observed_; }
    /// Ground when |z - terrain (bilinear)| <= limit_m_ of the nearest cell.
    bool classify(const glm::vec3& p, float& height_m) const override;
    /// Takes the height error of the point's view off first (when views were corrected).
    bool classify(const core::CloudPoint& p, float& height_m) const override;

  protected:
    /// `minimum` (the ground-level surface: grid_'s geometry, kNoPoint where no point
    /// fell) to grid_.z_m and limit_m_ (one tolerance per cell).
    virtual void fitTerrain(std::vector<float>& minimum, const std::vector<std::uint8_t>& observed) = 0;
    /// The filter's threshold widened to kThicknessSigmas ground thicknesses.
    double groundThreshold(double threshold_m) const {
        return std::max(threshold_m, kThicknessSigmas * grid_.ground_sigma_m);
    }
    /// The filter's threshold (the part of limit_m_ that groundThreshold() widens); set by
    /// the filter, so that the limits follow the thickness once the views are corrected.
    double threshold_m_ = 0;
    /// A cell's lowest heights this far below every height around it are low outliers,
    /// left out of its level (dropLowOutliers); 0 = none are.
    double low_outlier_m_ = 0;
    /// Metres per unit of the cloud's heights (SmrfOptions::z_unit_m): the fixed heights
    /// here, in metres (kThicknessWindow_m, kLevelWindow_m, kThinGround_m,
    /// kRegisterViews_m, kViewGate_m, kViewReach_m), are divided by it.
    double z_unit_m_ = 1;
    int threads_ = 1;  // fitTerrain()'s threads

    TerrainGrid grid_;
    std::vector<float> limit_m_;

  private:
    // Each view's height error as a plane, offset_m + dzdx * (x - x0_m) + dzdy * (y - y0_m),
    // fitted to the residuals of its lowest points against the terrain.
    struct ViewPlane {
        double x0_m = 0, y0_m = 0, offset_m = 0, dzdx = 0, dzdy = 0;
    };
    // The lowest point of one view in one block of kViewBlock x kViewBlock cells.
    struct ViewLow {
        float z, x, y;
    };
    static constexpr int kViewBlock = 4;
    static constexpr double kViewGate_m = 0.15;  // residuals this close always count
    static constexpr double kViewReach_m = 2.0;  // a view's error is within this of the first terrain
    /// Fits view_planes_; false (none) when there is one view or too few points.
    bool correctViews();
    double viewError(std::size_t view, double x, double y) const;

    std::unordered_map<std::uint64_t, ViewLow> view_lows_;  // (view, block x, block y) -> lowest point
    std::uint64_t last_view_key_ = 0;                       // the entry keepViewLow touched last
    ViewLow* last_view_low_ = nullptr;
    bool too_many_view_blocks_ = false;
    std::vector<ViewPlane> view_planes_;  // by view; empty: no correction
    double cell_m_, inv_cell_;
    std::size_t max_cells_;
    const char* cell_option_;
    std::unordered_map<std::uint64_t, std::uint32_t> tiles_;  // tile (tx, ty) -> its index in tile_data_
    // Per cell: its kCellLowest lowest heights (ascending, kNoPoint-padded) and its count.
    struct Cell {
        float low[kCellLowest];
        std::uint16_t view[kCellLowest];  // the view of each
        std::uint32_t n;
    };
    // A square tile of cells. It keeps only the cells that hold a point (`few`, found
    // through `slot`) until they are many; then every cell of the tile, row-major
    // (`dense`). A sparse survey or a corridor touches many tiles with a few points each:
    // such a tile costs its 2-byte slots and its few cells, about a fortieth of every cell.
    struct Tile {
        std::unique_ptr<Cell[]> dense;
        std::unique_ptr<std::uint16_t[]> slot;  // per cell: 1 + its index in few; 0: no point
        std::vector<Cell> few;
    };
    Tile* tileFor(int tx, int ty);
    /// The tile's cell `c` (row-major within the tile), created empty when it is not kept.
    static Cell& cellAt(Tile& tile, int c);
    /// The tile's cell `c`, or nullptr when no point fell in it.
    static const Cell* findCell(const Tile& tile, int c);
    static void keepLowest(Cell& cell, float z, std::uint16_t view);
    /// The spread of a cell's lowest heights, the thickness's sample; false for a cell
    /// with too few points, or too few near its lowest, to give one.
    bool cellSpread(const Cell& cell, double& spread_m) const;
    double fixed_sigma_m_ = -1;   // setGroundThickness()
    std::vector<bool> observed_;  // observedCells()
    // setExtent()'s cells (first > last: none given).
    int extent_i0_ = 1, extent_i1_ = 0, extent_j0_ = 1, extent_j1_ = 0;
    void keepViewLow(std::uint64_t key, const ViewLow& low);
    void merge(const RasterFit& other);  // other's points, as if added here
    std::vector<Tile> tile_data_;
    std::uint64_t last_key_ = 0;
    Tile* last_tile_ = nullptr;
    int ix_min_ = std::numeric_limits<int>::max(), ix_max_ = std::numeric_limits<int>::min();
    int iy_min_ = std::numeric_limits<int>::max(), iy_max_ = std::numeric_limits<int>::min();
};

/// Runs `fit` on points in memory: flags (1 = ground), optionally the surface and heights.
std::vector<std::uint8_t> classifyInMemory(TerrainFit& fit, std::span<const glm::vec3> points, TerrainGrid* surface,
                                           std::vector<float>* height_m);

}  // namespace sim
