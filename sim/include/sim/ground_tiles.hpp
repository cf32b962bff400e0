// sim/ground_tiles.hpp: `ladarvr ground` on surveys larger than one terrain raster and on
// several files. A survey is cut into square tiles; each tile's terrain is fitted on its
// own points and on its neighbours' points within a buffer around it, and only its own
// points take their classes from that fit, so that a point's class is the one a single
// run over the whole survey gives wherever the filter's reach is within the buffer.
// The points are streamed: one pass spills each point to its tile's scratch file (and to
// the neighbours' whose buffer it is in), each tile is then fitted and labelled from its
// file alone (several at once), and a last pass reads the inputs again and writes them
// out with their tile's labels, so the memory is a few rasters and chunks, not the points.
// A tile whose raster cuts a patch that SMRF's raised-segment test could decide otherwise
// seen whole is fitted again over the patch, from the other tiles' files. With SMRF, a
// tile whose raster a hole (cells without a point) crosses from a cut edge into its
// square is first fitted again with its buffer doubled: the fill's fixed sweeps do not
// settle such a hole, and its filled heights hang on where the raster cuts it.
// A folder of tiles (one output per input) uses each input as a tile and the inputs
// whose bounds touch it as its buffer, fitted again the same way from the other inputs.
#pragma once
#include <sim/ground_file.hpp>

#include <glm/glm.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

namespace sim {

/// How tiles are fitted.
struct GroundTiling {
    double tile_m = 0;                  // side of a square tile, in the file's horizontal units, > 0
    double buffer_m = 0;                // neighbours' points this far around a tile join its fit, same units
    int jobs = 1;                       // tiles fitted at once, >= 1
    int threads = 1;                    // threads of each fit, >= 1
    std::size_t max_cells = 0;          // each fit's raster bound (the memory's share of one job)
    std::filesystem::path scratch_dir;  // where the spilled points go (the output's folder)
    /// classifyGroundNeighbours: the survey's ground thickness (surveyThickness), < 0: the
    /// tile's own (measured on it and its buffer).
    double thickness_m = -1;
    /// classifyGroundTiled: where given, gets each tile's terrain over its own square (the
    /// frame groundFrame() of the first input's reader's origin); its complete() is called
    /// before the output lands.
    DtmMosaic* dtm = nullptr;
};

/// The buffer `o`'s filter needs around a tile, in `o`'s units (inUnits applied): four
/// times SMRF's largest opening radius plus four cells (the opening's reach, the
/// low-outlier test's and the terrain's interpolation across holes), or for CSF sixty
/// cloth cells (the cloth's rigidity carries a few cells; its fall is local).
double tileBuffer(const GroundFileOptions& o);

/// A file's horizontal extent in world coordinates.
struct GroundBox {
    glm::dvec2 min{0.0}, max{0.0};
};

/// Reads the world x-y bounds of `file` (a LAS header's, else its finite points': io::
/// inspectCloud). Throws core::Error("ground: <file>: ...").
GroundBox readGroundBox(const std::filesystem::path& file);

/// Throws core::Error("ground: inputs '<a>' and '<b>' ...; allowed ...") when `inputs`
/// cannot be merged into one output: different coordinate units or CRS, or different
/// point formats (a foreign LAS point format, its extra bytes, or the fields a PCD or
/// PLY carries).
void checkMergeable(const std::vector<std::filesystem::path>& inputs);

/// `inputs` split into surveys: the indices of the inputs that share one CRS and one pair of
/// coordinate units, in input order, each survey in the order of its first input. Inputs of
/// two surveys are never one another's buffer: the same numbers in two CRSs are two places.
/// Throws core::Error("ground: ...") when an input's header cannot be read.
std::vector<std::vector<std::size_t>> surveysOf(const std::vector<std::filesystem::path>& inputs);

/// Every point of `inputs` (in order; positions in the first one's frame) classified tile
/// by tile (`t`) and written to `out`, as classifyGroundFile writes one input; tiles and
/// cells lie on the cell lattice of the first one's groundFrame (a tile's buffer doubled
/// where a hole crosses its raster from a cut edge into its square, within t.max_cells). Throws
/// core::Error("ground: ...") when the tiles would be too many (kMaxTiles; raise tile_m)
/// or a fit's raster is over t.max_cells, and the reader's and writer's errors.
/// `progress(points)` is called as points are read (four passes: the spill, the tiles'
/// thickness samples, their fits, the writing), from this thread.
inline constexpr std::size_t kMaxTiles = 400;
GroundFileStats classifyGroundTiled(const std::vector<std::filesystem::path>& inputs, const std::filesystem::path& out,
                                    const GroundFileOptions& o, const GroundTiling& t, const io::LasOptions& las,
                                    const io::CopcOptions& copc, const std::function<void(std::size_t)>& progress);

/// The ground thickness one run over every point of `inputs` would measure (the median
/// of every cell's sample, TerrainFit::thicknessSamples): each input fitted with its
/// neighbours' points within t.buffer_m, the samples of the cells whose centre lies in
/// its box taken; `jobs` inputs at once. -1 when no cell gives a sample. `progress` is
/// called with each input's points as it is done (under a lock).
double surveyThickness(const std::vector<std::filesystem::path>& inputs, const std::vector<GroundBox>& boxes,
                       const GroundFileOptions& o, const GroundTiling& t,
                       const std::function<void(std::size_t)>& progress);

/// `inputs[index]` classified as one tile of the survey `inputs` make (`boxes[k]` the
/// bounds of inputs[k]): its terrain fitted on its points and on the other inputs' points
/// within t.buffer_m of its box, in the first input's groundFrame so that the raster's
/// cells are those of one merged run and of one run over the uncut survey, with t.thickness_m (surveyThickness) where it is >= 0;
/// written to `out` as classifyGroundFile writes it. The raster spans the cells within
/// that buffer of the bounds of the inputs joined to it through their buffers (one run's
/// raster over them); where a raised-segment patch it cuts needs it, the terrain is
/// fitted again over the patch from the inputs around it (at most four times, within
/// t.max_cells), and with its buffer doubled where a hole crosses it from a cut edge, as
/// a tile of classifyGroundTiled is.
/// `progress` as classifyGroundFile's (thread-safe where the caller runs several). `dtm`,
/// where given, gets the terrain's cells whose centres lie in the input's box (the frame
/// groundFrame() of the first input's reader's origin), and its complete() is called before
/// the output lands.
GroundFileStats classifyGroundNeighbours(const std::vector<std::filesystem::path>& inputs,
                                         const std::vector<GroundBox>& boxes, std::size_t index,
                                         const std::filesystem::path& out, const GroundFileOptions& o,
                                         const GroundTiling& t, const io::LasOptions& las, const io::CopcOptions& copc,
                                         const std::function<void(std::size_t)>& progress, DtmMosaic* dtm = nullptr);

}  // namespace sim
