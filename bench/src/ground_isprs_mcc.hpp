// bench/src/ground_isprs_mcc.hpp: multiscale surface filters on the ISPRS samples
// (`bench ground-isprs --multiscale`), prototypes scored beside `ladarvr ground`, not product
// code: multiscale curvature classification (MCC: Evans and Hudak 2007), a coarse-to-fine
// pyramid of residual tests on the lowest points (after Mongus and Zalik 2012's
// parameter-free filter), and each of them applied to SMRF's answer (MCC taking points off
// its ground, the pyramid giving ground back). Smooth surfaces are rasters whose empty cells
// are filled by a pyramid of plane fits and relaxation (no thin-plate spline).
#pragma once
#include "ground_isprs_adaptive.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace core {
struct CloudPoint;
}

namespace bench {

/// Heights on a regular grid over a sample: cell (i, j) covers x in [x0_m + i * cell_m,
/// x0_m + (i + 1) * cell_m) and likewise in y; its value stands at the cell's centre.
struct HeightRaster {
    double x0_m = 0, y0_m = 0, cell_m = 1;
    int nx = 0, ny = 0;
    std::vector<float> z_m;  // row-major, nx * ny

    /// The grid of `cell_m` cells spanning `points` (x-y), heights 0. Throws core::Error
    /// when it would hold more than 2^24 cells.
    static HeightRaster spanning(const std::vector<core::CloudPoint>& points, double cell_m);
    int column(double x) const;  // clamped to the grid
    int row(double y) const;
    std::size_t index(int i, int j) const { return std::size_t(j) * std::size_t(nx) + std::size_t(i); }
    /// Bilinear between cell centres; beyond the outer centres, the edge's value.
    double heightAt(double x, double y) const;
    /// Rise over run at the cell holding (x, y), from central differences.
    double slopeAt(double x, double y) const;
};

/// Fills the cells of `z` (nx x ny) whose `known` is 0: going up a pyramid of 2 x 2 blocks
/// until a level is whole, each block takes the plane fitted to the known cells beneath it
/// at its centre (where they span one), then on the way down each unknown cell takes the
/// level above's bilinear value, then `sweeps` over-relaxation sweeps move the unknown
/// cells towards the mean of their 4-neighbours. A plane is filled exactly. Deterministic;
/// nothing known leaves `z` alone.
void fillHoles(std::vector<float>& z, const std::vector<std::uint8_t>& known, int nx, int ny, int sweeps);

/// The surface through the points whose `use` flag is 1: each cell the mean of their
/// heights moved to its centre along the plane through the points nearby, empty cells
/// filled (fillHoles), then with `smooth` averaged over 3 x 3 cells.
HeightRaster surfaceThrough(const std::vector<core::CloudPoint>& points, const std::vector<std::uint8_t>& use,
                            double cell_m, bool smooth);

/// 1 for each point more than `drop_m` below every other height around it (the lowest of
/// the other 1 m cells within 2 cells, the next one of its own), as `ladarvr ground` leaves
/// out multipath and noise under a real survey.
std::vector<std::uint8_t> lowOutliers(const std::vector<core::CloudPoint>& points, double drop_m);

/// MCC (Evans and Hudak 2007, §2): at three scales (cells of 0.5, 1 and 1.5 x `scale_m`,
/// tolerances `tolerance_m` + 0, 1, 2 x `tolerance_step_m`), the surface through the points
/// still ground, averaged over 3 x 3 cells; a point more than the tolerance above it is
/// dropped; repeated per scale until fewer than 1 %, 0.1 %, 0.01 % of the ground go.
struct MccOptions {
    double scale_m = 1.0;  // lambda: about the point spacing (1 point a square metre)
    double tolerance_m = 0.3;
    double tolerance_step_m = 0.1;
    int max_iterations = 40;     // per scale
    double low_outlier_m = 6.0;  // as `ladarvr ground`; 0 = none left out
    /// Only points where the surface is steeper than min_slope (0: any) and gentler than
    /// max_slope (0: any) may be dropped.
    double min_slope = 0, max_slope = 0;
};

/// 1 = ground. `start` (when given): only its ground may stay ground (MCC's test on
/// another filter's answer), else every point but the low outliers starts as ground.
std::vector<std::uint8_t> mccGround(const std::vector<core::CloudPoint>& points, const MccOptions& o,
                                    const std::vector<std::uint8_t>* start = nullptr);

/// The residual pyramid: the lowest point of each `top_cell_m` cell is ground; at each
/// finer level (cells halved down to `bottom_cell_m`) the lowest point of each cell joins
/// the ground when it lies at most the level's tolerance above the surface through the
/// ground so far (cells of the level above); last, a point is ground within `threshold_m`
/// + `scalar` x slope of the surface through the ground at the finest level (SMRF's test).
struct PyramidOptions {
    double top_cell_m = 32;
    double bottom_cell_m = 1;
    /// A level of `cell` m tolerates tolerance_m + tolerance_per_m x cell.
    double tolerance_m = 0.3;
    double tolerance_per_m = 0.05;
    /// Instead, each level's tolerance from its residuals: their median plus 3 robust
    /// sigmas (1.4826 x the median absolute deviation), at least tolerance_m.
    bool from_residuals = false;
    double threshold_m = 0.5, scalar = 1.25;
    double low_outlier_m = 6.0;
};

/// 1 = ground. `seed` (when given): its ground starts the pyramid and stays ground, and
/// only its other points are tested (ground given back to another filter's answer).
std::vector<std::uint8_t> pyramidGround(const std::vector<core::CloudPoint>& points, const PyramidOptions& o,
                                        const std::vector<std::uint8_t>* seed = nullptr);

/// Scores every variant (MCC, the pyramid, each on SMRF's answer, a few parameter sets
/// around the papers' defaults) on `samples` beside `ladarvr ground`, and prints one table:
/// per variant the means, the samples more than a point past CSF's published total error
/// and each sample's total error. Throws core::Error.
void runMultiscale(const std::vector<AdaptiveSample>& samples);

}  // namespace bench
