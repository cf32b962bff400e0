// sim/ground_file.hpp: the ground of a cloud we did not generate (`ladarvr ground`): a
// whole-cloud filter (SMRF or CSF, sim/ground.hpp) run on a file's points, read twice
// (pass 1 fits the terrain, pass 2 labels each point and writes it), so the memory is the
// terrain raster and two chunks whatever the file's size. The defaults are the options
// that did best with one parameter set on the ISPRS filter-test samples (real airborne
// surveys; `ladarvr bench ground-isprs`), not the generator's.
#pragma once
#include <io/cloud_io.hpp>
#include <io/copc_writer.hpp>
#include <sim/ground.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace sim {

class DtmMosaic;

/// How far below the ground around it a return is a low outlier in a real survey
/// (SmrfOptions::low_outlier_m): the best single value on the ISPRS samples.
inline constexpr double kSurveyLowOutlier_m = 6.0;
/// The hole filling's sweeps in a real survey (SmrfOptions::fill_sweeps).
inline constexpr int kSurveyFillSweeps = 100;
/// SMRF's options for real airborne surveys: PDAL's defaults (the best one set of cell,
/// slope, window, threshold and scalar on the ISPRS samples) with low outliers left out,
/// raised segments taken out and sparse openings.
SmrfOptions surveySmrfOptions();
/// CSF's options for real airborne surveys: the paper's with low outliers left out.
CsfOptions surveyCsfOptions();

/// Which of a pulse's returns may be ground.
enum class GroundReturns {
    Auto,  // Last in a discrete-return cloud (ReturnCounts::discrete), All otherwise
    Last,  // only a pulse's last return (or its only one)
    All,   // any return the filter finds on the terrain
};

/// "auto", "last" or "all"; throws core::Error("<what> <name>: allowed auto, last, all").
GroundReturns parseGroundReturns(const std::string& name, const std::string& what);

/// Whether `p` is not its pulse's last return: its return number 1 .. returns - 1. A
/// return number of 0 (not recorded), or one at or above the count, is taken as last.
inline bool notLastReturn(const core::CloudPoint& p) { return p.return_number >= 1 && p.return_number < p.returns; }

/// A cloud's points counted by their returns: what GroundReturns::Auto decides on.
struct ReturnCounts {
    std::size_t single = 0;    // the only return of their pulse
    std::size_t not_last = 0;  // notLastReturn
    void add(std::span<const core::CloudPoint> points);
    void add(const ReturnCounts& other) {
        single += other.single;
        not_last += other.not_last;
    }
    /// A discrete-return cloud: some pulses gave one return and some points are not their
    /// pulse's last. In such a survey a return that is not the last has a farther one
    /// behind it and is not the ground (no producer's class 2 of the real surveys holds
    /// one). A file that stores every pulse's first and last echo as two full sets (the
    /// ISPRS raw sites: each point "1 of 2" or "2 of 2", no single return) is not: its
    /// first echo lies on the ground wherever the pulse hit only the ground.
    bool discrete() const { return single > 0 && not_last > 0; }
};

/// What `ladarvr ground` runs.
struct GroundFileOptions {
    GroundMethod method = GroundMethod::Smrf;  // Smrf or Csf (RANSAC works per view)
    SmrfOptions smrf = surveySmrfOptions();
    CsfOptions csf = surveyCsfOptions();
    /// A LAS/LAZ/COPC input from another producer keeps its ASPRS classes: ground points
    /// become class 2, its class-2 points that are not ground become 1, every other class
    /// stays. With `reclassify`, every point that is not ground becomes class 1.
    bool reclassify = false;
    /// The paper's colours written as each point's RGB: ground white, every other point
    /// by its height above the terrain on the jet map (sim/colour.hpp; red at the ground,
    /// blue at the highest point above it in the output).
    bool whiten = false;
    /// A LAS/LAZ/COPC input's point more than the filter's low-outlier gap below the
    /// terrain (SmrfOptions::low_outlier_m, CsfOptions::low_outlier_m: the returns the fit
    /// left out as low outliers) gets ASPRS class 7, low point (noise), rather than 1 or
    /// its own class. Nothing with the gap 0 (low outliers kept) or without side records.
    bool mark_noise = false;
    /// Which returns may be ground: with Last (Auto in a discrete-return cloud), a return
    /// that is not its pulse's last is never ground, whatever its height; the terrain is
    /// fitted on every return either way.
    GroundReturns returns = GroundReturns::Auto;
};

/// Whether only last returns may be ground under `o` in a cloud of these counts.
bool lastReturnsOnly(const GroundFileOptions& o, const ReturnCounts& counts);

/// Throws core::Error("ground: ...") naming the option when `o` cannot run: RANSAC named,
/// or a filter's option out of its range (validate(SmrfOptions) etc.).
void validate(const GroundFileOptions& o);
/// One line: the method and its options, e.g. "smrf (cell 1 m, slope 0.15, ...)".
std::string describe(const GroundFileOptions& o);

/// The side of `o`'s raster cells, in its units: SMRF's cell, CSF's cloth.
double groundCell(const GroundFileOptions& o);

/// The frame `ladarvr ground` fits a file's points in: `origin` (its reader's) moved down
/// in x and y to a whole multiple of groundCell(o), z kept. The raster's cells then lie on
/// one lattice of the survey's coordinates, whatever file, cut or tile of the survey is
/// read and wherever its reader puts its origin; a reader's origin is in whole units, so
/// with a cell that divides one unit the frame is that origin.
glm::dvec3 groundFrame(const glm::dvec3& origin, const GroundFileOptions& o);

/// The filter on points in memory: one flag per point, 1 = ground. The same labels as
/// classifyGroundFile gives for a file of these points whose origin is its groundFrame()
/// (a point's view is its LAS point source ID, whose height error a thick ground's fit
/// estimates; GroundFileOptions::returns decided on these points' returns). Needs
/// validate(o) passed.
std::vector<std::uint8_t> classifyGround(std::span<const core::CloudPoint> points, const GroundFileOptions& o);

/// What classifyGroundFile did.
struct GroundFileStats {
    std::size_t points = 0;           // written
    std::size_t ground_points = 0;    // of them, labelled ground
    std::size_t was_ground = 0;       // labelled ground in the input (LAS class 2)
    std::size_t still_ground = 0;     // of those, labelled ground again
    std::size_t noise_points = 0;     // given class 7 (GroundFileOptions::mark_noise)
    bool last_returns_only = false;   // lastReturnsOnly held
    std::size_t not_last_points = 0;  // on the terrain but not ground: not their pulse's last return
    std::string reader_warning;       // io::CloudReader::warning() of the input, or empty
    int nx = 0, ny = 0;               // the terrain raster (the largest tile's when tiled)
    double cell_m = 0;
    std::size_t tiles = 1;   // terrain fits run (tiles with points of their own)
    float colour_top_m = 0;  // with whiten: the height above ground the jet map ends at
};

/// Reads `in` (any cloud io::CloudReader reads) twice, fitted in its groundFrame(), and
/// writes every point to `out`
/// (format from its name) with label Ground where the filter says ground and
/// GroundFileOptions::returns allows it (decided on `in`'s own returns) and Environment
/// elsewhere (a target label is kept), its height above the terrain, every other field
/// as read. A LAS/LAZ/COPC file from another producer keeps every field it carries (its
/// classes as GroundFileOptions::reclassify says, its CRS, colours, GPS times, extra
/// bytes: io::LasOptions::foreign) when `out` is LAS, LAZ or COPC. `max_cells` bounds
/// the terrain raster (the caller's memory bound); a cloud wider than that is refused
/// naming the cell option. `las` and `copc` go to the writer.
/// `progress(points)` is called as points are read (both passes; a third before the
/// writing with GroundFileOptions::whiten, which finds the colour map's top). The output is written
/// through io::CloudWriter (a temporary renamed into place); the caller checks that `out`
/// may be written and is not `in`. `threads` share the fit (the same fit whatever their
/// number). `dtm`, where given, gets the fitted terrain (its frame groundFrame() of `in`'s
/// reader's origin), and its complete() is called before the output lands. Throws core::Error.
GroundFileStats classifyGroundFile(const std::filesystem::path& in, const std::filesystem::path& out,
                                   const GroundFileOptions& o, std::size_t max_cells, const io::LasOptions& las,
                                   const io::CopcOptions& copc, const std::function<void(std::size_t)>& progress,
                                   int threads = 1, DtmMosaic* dtm = nullptr);

}  // namespace sim
