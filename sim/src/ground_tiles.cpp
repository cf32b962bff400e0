// sim/src/ground_tiles.cpp: see sim/ground_tiles.hpp. Three passes over the inputs: the
// spill (each point to its tile's scratch file, and to those of the neighbours whose
// buffer holds it), the tiles (each fitted from its file and its own points labelled into
// a results file, in the order they were spilled), and the writing (the inputs read again
// in the same order, each point's label taken from its tile's results in turn).
#include "ground_label.hpp"
#include "ground_raster.hpp"

#include <sim/ground_tiles.hpp>

#include <core/error.hpp>
#include <io/cloud_info.hpp>
#include <io/cloud_reader.hpp>
#include <platform/jobs.hpp>
#include <platform/scratch_file.hpp>
#include <sim/dtm.hpp>
#include <sim/ground_units.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

namespace sim {

double tileBuffer(const GroundFileOptions& o) {
    if (o.method == GroundMethod::Csf) return 60.0 * o.csf.cloth_m;
    return 4.0 * o.smrf.window_m + 4.0 * o.smrf.cell_m;
}

GroundBox readGroundBox(const std::filesystem::path& file) {
    const io::CloudInfo info = io::inspectCloud(file, "ground");
    GroundBox box;
    if (info.has_bounds) {
        box.min = glm::dvec2(info.min.x, info.min.y);
        box.max = glm::dvec2(info.max.x, info.max.y);
    }
    return box;
}

namespace {

std::string quoted(const std::filesystem::path& p) { return "'" + core::printable(p.string(), 400) + "'"; }

// What must agree between inputs merged into one output.
struct InputKind {
    CoordinateUnits units;
    std::string crs;
    bool foreign = false;
    int point_format = 0;
    bool nir = false;
    std::string extra_bytes;
    core::CloudFields fields;
};

InputKind kindOf(const std::filesystem::path& file) {
    InputKind k;
    k.units = readCoordinateUnits(file, "ground");
    const io::CloudReader reader(file, io::SideRecords::Keep);
    k.fields = reader.fields();
    if (const auto f = reader.foreignHeader()) {
        k.foreign = true;
        k.crs = f->wkt;
        k.point_format = f->point_format;
        k.nir = f->nir;
        k.extra_bytes = f->extra_bytes_vlr;
    }
    return k;
}

bool sameFields(const core::CloudFields& a, const core::CloudFields& b) {
    return a.rgb == b.rgb && a.label == b.label && a.view == b.view && a.range == b.range &&
           a.intensity == b.intensity && a.returns == b.returns && a.incidence == b.incidence &&
           a.scan_angle == b.scan_angle && a.height_above_ground == b.height_above_ground;
}

}  // namespace

void checkMergeable(const std::vector<std::filesystem::path>& inputs) {
    if (inputs.size() < 2) return;
    const InputKind first = kindOf(inputs[0]);
    for (std::size_t i = 1; i < inputs.size(); ++i) {
        const InputKind k = kindOf(inputs[i]);
        std::string why;
        if (k.units.horizontal_m != first.units.horizontal_m || k.units.vertical_m != first.units.vertical_m)
            why = "are in different units";
        else if (k.crs != first.crs)
            why = "declare different CRSs";
        else if (k.foreign != first.foreign || k.point_format != first.point_format || k.nir != first.nir ||
                 k.extra_bytes != first.extra_bytes || (!k.foreign && !sameFields(k.fields, first.fields)))
            why = "have different point formats";
        if (!why.empty())
            throw core::Error("ground: inputs " + quoted(inputs[0]) + " and " + quoted(inputs[i]) + " " + why +
                              "; allowed into one --out: inputs of one CRS, unit and point format (or one output "
                              "each with --out-dir)");
    }
}

std::vector<std::vector<std::size_t>> surveysOf(const std::vector<std::filesystem::path>& inputs) {
    std::vector<std::vector<std::size_t>> surveys;
    std::vector<InputKind> firsts;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const InputKind k = kindOf(inputs[i]);
        std::size_t s = 0;
        while (s < firsts.size() && !(firsts[s].units.horizontal_m == k.units.horizontal_m &&
                                      firsts[s].units.vertical_m == k.units.vertical_m && firsts[s].crs == k.crs))
            ++s;
        if (s == firsts.size()) {
            firsts.push_back(k);
            surveys.emplace_back();
        }
        surveys[s].push_back(i);
    }
    return surveys;
}

namespace {

// Spilled: a point in the survey's frame; `reserved` says whether it is the tile's own.
constexpr std::size_t kSpillChunk = 1u << 16;

constexpr std::size_t kResultBytes = 1 + sizeof(float);

struct Tile {
    std::optional<platform::ScratchFile> spill;
    std::optional<platform::ScratchFile> results;
    std::int64_t tx = 0, ty = 0;
    std::uint64_t own = 0, all = 0;
    int nx = 0, ny = 0;
    float top_m = 0;
    std::optional<core::HeightSpan> heights;  // its own points' heights above ground (whiten)
};

std::uint64_t tileKey(std::int64_t tx, std::int64_t ty) {
    return (std::uint64_t(std::uint32_t(std::int32_t(tx))) << 32) | std::uint32_t(std::int32_t(ty));
}

// An x-y box, lo and hi.
using XyBox = std::pair<glm::dvec2, glm::dvec2>;

// [lo, hi) within the cells of the inputs that reach it; `cells` holds each input's
// lowest and highest cell (index, not metres).
XyBox clipToCells(const std::vector<XyBox>& cells, double cell_m, const glm::dvec2& lo, const glm::dvec2& hi) {
    glm::dvec2 reach_lo(1e300), reach_hi(-1e300);
    for (const auto& [first, last] : cells) {
        const glm::dvec2 a = first * cell_m, b = (last + 1.0) * cell_m;
        if (b.x <= lo.x || a.x >= hi.x || b.y <= lo.y || a.y >= hi.y) continue;
        reach_lo = glm::min(reach_lo, a);
        reach_hi = glm::max(reach_hi, b);
    }
    return {glm::max(lo, reach_lo), glm::min(hi, reach_hi)};
}

// Whether box `b` comes within `reach_m` of box `a`.
bool within(const GroundBox& a, const GroundBox& b, double reach_m) {
    return b.max.x >= a.min.x - reach_m && b.min.x <= a.max.x + reach_m && b.max.y >= a.min.y - reach_m &&
           b.min.y <= a.max.y + reach_m;
}

// Each box's survey: the bounds of the boxes joined to it through boxes within
// `reach_m` of each other (a folder of tiles is one survey; inputs further apart are
// surveys of their own, as the tiles of one run over them take them). An empty box (min
// over max) joins none. Sorted by their lowest x, a box meets only those after it that
// start within its reach.
std::vector<GroundBox> surveyBoxes(const std::vector<GroundBox>& boxes, double reach_m) {
    std::vector<std::size_t> order(boxes.size()), parent(boxes.size());
    for (std::size_t k = 0; k < boxes.size(); ++k) order[k] = parent[k] = k;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return boxes[a].min.x < boxes[b].min.x; });
    const auto find = [&](std::size_t k) {
        while (parent[k] != k) k = parent[k] = parent[parent[k]];
        return k;
    };
    const auto empty = [](const GroundBox& b) { return b.min.x > b.max.x || b.min.y > b.max.y; };
    for (std::size_t a = 0; a < order.size(); ++a)
        for (std::size_t b = a + 1; b < order.size(); ++b) {
            const GroundBox &p = boxes[order[a]], &q = boxes[order[b]];
            if (q.min.x > p.max.x + reach_m) break;
            if (!empty(p) && !empty(q) && within(p, q, reach_m)) parent[find(order[b])] = find(order[a]);
        }
    std::vector<GroundBox> joined(boxes.size(), GroundBox{glm::dvec2(1e300), glm::dvec2(-1e300)});
    for (std::size_t k = 0; k < boxes.size(); ++k) {
        GroundBox& survey = joined[find(k)];
        survey.min = glm::min(survey.min, boxes[k].min);
        survey.max = glm::max(survey.max, boxes[k].max);
    }
    std::vector<GroundBox> out(boxes.size());
    for (std::size_t k = 0; k < boxes.size(); ++k) out[k] = joined[find(k)];
    return out;
}

class Tiler {
  public:
    // `survey`: the inputs' bounds in the survey's frame; tiles beyond them hold no point
    // of their own, so no buffer is spilled to them.
    Tiler(const GroundTiling& t, double cell_m, std::filesystem::path scratch, const GroundBox& survey)
        : t_(t),
          cell_m_(cell_m),
          inv_cell_(1.0 / cell_m),
          scratch_(std::move(scratch)),
          kx_min_(index(survey.min.x)),
          kx_max_(index(survey.max.x)),
          ky_min_(index(survey.min.y)),
          ky_max_(index(survey.max.y)) {}

    std::uint64_t ownKey(const core::CloudPoint& p) const { return tileKey(index(p.position.x), index(p.position.y)); }

    // The point to its tile's file and to every other tile whose buffer holds it. Tile k
    // spans [k T, (k + 1) T) and its buffer reaches `buffer_m` beyond, so those are the
    // tiles from the one holding x - buffer_m to the one holding x + buffer_m: more than
    // the next one where the buffer is wider than a tile.
    void spill(core::CloudPoint p, std::size_t input) {
        const double x = p.position.x, y = p.position.y;
        if (std::isfinite(p.position.z) && std::abs(x * inv_cell_) < 1e9 && std::abs(y * inv_cell_) < 1e9) {
            if (input >= cells_.size()) cells_.resize(input + 1, {glm::dvec2(1e300), glm::dvec2(-1e300)});
            const glm::dvec2 cell(std::floor(x * inv_cell_), std::floor(y * inv_cell_));
            cells_[input].first = glm::min(cells_[input].first, cell);
            cells_[input].second = glm::max(cells_[input].second, cell);
        }
        const std::int64_t tx = index(x), ty = index(y);
        for (std::int64_t ky = index(y - t_.buffer_m); ky <= index(y + t_.buffer_m); ++ky)
            for (std::int64_t kx = index(x - t_.buffer_m); kx <= index(x + t_.buffer_m); ++kx) {
                const bool own = kx == tx && ky == ty;
                if (!own && (kx < kx_min_ || kx > kx_max_ || ky < ky_min_ || ky > ky_max_)) continue;
                Tile& tile = at(tileKey(kx, ky));
                p.reserved = own ? 1 : 0;
                tile.spill->append(&p, sizeof p);
                tile.all += 1;
                tile.own += own;
            }
    }

    std::map<std::uint64_t, Tile>& tiles() { return tiles_; }
    const std::map<std::uint64_t, Tile>& tiles() const { return tiles_; }
    std::int64_t index(double v) const { return std::int64_t(std::floor(v / t_.tile_m)); }

    // The extent of a tile's raster (TerrainFit::setExtent): the raster one run over the
    // surveys that reach its buffer would have (the cells from the lowest to the highest
    // their inputs' points touch), within that buffer. A tile's points may stop short of it (a
    // survey's ragged edge), and the filling of the empty cells up to it moves the
    // surface near that edge.
    std::pair<glm::dvec2, glm::dvec2> rasterBox(const Tile& tile) const {
        const glm::dvec2 lo = glm::dvec2(double(tile.tx), double(tile.ty)) * t_.tile_m - t_.buffer_m;
        const glm::dvec2 hi = glm::dvec2(double(tile.tx + 1), double(tile.ty + 1)) * t_.tile_m + t_.buffer_m;
        return clip(lo, hi);
    }

    // [lo, hi) within the cells of the surveys that reach it (after joinSurveys()).
    XyBox clip(const glm::dvec2& lo, const glm::dvec2& hi) const { return clipToCells(cells_, cell_m_, lo, hi); }

    // Once every point is spilled: each input's cells widened to its survey's, the inputs
    // joined through their buffers (surveyBoxes), so that a tile's raster ends where one
    // run over the survey ends, not where the inputs that reach its buffer do (a survey
    // cut into files, its edge set by a file beyond the buffer).
    void joinSurveys() {
        std::vector<GroundBox> boxes;
        for (const auto& [first, last] : cells_) boxes.push_back({first * cell_m_, (last + 1.0) * cell_m_});
        const std::vector<GroundBox> surveys = surveyBoxes(boxes, t_.buffer_m);
        for (std::size_t k = 0; k < cells_.size(); ++k)
            if (surveys[k].min.x <= surveys[k].max.x)
                cells_[k] = {glm::round(surveys[k].min * inv_cell_), glm::round(surveys[k].max * inv_cell_) - 1.0};
    }

  private:
    Tile& at(std::uint64_t key) {
        auto it = tiles_.find(key);
        if (it != tiles_.end()) return it->second;
        if (tiles_.size() >= kMaxTiles)
            throw core::Error("ground: --tile-m " + std::to_string(t_.tile_m) + ": the survey makes over " +
                              std::to_string(kMaxTiles) + " tiles; allowed at most " + std::to_string(kMaxTiles) +
                              " (raise --tile-m or --memory-mb)");
        Tile& tile = tiles_[key];
        tile.tx = std::int32_t(std::uint32_t(key >> 32));
        tile.ty = std::int32_t(std::uint32_t(key));
        tile.spill.emplace(scratch_, "ground tiles");
        return tile;
    }

    GroundTiling t_;
    double cell_m_, inv_cell_;
    std::vector<XyBox> cells_;  // by input: the lowest and highest cell its points (its survey's) touched
    std::filesystem::path scratch_;
    std::int64_t kx_min_, kx_max_, ky_min_, ky_max_;  // the tiles the survey's bounds reach
    std::map<std::uint64_t, Tile> tiles_;
};

// Calls fn(chunk) for each chunk of a tile's spilled points, the own-point flag cleared
// into `own` (one per point).
void eachSpilled(Tile& tile, std::vector<core::CloudPoint>& chunk, std::vector<std::uint8_t>& own,
                 const std::function<void()>& fn) {
    tile.spill->rewind();
    for (std::uint64_t left = tile.all; left > 0;) {
        const std::size_t n = std::size_t(std::min<std::uint64_t>(left, kSpillChunk));
        chunk.resize(n);
        own.resize(n);
        tile.spill->read(chunk.data(), n * sizeof(core::CloudPoint));
        for (std::size_t i = 0; i < n; ++i) {
            own[i] = chunk[i].reserved;
            chunk[i].reserved = 0;
        }
        left -= n;
        fn();
    }
}

// A tile's fit with every point of its file added.
std::unique_ptr<TerrainFit> gather(Tile& tile, const GroundFileOptions& o, const GroundTiling& t) {
    std::unique_ptr<TerrainFit> fit = startFit(o, t.max_cells);
    std::vector<core::CloudPoint> chunk;
    std::vector<std::uint8_t> own;
    eachSpilled(tile, chunk, own, [&] { fit->add(chunk); });
    return fit;
}

// The ground thickness's samples of the cells in a tile's own square.
void tileSamples(Tile& tile, const GroundFileOptions& o, const GroundTiling& t, std::vector<double>& out) {
    const std::unique_ptr<TerrainFit> fit = gather(tile, o, t);
    const glm::dvec2 lo(double(tile.tx) * t.tile_m, double(tile.ty) * t.tile_m);
    fit->thicknessSamples(lo, lo + glm::dvec2(t.tile_m), out);
}

// A fit on the own points of every tile that lie in [box.first, box.second): a buffer
// wider than the one spilled.
std::unique_ptr<TerrainFit> gatherBox(const Tiler& tiler, const std::pair<glm::dvec2, glm::dvec2>& box,
                                      const GroundFileOptions& o, const GroundTiling& t) {
    std::unique_ptr<TerrainFit> fit = startFit(o, t.max_cells);
    const auto& [lo, hi] = box;
    std::vector<core::CloudPoint> chunk;
    for (std::int64_t ky = tiler.index(lo.y); ky <= tiler.index(hi.y); ++ky)
        for (std::int64_t kx = tiler.index(lo.x); kx <= tiler.index(hi.x); ++kx) {
            const auto it = tiler.tiles().find(tileKey(kx, ky));
            if (it == tiler.tiles().end() || !it->second.spill || it->second.own == 0) continue;
            const Tile& other = it->second;
            for (std::uint64_t at = 0; at < other.all;) {
                const std::size_t n = std::size_t(std::min<std::uint64_t>(other.all - at, kSpillChunk));
                chunk.resize(n);
                other.spill->readAt(chunk.data(), n * sizeof(core::CloudPoint), at * sizeof(core::CloudPoint));
                at += n;
                std::erase_if(chunk, [&](const core::CloudPoint& p) {
                    return p.reserved == 0 || p.position.x < lo.x || p.position.x >= hi.x || p.position.y < lo.y ||
                           p.position.y >= hi.y;
                });
                for (core::CloudPoint& p : chunk) p.reserved = 0;
                fit->add(chunk);
            }
        }
    return fit;
}

// A tile is fitted again, at most kMaxRefits times, over the whole of a patch that the
// raised-segment test decided near it (within kCutCells cells of its square) when the
// patch comes within kCutCells cells of an edge of its raster beyond which the survey
// goes on: the test sees a patch whole or not at all, and a cut one has another area and
// border. kCutCells: the low-outlier test's reach over its rounds (20 cells), within
// which a level near the cut differs from the untiled run's, and the segments' joining;
// it also covers the tall-segment test's rays (18 cells).
constexpr int kMaxRefits = 4;
constexpr double kCutCells = 22;

// The survey's cells within a box (clipToCells over the inputs), and a fit on the
// survey's points within a box: what a tile's re-fit needs from the tiles around it.
using ClipBox = std::function<XyBox(const glm::dvec2& lo, const glm::dvec2& hi)>;
using GatherBox = std::function<std::unique_ptr<TerrainFit>(const XyBox& box)>;

// The sides of a raster over `box` beyond which the survey goes on (its cut edges), low
// x and y, then high.
std::pair<glm::bvec2, glm::bvec2> cutSides(const XyBox& box, double cell_m, const ClipBox& clip) {
    const XyBox wider = clip(box.first - cell_m, box.second + cell_m);
    return {glm::lessThan(wider.first, box.first), glm::greaterThan(wider.second, box.second)};
}

// Whether a hole of `fit`'s raster (cells without a point, joined through their four
// neighbours, as the fill's relaxation joins them) runs from a cut edge (`cut`) into the
// tile's square `own`: the filled heights there then hang on where the raster was cut,
// as far as the fixed sweeps have not settled them. False for a fit that is not a
// raster's.
bool holeCutAcross(const TerrainFit& fit, const XyBox& own, const std::pair<glm::bvec2, glm::bvec2>& cut) {
    const auto* raster = dynamic_cast<const RasterFit*>(&fit);
    if (!raster) return false;
    const TerrainGrid& g = raster->surface();
    // The cells whose centres lie in the tile's square.
    const auto first = [&](double v, double x0) { return std::ceil((v - x0) / g.cell_m); };
    const double i0 = first(own.first.x, g.x0_m), i1 = first(own.second.x, g.x0_m) - 1;
    const double j0 = first(own.first.y, g.y0_m), j1 = first(own.second.y, g.y0_m) - 1;
    const auto& [lo, hi] = cut;
    return holeReaches(raster->observedCells(), g.nx, g.ny, {lo.x, lo.y, hi.x, hi.y}, i0, i1, j0, j1);
}

// Fits `fit` (a tile's points added) over `box` with the survey's thickness. Where
// `holes` (SMRF's fill of a fixed number of sweeps) and a hole runs from a cut edge into
// the tile's square `own` (holeCutAcross), it is fitted again with its buffer doubled.
// Then again over a wider box, gathered by `gather`, while a patch near `own` needs it
// (above). Every raster within the bound t.max_cells.
void fitOverPatches(std::unique_ptr<TerrainFit>& fit, XyBox box, const XyBox& own, double cell_m, double thickness_m,
                    const GroundTiling& t, bool holes, const ClipBox& clip, const GatherBox& gather) {
    const auto finish = [&] {
        fit->setExtent(box.first, box.second);
        fit->setGroundThickness(thickness_m);
        fit->setFitThreads(t.threads);
        fit->fit();
    };
    const auto fits = [&](const XyBox& b) {
        const glm::dvec2 cells = (b.second - b.first) / cell_m + 2.0;
        return cells.x * cells.y <= double(t.max_cells);
    };
    finish();
    if (holes && holeCutAcross(*fit, own, cutSides(box, cell_m, clip))) {
        const XyBox wide = clip(glm::min(box.first, own.first - 2.0 * t.buffer_m),
                                glm::max(box.second, own.second + 2.0 * t.buffer_m));
        if (wide != box && fits(wide)) {
            box = wide;
            fit = gather(box);
            finish();
        }
    }
    const double margin_m = kCutCells * cell_m;
    std::vector<XyBox> patches;
    for (int refit = 0; refit < kMaxRefits; ++refit) {
        patches.clear();
        fit->testedPatches(own.first, own.second, margin_m, patches);
        const auto [cut_lo, cut_hi] = cutSides(box, cell_m, clip);
        glm::dvec2 lo = box.first, hi = box.second;
        for (const auto& [a, b] : patches) {
            if (!((cut_lo.x && a.x < box.first.x + margin_m) || (cut_lo.y && a.y < box.first.y + margin_m) ||
                  (cut_hi.x && b.x > box.second.x - margin_m) || (cut_hi.y && b.y > box.second.y - margin_m)))
                continue;
            lo = glm::min(lo, a - t.buffer_m);
            hi = glm::max(hi, b + t.buffer_m);
        }
        const XyBox grown = clip(lo, hi);
        if (grown == box || !fits(grown)) break;
        box = grown;
        fit = gather(box);
        finish();
    }
}

// One tile: fitted on every point of its file with the survey's thickness (again over a
// wider box where a patch needs it, above), its own points labelled in order.
void runTile(Tile& tile, const Tiler& tiler, const GroundFileOptions& o, const GroundTiling& t, double thickness_m,
             double cell_m, const std::filesystem::path& scratch) {
    std::unique_ptr<TerrainFit> fit = gather(tile, o, t);
    const glm::dvec2 own_lo = glm::dvec2(double(tile.tx), double(tile.ty)) * t.tile_m;
    fitOverPatches(
        fit, tiler.rasterBox(tile), {own_lo, own_lo + t.tile_m}, cell_m, thickness_m, t, o.method == GroundMethod::Smrf,
        [&](const glm::dvec2& lo, const glm::dvec2& hi) { return tiler.clip(lo, hi); },
        [&](const XyBox& box) { return gatherBox(tiler, box, o, t); });
    tile.nx = fit->surface().nx;
    tile.ny = fit->surface().ny;
    if (t.dtm) t.dtm->add(fit->surface(), own_lo, own_lo + t.tile_m);
    tile.results.emplace(scratch, "ground tiles");
    std::vector<core::CloudPoint> chunk;
    std::vector<std::uint8_t> own;
    eachSpilled(tile, chunk, own, [&] {
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            if (own[i] == 0) continue;
            float height_m = 0;
            const std::uint8_t ground = fit->classify(chunk[i], height_m) ? 1 : 0;
            if (!ground) tile.top_m = std::max(tile.top_m, height_m);
            if (o.whiten) {
                if (!tile.heights) tile.heights = aboveGroundHeights(o);
                tile.heights->add(height_m);
            }
            unsigned char bytes[kResultBytes];
            bytes[0] = ground;
            std::memcpy(bytes + 1, &height_m, sizeof(float));
            tile.results->append(bytes, kResultBytes);
        }
    });
    tile.results->rewind();
}

// The median of the samples, as one fit over them all takes it; -1 (measure) for none.
double medianThickness(std::vector<double>& samples) {
    if (samples.empty()) return -1;
    const auto mid = samples.begin() + std::ptrdiff_t(samples.size() / 2);
    std::nth_element(samples.begin(), mid, samples.end());
    return *mid;
}

// Every tile with points of its own, `jobs` at once: first the survey's ground thickness
// from every tile's own cells, then each tile's fit and labels.
void runTiles(Tiler& tiler, const GroundFileOptions& o, const GroundTiling& t, double cell_m,
              const std::filesystem::path& scratch, const std::function<void(std::size_t)>& progress) {
    std::map<std::uint64_t, Tile>& tiles = tiler.tiles();
    std::vector<Tile*> work;
    for (auto& [key, tile] : tiles) {
        if (tile.own > 0) {
            tile.spill->flush();  // readable by the other tiles' wider fits
            work.push_back(&tile);
        } else
            tile.spill.reset();  // only the buffer of others
    }
    std::mutex mutex;
    std::vector<double> samples;
    platform::runJobs(work.size(), t.jobs, [&](std::size_t i) {
        std::vector<double> mine;
        tileSamples(*work[i], o, t, mine);
        const std::lock_guard lock(mutex);
        samples.insert(samples.end(), mine.begin(), mine.end());
    });
    for (const Tile* tile : work) progress(std::size_t(tile->own));
    const double thickness_m = medianThickness(samples);
    // A tile's wider fit reads the others' files: they go once every tile is done.
    platform::runJobs(work.size(), t.jobs,
                      [&](std::size_t i) { runTile(*work[i], tiler, o, t, thickness_m, cell_m, scratch); });
    for (Tile* tile : work) {
        tile->spill.reset();
        progress(std::size_t(tile->own));
    }
}

}  // namespace

GroundFileStats classifyGroundTiled(const std::vector<std::filesystem::path>& inputs, const std::filesystem::path& out,
                                    const GroundFileOptions& o, const GroundTiling& tiling, const io::LasOptions& las,
                                    const io::CopcOptions& copc, const std::function<void(std::size_t)>& progress) {
    GroundFileStats st;
    // Tiles of whole cells: each cell of the raster, and its thickness sample, in one tile.
    GroundTiling t = tiling;
    const double cell = groundCell(o);
    t.tile_m = std::max(1.0, std::round(t.tile_m / cell)) * cell;
    // The points are fitted in the survey's frame (the first input's origin on the cell
    // lattice, groundFrame) and written in the first input's frame.
    std::vector<glm::dvec3> shifts, writes;
    glm::dvec3 origin{0.0}, frame{0.0};
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const io::CloudReader reader(inputs[i]);
        if (i == 0) {
            origin = reader.origin();
            frame = groundFrame(origin, o);
        }
        shifts.push_back(reader.origin() - frame);
        writes.push_back(reader.origin() - origin);
    }
    const auto moveBy = [](core::CloudPoint& p, const glm::dvec3& shift) {
        if (shift != glm::dvec3(0.0)) p.position = glm::vec3(glm::dvec3(p.position) + shift);
    };

    // Pass 1: the spill, to the tiles within the inputs' bounds (a cell's margin for the
    // header's rounding).
    GroundBox survey{glm::dvec2(1e300), glm::dvec2(-1e300)};
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const GroundBox box = readGroundBox(inputs[i]);
        survey.min = glm::min(survey.min, box.min - glm::dvec2(frame) - cell);
        survey.max = glm::max(survey.max, box.max - glm::dvec2(frame) + cell);
    }
    Tiler tiler(t, cell, t.scratch_dir, survey);
    ReturnCounts counts;  // every input's: the rule of the returns is the survey's
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        io::CloudReader reader(inputs[i]);
        io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
            counts.add(chunk);
            for (core::CloudPoint& p : chunk) {
                moveBy(p, shifts[i]);
                tiler.spill(p, i);
            }
            progress(chunk.size());
        });
    }
    tiler.joinSurveys();
    // Pass 2: the tiles.
    auto& tiles = tiler.tiles();
    runTiles(tiler, o, t, cell, t.scratch_dir, progress);
    st.tiles = 0;
    core::HeightSpan heights = aboveGroundHeights(o);
    for (auto& [key, tile] : tiles) {
        if (tile.own == 0) continue;
        st.tiles += 1;
        if (std::size_t(tile.nx) * std::size_t(tile.ny) > std::size_t(st.nx) * std::size_t(st.ny)) {
            st.nx = tile.nx;
            st.ny = tile.ny;
        }
        st.colour_top_m = std::max(st.colour_top_m, tile.top_m);
        if (tile.heights) heights.merge(*tile.heights);
        tile.heights.reset();
    }
    st.colour_top_m = core::topWithoutStrays(heights.span(), st.colour_top_m);
    st.cell_m = cell;

    // Pass 3: the writing, each point's label from its tile's results in turn.
    const io::CloudFormat format = io::formatForPath(out, "ground: --out");
    const bool las_out =
        format == io::CloudFormat::Las || format == io::CloudFormat::Laz || format == io::CloudFormat::Copc;
    std::optional<io::CloudWriter> writer;
    std::optional<GroundLabeller> labeller;
    std::size_t stride = 0;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        io::CloudReader reader(inputs[i], las_out ? io::SideRecords::Keep : io::SideRecords::Drop);
        if (i == 0) {
            core::CloudFields fields = reader.fields();
            fields.label = true;
            fields.height_above_ground = true;
            if (o.whiten) fields.rgb = true;
            io::LasOptions with = las;
            with.foreign = reader.foreignHeader();
            stride = with.foreign ? with.foreign->stride() : 0;
            writer.emplace(out, format, origin, fields, with, format == io::CloudFormat::Copc ? &copc : nullptr);
            st.last_returns_only = lastReturnsOnly(o, counts);
            labeller.emplace(o, stride, st.colour_top_m, st.last_returns_only);
            if (with.foreign && !with.foreign->crs_problem.empty())
                st.reader_warning = with.foreign->crs_problem + "; written without a CRS";
        }
        io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk, std::vector<unsigned char>& records) {
            for (std::size_t k = 0; k < chunk.size(); ++k) {
                core::CloudPoint& p = chunk[k];
                core::CloudPoint fitted = p;
                moveBy(fitted, shifts[i]);
                moveBy(p, writes[i]);
                auto it = tiles.find(tiler.ownKey(fitted));
                if (it == tiles.end() || !it->second.results)
                    throw core::Error("ground: " + quoted(inputs[i]) + ": changed while it was read");
                unsigned char bytes[kResultBytes];
                it->second.results->read(bytes, kResultBytes);
                float height_m = 0;
                std::memcpy(&height_m, bytes + 1, sizeof(float));
                labeller->apply(p, stride > 0 ? records.data() + k * stride : nullptr, bytes[0] != 0, height_m, st);
            }
            st.points += chunk.size();
            writer->append(chunk, records);
            progress(chunk.size());
        });
        if (!reader.warning().empty()) st.reader_warning += (st.reader_warning.empty() ? "" : "; ") + reader.warning();
    }
    if (t.dtm) t.dtm->complete();
    writer->commit();
    return st;
}

namespace {

glm::dvec3 originOf(const std::filesystem::path& file) {
    const io::CloudReader reader(file);
    return reader.origin();
}

// The other inputs whose box comes within t.buffer_m of input `index`'s, their points
// moved into the frame of `frame` and kept within that distance.
std::vector<FitSource> neighbours(const std::vector<std::filesystem::path>& inputs, const std::vector<GroundBox>& boxes,
                                  std::size_t index, const glm::dvec3& frame, double buffer_m) {
    const GroundBox& box = boxes[index];
    std::vector<FitSource> extra;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
        if (k == index || !within(box, boxes[k], buffer_m)) continue;
        FitSource s;
        s.file = inputs[k];
        s.shift = originOf(inputs[k]) - frame;
        s.min = glm::dvec2(box.min.x - buffer_m - frame.x, box.min.y - buffer_m - frame.y);
        s.max = glm::dvec2(box.max.x + buffer_m - frame.x, box.max.y + buffer_m - frame.y);
        extra.push_back(std::move(s));
    }
    return extra;
}

}  // namespace

double surveyThickness(const std::vector<std::filesystem::path>& inputs, const std::vector<GroundBox>& boxes,
                       const GroundFileOptions& o, const GroundTiling& t,
                       const std::function<void(std::size_t)>& progress) {
    const glm::dvec3 frame = groundFrame(originOf(inputs[0]), o);
    std::mutex mutex;
    std::vector<double> samples;
    platform::runJobs(inputs.size(), t.jobs, [&](std::size_t i) {
        const std::unique_ptr<TerrainFit> fit = startFit(o, t.max_cells);
        std::vector<FitSource> sources = neighbours(inputs, boxes, i, frame, t.buffer_m);
        FitSource own;
        own.file = inputs[i];
        own.shift = originOf(inputs[i]) - frame;
        own.min = glm::dvec2(-1e300);
        own.max = glm::dvec2(1e300);
        sources.insert(sources.begin(), own);
        std::size_t read = 0;
        for (const FitSource& source : sources)
            addSource(*fit, source, [&](std::size_t n) { read += source.file == inputs[i] ? n : 0; });
        std::vector<double> mine;
        const GroundBox& box = boxes[i];
        fit->thicknessSamples(box.min - glm::dvec2(frame), box.max - glm::dvec2(frame), mine);
        const std::lock_guard lock(mutex);
        samples.insert(samples.end(), mine.begin(), mine.end());
        progress(read);
    });
    return medianThickness(samples);
}

GroundFileStats classifyGroundNeighbours(const std::vector<std::filesystem::path>& inputs,
                                         const std::vector<GroundBox>& boxes, std::size_t index,
                                         const std::filesystem::path& out, const GroundFileOptions& o,
                                         const GroundTiling& t, const io::LasOptions& las, const io::CopcOptions& copc,
                                         const std::function<void(std::size_t)>& progress, DtmMosaic* dtm) {
    // The first input's frame on the cell lattice: the raster's cells lie where one
    // merged run, or one run over the uncut survey, puts them.
    const glm::dvec3 frame = groundFrame(originOf(inputs[0]), o);
    const glm::dvec2 at(frame);
    const double cell_m = groundCell(o);
    // The cells of the survey's bounds (one merged run's raster), and the input's own
    // box, in the frame.
    const GroundBox survey = surveyBoxes(boxes, t.buffer_m)[index];
    const std::vector<XyBox> cells{{glm::floor((survey.min - at) / cell_m), glm::floor((survey.max - at) / cell_m)}};
    const XyBox own{boxes[index].min - at, boxes[index].max - at};
    const ClipBox clip = [&](const glm::dvec2& lo, const glm::dvec2& hi) { return clipToCells(cells, cell_m, lo, hi); };
    // A wider fit reads every input whose bounds reach its box (the inputs stay where
    // they are, so there is nothing to keep).
    const GatherBox gather = [&](const XyBox& box) {
        std::unique_ptr<TerrainFit> fit = startFit(o, t.max_cells);
        const GroundBox world{box.first + at, box.second + at};
        for (std::size_t k = 0; k < inputs.size(); ++k)
            if (within(world, boxes[k], 0.0))
                addSource(*fit, FitSource{inputs[k], originOf(inputs[k]) - frame, box.first, box.second});
        return fit;
    };
    // The raster spans the survey's cells within the buffer of the input's box, as a
    // tile's does, and is fitted again over a raised-segment patch that it cuts.
    const FitOver over = [&](std::unique_ptr<TerrainFit>& fit) {
        fitOverPatches(fit, clip(own.first - t.buffer_m, own.second + t.buffer_m), own, cell_m, t.thickness_m, t,
                       o.method == GroundMethod::Smrf, clip, gather);
    };
    return classifyOneFile(inputs[index], originOf(inputs[index]) - frame,
                           neighbours(inputs, boxes, index, frame, t.buffer_m), out, o, t.max_cells, t.threads,
                           t.thickness_m, las, copc, progress, over, dtm, own.first, own.second);
}

}  // namespace sim
