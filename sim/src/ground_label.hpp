// sim/src/ground_label.hpp: what the one-file and the tiled `ladarvr ground` share: the
// filter started with a raster bound, a point's class and colour from its fit, and the
// classification of one file whose terrain is fitted on its points and on points of other
// files around it (a folder of tiles).
#pragma once
#include <core/height_span.hpp>
#include <sim/ground.hpp>
#include <sim/ground_file.hpp>

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace sim {

/// `o`'s filter with its raster bounded by `max_cells` (and its own bound).
std::unique_ptr<TerrainFit> startFit(const GroundFileOptions& o, std::size_t max_cells);

/// No heights above the terrain yet: with every point's, they give the top of the jet map
/// of `whiten`, stray returns left out (core::kStrayGap_m in the cloud's height unit).
inline core::HeightSpan aboveGroundHeights(const GroundFileOptions& o) {
    return core::HeightSpan(core::kStrayGap_m / (o.method == GroundMethod::Csf ? o.csf.z_unit_m : o.smrf.z_unit_m));
}

/// Gives a point its class as classifyGroundFile writes it: label, height above ground,
/// the foreign record's ASPRS class, and with GroundFileOptions::whiten its colour.
class GroundLabeller {
  public:
    /// `stride`: the side records' bytes per point (0: none); `colour_top_m`: the height
    /// above ground where the jet map ends (whiten only); `last_only`: a return that is not
    /// its pulse's last is not ground (lastReturnsOnly).
    GroundLabeller(const GroundFileOptions& o, std::size_t stride, float colour_top_m, bool last_only);
    /// Labels `p` (and its side record at `record` when stride > 0) and counts it in `st`;
    /// `ground` is the fit's word, which `last_only` may overrule.
    void apply(core::CloudPoint& p, unsigned char* record, bool ground, float height_m, GroundFileStats& st) const;

  private:
    const GroundFileOptions& o_;
    std::size_t stride_;
    float top_m_;
    bool last_only_;
    std::vector<std::uint32_t> jet_;
};

/// Where a fit takes more points from: a file, its points moved by `shift` into the fit's
/// frame, only those within [min, max] (x-y, in that frame) kept.
struct FitSource {
    std::filesystem::path file;
    glm::dvec3 shift{0.0};
    glm::dvec2 min{0.0}, max{0.0};
};

/// Fits a terrain whose points are added (its threads and thickness set), and may
/// replace it by another fit over a wider box (a tile's re-fit over a patch it cuts).
using FitOver = std::function<void(std::unique_ptr<TerrainFit>& fit)>;

/// classifyGroundFile with the fit in another frame and fed more points: `in`'s points
/// are moved by `shift` for the fit and the test (written where they are), and `extra`'s
/// points join the fit (GroundFileOptions::returns decided on `in`'s points alone). `threads` >= 1 share each fit's gathering and fitting;
/// `thickness_m` >= 0 is the ground thickness the fit uses (TerrainFit::setGroundThickness).
/// `fit_over`, where given, runs the fit in place of TerrainFit::fit(). `dtm`, where given,
/// gets the fitted terrain's cells whose centres lie in [dtm_lo, dtm_hi] (the fit's frame).
GroundFileStats classifyOneFile(const std::filesystem::path& in, const glm::dvec3& shift,
                                const std::vector<FitSource>& extra, const std::filesystem::path& out,
                                const GroundFileOptions& o, std::size_t max_cells, int threads, double thickness_m,
                                const io::LasOptions& las, const io::CopcOptions& copc,
                                const std::function<void(std::size_t)>& progress, const FitOver& fit_over = {},
                                DtmMosaic* dtm = nullptr,
                                const glm::dvec2& dtm_lo = glm::dvec2(-std::numeric_limits<double>::infinity()),
                                const glm::dvec2& dtm_hi = glm::dvec2(std::numeric_limits<double>::infinity()));

/// Adds `source`'s points within its box to `fit`, read a chunk at a time; `progress`,
/// where given, is called with each chunk's points as read. The points are gathered on
/// one thread (TerrainFit::add), as every pass of a run gathers them: another thread would
/// gather its share into a raster of its own beside the run's, which the run's memory plan
/// (--memory-mb) does not count, and where the points are many the run is their reading and
/// writing. The fit itself uses the run's threads (TerrainFit::setFitThreads).
void addSource(TerrainFit& fit, const FitSource& source, const std::function<void(std::size_t)>& progress = {});

}  // namespace sim
