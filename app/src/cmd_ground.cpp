// app/src/cmd_ground.cpp: `ladarvr ground IN... (--out OUT | --out-dir DIR) [--method
// smrf|csf] [--smrf-*|--csf-*] [--returns auto|last|all] [--reclassify] [--whiten] [--jobs K] [--threads N]
// [--only-tile I] [--dtm DTM.asc|DTM.tif | --dtm-dir DIR [--dtm-format asc|tif]] [--dtm-tiff
// auto|classic|bigtiff] [--json]`: the
// ground of clouds we did not generate (real surveys' LAS/LAZ, a folder of their tiles, or
// any cloud we read), classified by a whole-cloud filter (sim/ground_file.hpp)
// and written with every ground point labelled ground (LAS class 2); a LAS/LAZ/COPC input
// keeps its other classes and every other field it carries. One input whose terrain
// raster fits the memory is classified in one run; a larger survey, or several inputs
// merged into --out, tile by tile with a buffer (sim/ground_tiles.hpp); with --out-dir
// each input is a tile written to a file of its own, its neighbours its buffer. Options
// are parsed and checked here. The defaults are the set tuned on the ISPRS samples
// (docs/ground.md), not `generate --ground`'s.
#include "cli_common.hpp"
#include "commands.hpp"
#include "ground_options.hpp"

#include <core/error.hpp>
#include <io/cloud_info.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc_writer.hpp>
#include <platform/atomic_file.hpp>
#include <platform/input_set.hpp>
#include <platform/jobs.hpp>
#include <platform/progress.hpp>
#include <platform/safe_file.hpp>
#include <sim/dtm.hpp>
#include <sim/ground_file.hpp>
#include <sim/ground_tiles.hpp>
#include <sim/ground_units.hpp>
#include <sim/memory_budget.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>

namespace app {
namespace {

// What the terrain raster holds per cell while it is gathered and fitted: the lowest
// heights with their views (100 bytes) and the fit's working rasters.
constexpr std::uint64_t kBytesPerCell = 160;
// A tile's side at most, metres: the tiles of a large survey stay a few rasters' size even
// where the memory would allow one huge one, so that --jobs has tiles to share.
constexpr double kLargestTile_m = 2000.0;
// A raster at least this large with at least this many cells a point: SMRF's run is mostly
// the filling and opening of empty cells, and a coarser cell would shorten it.
constexpr std::uint64_t kSparseRasterCells = 500000, kSparseCellsPerPoint = 50;
// --dtm over several inputs: one grid may span at most this many times the cells of the
// inputs' bounds, plus this many (tiles of one survey, not surveys far apart).
constexpr std::uint64_t kDtmSpread = 16, kDtmSpreadCells = 1000000;
// Input files of one run at most (a folder's tiles included).
constexpr std::size_t kMostInputs = 65536;

struct GroundFileCli {
    std::vector<std::string> in;
    std::vector<std::string> in_folders;  // the inputs that were folders of tiles
    std::string out, out_dir;
    std::string dtm;                 // --dtm: the terrain as an ESRI ASCII grid or a GeoTIFF; empty: none
    std::string dtm_dir;             // --dtm-dir: with --out-dir, one grid per input in this folder
    std::string dtm_format = "asc";  // --dtm-format: --dtm-dir's grids, asc or tif
    std::string dtm_tiff = "auto";   // --dtm-tiff: a GeoTIFF grid as classic TIFF or BigTIFF
    std::string method = "smrf";
    std::string returns = "auto";
    sim::GroundFileOptions options;
    double low_outlier_m = sim::kSurveyLowOutlier_m;
    double memory_mb = 1024.0;
    double tile_m = 0;  // 0: tiles only where one raster does not fit
    int jobs = 1, threads = 0, only_tile = -1;
    bool json = false;
};

// The memory of one job: the reader's two chunks of points and of side records (a
// foreign LAS file's ForeignPoint and extra bytes), the writer's share, and a raster.
struct MemoryPlan {
    std::uint64_t budget = 0, per_job = 0;
    io::CopcOptions copc;
    std::size_t max_cells = 0;  // a raster's cells in each job
};

std::size_t sideBytes(const std::string& file, io::CloudFormat format) {
    if (format != io::CloudFormat::Las && format != io::CloudFormat::Laz && format != io::CloudFormat::Copc) return 0;
    const io::CloudReader reader(file, io::SideRecords::Keep);
    const auto foreign = reader.foreignHeader();
    return foreign ? foreign->stride() : 0;
}

// `held`: bytes the run holds beside the jobs (the tiles' ground thickness samples).
MemoryPlan planMemory(const GroundFileCli& cli, io::CloudFormat format, std::size_t side_bytes, int jobs,
                      std::uint64_t held = 0) {
    MemoryPlan plan;
    plan.budget = sim::memoryBudgetBytes(cli.memory_mb, "ground");
    const std::uint64_t reading =
        2 * io::CloudReader::kChunkPoints * (sizeof(core::CloudPoint) + std::uint64_t(side_bytes));
    std::uint64_t writing = 2 * io::lazChunkBytes();
    const std::uint64_t share = (plan.budget > held ? plan.budget - held : 0) / std::uint64_t(jobs);
    if (format == io::CloudFormat::Copc) {
        writing = std::max<std::uint64_t>(io::copcMinimumBytes(0), share > reading ? (share - reading) / 2 : 0);
        plan.copc.memory_bytes = writing;
    }
    const std::uint64_t least = reading + writing + 1024 * kBytesPerCell;
    sim::refuseOverBudget("ground", plan.budget, held + std::uint64_t(jobs) * least,
                          (jobs > 1 ? "for each job of --jobs: " : std::string()) +
                              "two chunks of points and their side records read, the writer's buffers and a raster",
                          jobs > 1 ? "raise --memory-mb or lower --jobs" : "raise --memory-mb");
    plan.per_job = share;
    plan.max_cells = std::size_t((share - reading - writing) / kBytesPerCell);
    return plan;
}

// The box a run plans its raster and tiles over: a LAS/LAZ/COPC file's header bounds, read
// without decoding its points (the passes that classify them decode them), or a PCD or
// PLY file's points' bounds.
sim::GroundBox groundBox(const std::filesystem::path& file) {
    const io::CloudBounds bounds = io::readCloudBounds(file, "ground");
    sim::GroundBox box;
    if (bounds.has_bounds) {
        box.min = glm::dvec2(bounds.min.x, bounds.min.y);
        box.max = glm::dvec2(bounds.max.x, bounds.max.y);
    }
    return box;
}

// The LAZ writer's compressing threads for one run whose raster spans `cells` (the
// output is the same whatever their number): one per core, fewer where the memory left
// beside `plan`'s raster cannot hold their chunks (each thread holds one more chunk of
// points and their side records), none where it holds no more. Lowers
// `plan.max_cells` by what the threads' chunks take.
int writerThreads(MemoryPlan& plan, io::CloudFormat format, std::size_t side_bytes, std::uint64_t cells) {
    if (format != io::CloudFormat::Laz) return 0;
    const std::uint64_t chunk = io::lazChunkBytes() + io::lazChunkPoints() * std::uint64_t(side_bytes);
    int threads = int(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
    for (; threads > 0; --threads) {
        const std::uint64_t cells_left = std::uint64_t(threads) * chunk / kBytesPerCell + 1;
        if (plan.max_cells > cells_left && cells <= plan.max_cells - cells_left) {
            plan.max_cells -= std::size_t(cells_left);
            break;
        }
    }
    return threads;
}

// The cells one run's raster spans over `box` (the filter's grid, in the file's frame).
std::uint64_t cellsOver(const sim::GroundBox& box, const glm::dvec3& origin, double cell) {
    const auto span = [&](double lo, double hi, double o) {
        return std::uint64_t(std::floor((hi - o) / cell) - std::floor((lo - o) / cell)) + 1;
    };
    return span(box.min.x, box.max.x, origin.x) * span(box.min.y, box.max.y, origin.y);
}

double filterCell(const sim::GroundFileOptions& o) {
    return o.method == sim::GroundMethod::Csf ? o.csf.cloth_m : o.smrf.cell_m;
}
std::size_t filterMaxCells(const sim::GroundFileOptions& o) {
    return o.method == sim::GroundMethod::Csf ? o.csf.max_cells : o.smrf.max_cells;
}

// The tile side (file units) whose raster, buffer included, fits `max_cells`.
double tileSide(const GroundFileCli& cli, const sim::GroundFileOptions& o, const sim::CoordinateUnits& units,
                std::size_t max_cells, double buffer) {
    const double cell = filterCell(o);
    const double fits = std::floor(std::sqrt(double(std::min(max_cells, filterMaxCells(o))))) - 2.0;
    const double side = fits * cell - 2.0 * buffer;
    if (cli.tile_m > 0) {
        const double forced = cli.tile_m / units.horizontal_m;
        if (forced > side)
            throw core::Error("ground: --tile-m " + core::printable(std::to_string(cli.tile_m), 40) +
                              ": a tile's raster with its buffer is over the memory's share; allowed at most " +
                              std::to_string(std::max(0.0, side * units.horizontal_m)) + " m (or raise --memory-mb)");
        return forced;
    }
    // A tile narrower than its buffer would fit more buffer than points of its own.
    if (side < std::max(buffer, 16.0 * cell)) {
        std::ostringstream mb;
        mb << cli.memory_mb;
        throw core::Error("ground: --memory-mb " + mb.str() +
                          ": a tile at least as wide as its buffer does not fit with its buffer; raise --memory-mb" +
                          (cli.jobs > 1 ? " or lower --jobs" : ""));
    }
    return std::min(side, kLargestTile_m / units.horizontal_m);
}

// Where an ASCII grid's CRS goes: beside it, under its name with .prj. A GeoTIFF holds its
// own (its GeoTIFF keys): none.
std::optional<std::filesystem::path> prjFor(const std::filesystem::path& grid) {
    if (isGeoTiffName(grid)) return std::nullopt;
    return std::filesystem::path(grid).replace_extension(".prj");
}

// --dtm-tiff's value as the writer's kind.
io::TiffKind tiffKind(const GroundFileCli& cli) {
    if (cli.dtm_tiff == "classic") return io::TiffKind::classic;
    if (cli.dtm_tiff == "bigtiff") return io::TiffKind::big;
    return io::TiffKind::automatic;
}

// One grid of the terrain (--dtm, or one of --dtm-dir's) with its input's CRS: an ESRI
// ASCII grid with the CRS beside it in a .prj of its name (as GIS read an ASCII grid's)
// when the input has one (OGC WKT, up to a NUL), or a GeoTIFF with the CRS in its keys.
// Written to temporaries before the cloud lands, renamed into place after it.
class DtmOutput {
  public:
    DtmOutput(const std::filesystem::path& grid, const std::filesystem::path& input, io::TiffKind kind)
        : grid_(grid), prj_(prjFor(grid)), kind_(kind) {
        if (const auto foreign = io::CloudReader(input, io::SideRecords::Keep).foreignHeader())
            wkt_ = foreign->wkt.substr(0, foreign->wkt.find('\0'));
    }
    DtmOutput(const DtmOutput&) = delete;
    DtmOutput& operator=(const DtmOutput&) = delete;

    const std::filesystem::path& grid() const { return grid_; }

    // Before any work: its folder made, the grid's destination and the .prj's checked.
    void prepare(const platform::InputSet& inputs, std::string_view option) const {
        createParentFolders(grid_, option);
        platform::checkWritableDestination(grid_, inputs);
        if (prj_ && !wkt_.empty()) platform::checkWritableDestination(*prj_, inputs);
    }

    // The grid of `cell` cells on the lattice of `frame`, for the classifier to fill.
    sim::DtmMosaic& start(double cell, const glm::dvec3& frame) {
        const std::filesystem::path folder = grid_.parent_path();
        mosaic_.emplace(folder.empty() ? std::filesystem::path(".") : folder, core::printable(grid_.string(), 400),
                        cell, frame);
        mosaic_->on_complete = [this](sim::DtmMosaic& grid) {
            grid_file_ = std::make_unique<platform::TempFile>(grid_);
            if (!prj_) {
                std::string problem;
                const std::vector<io::GeoKey> keys = io::geoKeysForWkt(wkt_, problem);
                for (const io::GeoKey& k : keys)
                    if ((k.id == 3072 || k.id == 2048) && k.value != 32767) epsg_ = k.value;
                keyed_ = !keys.empty();
                big_ = grid.writeGeoTiff(grid_file_->file(), keys, kind_);
                return;
            }
            grid.write(grid_file_->file());
            if (wkt_.empty()) return;
            prj_file_ = std::make_unique<platform::TempFile>(*prj_);
            if (std::fwrite(wkt_.data(), 1, wkt_.size(), prj_file_->file()) != wkt_.size() ||
                std::fflush(prj_file_->file()) != 0)
                throw core::Error("output: " + core::printable(prj_->string(), 400) +
                                  ": write failed: " + std::strerror(errno));
        };
        return *mosaic_;
    }

    // After the cloud landed.
    void commit() {
        if (grid_file_) grid_file_->commit();
        if (prj_file_) prj_file_->commit();
    }

    int columns() const { return mosaic_ ? mosaic_->columns() : 0; }
    int rows() const { return mosaic_ ? mosaic_->rows() : 0; }
    sim::DtmMosaic* mosaic() { return mosaic_ ? &*mosaic_ : nullptr; }

    // Where the CRS went, for the JSON: the .prj's path, the GeoTIFF's keys ("EPSG:N", or
    // "GeoTIFF keys" for a CRS without a code), or null.
    nlohmann::json crsJson() const {
        if (prj_file_) return std::filesystem::absolute(*prj_).string();
        if (keyed_) return epsg_ ? "EPSG:" + std::to_string(epsg_) : std::string("GeoTIFF keys");
        return nullptr;
    }
    bool bigTiff() const { return big_; }
    // "bigtiff" for a BigTIFF, "classic" for a classic TIFF, null for an ASCII grid.
    nlohmann::json tiffJson() const {
        if (prj_) return nullptr;
        return big_ ? "bigtiff" : "classic";
    }
    // The same for the text line.
    std::string crsLine() const {
        if (prj_file_) return ", its CRS in " + platform::messageLine(prj_->string(), 400);
        if (keyed_)
            return epsg_ ? ", its CRS in its GeoTIFF keys (EPSG:" + std::to_string(epsg_) + ")"
                         : std::string(", its CRS in its GeoTIFF keys");
        return wkt_.empty() ? ", no CRS (the input has none)" : ", no CRS (PROJ cannot read the input's)";
    }

  private:
    std::filesystem::path grid_;
    std::optional<std::filesystem::path> prj_;  // an ASCII grid's .prj
    io::TiffKind kind_;                         // a GeoTIFF's: classic, BigTIFF, or as its size needs
    std::string wkt_;
    std::optional<sim::DtmMosaic> mosaic_;
    std::unique_ptr<platform::TempFile> grid_file_, prj_file_;
    int epsg_ = 0;        // a GeoTIFF's horizontal EPSG code, 0 none
    bool keyed_ = false;  // a GeoTIFF with keys
    bool big_ = false;    // a GeoTIFF written as a BigTIFF
};

void printStats(const GroundFileCli& cli, const std::string& in, const std::string& out, const sim::GroundFileStats& st,
                const sim::CoordinateUnits& units, bool tiled, double seconds, nlohmann::json* array,
                const DtmOutput* dtm = nullptr) {
    const double share = st.points > 0 ? 100.0 * double(st.ground_points) / double(st.points) : 0.0;
    if (cli.json) {
        nlohmann::json j;
        j["in"] = in;
        if (cli.in.size() > 1 && cli.out_dir.empty()) j["inputs"] = cli.in;
        j["out"] = out;
        j["method"] = sim::groundMethodName(cli.options.method);
        j["options"] = sim::describe(cli.options);
        j["points"] = st.points;
        j["ground_points"] = st.ground_points;
        j["input_ground_points"] = st.was_ground;
        j["input_ground_points_kept"] = st.still_ground;
        if (cli.options.mark_noise) j["noise_points"] = st.noise_points;
        j["ground_returns"] = st.last_returns_only ? "last" : "all";
        j["not_last_points"] = st.not_last_points;
        j["raster"] = {{"nx", st.nx}, {"ny", st.ny}, {"cell_m", st.cell_m * units.horizontal_m}};
        if (tiled) j["tiles"] = st.tiles;
        if (dtm)
            j["dtm"] = {{"path", std::filesystem::absolute(dtm->grid()).string()},
                        {"columns", dtm->columns()},
                        {"rows", dtm->rows()},
                        {"cell_m", st.cell_m * units.horizontal_m},
                        {"crs", dtm->crsJson()},
                        {"tiff", dtm->tiffJson()}};
        j["seconds"] = seconds;
        if (array) {
            array->push_back(std::move(j));
            return;
        }
        std::printf("%s\n", j.dump(2).c_str());
        return;
    }
    std::printf("ground: wrote %s: %zu points, %zu ground (%.2f %%), ", platform::messageLine(out, 400).c_str(),
                st.points, st.ground_points, share);
    if (cli.options.mark_noise) std::printf("%zu low noise (class 7), ", st.noise_points);
    if (st.last_returns_only)
        std::printf("last returns only (%zu earlier returns on the terrain left out), ", st.not_last_points);
    std::printf("%s, ", sim::describe(cli.options).c_str());
    if (tiled)
        std::printf("%zu tiles, largest raster %d x %d, %.3f s\n", st.tiles, st.nx, st.ny, seconds);
    else
        std::printf("raster %d x %d, %.3f s\n", st.nx, st.ny, seconds);
    if (dtm)
        std::printf("ground: wrote %s: the terrain%s, %d x %d cells of %g m%s\n",
                    platform::messageLine(dtm->grid().string(), 400).c_str(), dtm->bigTiff() ? " as a BigTIFF" : "",
                    dtm->columns(), dtm->rows(), st.cell_m * units.horizontal_m, dtm->crsLine().c_str());
}

// One line on stderr when SMRF's raster is far sparser than the points: its time then goes
// to the empty cells (docs/ground.md, "Sparse surveys"), and the user can choose a coarser
// cell. Tiles are left out: their rasters are sized to the memory, not the survey.
void noteSparseRaster(const sim::GroundFileOptions& o, const sim::GroundFileStats& st,
                      const sim::CoordinateUnits& units) {
    if (o.method != sim::GroundMethod::Smrf || st.points == 0 || st.nx <= 0 || st.ny <= 0) return;
    const std::uint64_t cells = std::uint64_t(st.nx) * std::uint64_t(st.ny);
    if (cells < kSparseRasterCells || cells < kSparseCellsPerPoint * std::uint64_t(st.points)) return;
    std::fprintf(stderr,
                 "ground: %zu points over %llu cells of %g m, one point per %.0f cells: most of the run fills "
                 "empty cells; a coarser --smrf-cell-m is faster on so sparse a survey (docs/ground.md, \"Sparse "
                 "surveys\")\n",
                 st.points, static_cast<unsigned long long>(cells), st.cell_m * units.horizontal_m,
                 double(cells) / double(st.points));
}

// `ground IN... --out OUT`: one run, or tiles where one raster does not fit or several
// inputs are merged.
void runOne(GroundFileCli& cli, const sim::CoordinateUnits& units, const sim::GroundFileOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<platform::RunPath> paths;
    for (const std::string& in : cli.in) paths.push_back({"input", in, platform::PathRole::Input, {}});
    paths.push_back({"--out", cli.out, platform::PathRole::Output, {}});
    if (!cli.dtm.empty()) {
        paths.push_back({"--dtm", cli.dtm, platform::PathRole::Output, {}});
        if (const auto prj = prjFor(cli.dtm))
            paths.push_back({"--dtm's CRS", prj->string(), platform::PathRole::Output, {}});
    }
    platform::checkDistinctPaths("ground", paths);
    platform::InputSet inputs;
    std::vector<std::filesystem::path> files;
    for (const std::string& in : cli.in) {
        platform::checkInputFile(in, "ground: input " + core::printable(in, 400));
        inputs.addFile(in);
        files.emplace_back(in);
    }
    addTileFolders(inputs, cli.in_folders);
    const std::filesystem::path out = cli.out;
    const io::CloudFormat format = io::formatForPath(out, "ground: --out");
    std::size_t side = 0, declared = 0;
    glm::dvec3 origin{0.0};
    for (const std::string& in : cli.in) {
        side = std::max(side, sideBytes(in, format));  // the header checked before the output is touched
        const io::CloudReader reader(in);
        declared += reader.declaredPoints();
        if (&in == &cli.in.front()) origin = reader.origin();
    }
    if (cli.in.size() > 1) sim::checkMergeable(files);
    const MemoryPlan one = planMemory(cli, format, side, 1);
    const double buffer = sim::tileBuffer(o);
    // The first input's frame on the cell lattice: the raster's, the tiles' and the grid's.
    const glm::dvec3 frame = sim::groundFrame(origin, o);
    bool tiled = cli.in.size() > 1 || cli.tile_m > 0;
    std::uint64_t cells = 0;
    if (!tiled) {
        cells = cellsOver(groundBox(files[0]), frame, filterCell(o));
        tiled = cells > std::min(one.max_cells, filterMaxCells(o));
    }
    createParentFolders(out, "ground: --out");
    platform::checkWritableDestination(out, inputs);
    // --dtm: the terrain's cells gathered on the run's cell lattice, the first input's CRS.
    std::optional<DtmOutput> dtm;
    sim::DtmMosaic* terrain = nullptr;
    if (!cli.dtm.empty() && files.size() > 1) {
        // One grid spans the box around every input: refused where most of it would lie
        // over no input (inputs far apart), before any work.
        sim::GroundBox all{glm::dvec2(1e300), glm::dvec2(-1e300)};
        std::uint64_t covered = 0;
        for (const auto& f : files) {
            const sim::GroundBox b = groundBox(f);
            covered += cellsOver(b, frame, filterCell(o));
            all.min = glm::min(all.min, b.min);
            all.max = glm::max(all.max, b.max);
        }
        const std::uint64_t spanned = cellsOver(all, frame, filterCell(o));
        if (spanned > kDtmSpread * covered + kDtmSpreadCells)
            throw core::Error("ground: --dtm: the inputs lie far apart: one grid over them would hold " +
                              std::to_string(spanned) + " cells, their bounds " + std::to_string(covered) +
                              "; allowed inputs of one survey, or --out-dir with --dtm-dir (a grid per input)");
    }
    if (!cli.dtm.empty()) {
        dtm.emplace(cli.dtm, files[0], tiffKind(cli));
        dtm->prepare(inputs, "ground: --dtm");
        terrain = &dtm->start(filterCell(o), frame);
    }
    sim::GroundFileStats st;
    if (!tiled) {
        MemoryPlan run = one;
        io::LasOptions las;
        las.threads = writerThreads(run, format, side, cells);
        las.memory_bytes = std::uint64_t(las.threads + 2) * io::lazChunkBytes();
        platform::Progress progress(o.whiten ? "ground: reading three times" : "ground: reading twice",
                                    (o.whiten ? 3 : 2) * declared);
        st = sim::classifyGroundFile(
            files[0], out, o, run.max_cells, las, run.copc, [&](std::size_t n) { progress.advance(n); }, cli.threads,
            terrain);
        progress.finish();
    } else {
        // The tiles' rasters share the memory among --jobs; the reading and writing passes
        // run alone.
        // At most one thickness sample (8 bytes) per 16 points: a cell's sample needs 16.
        const MemoryPlan jobs = planMemory(cli, format, side, cli.jobs, declared / 16 * sizeof(double));
        sim::GroundTiling t;
        t.buffer_m = buffer;
        t.tile_m = tileSide(cli, o, units, jobs.max_cells, buffer);
        t.jobs = cli.jobs;
        t.threads = cli.threads;
        t.max_cells = jobs.max_cells;
        t.scratch_dir = out.parent_path().empty() ? std::filesystem::path(".") : out.parent_path();
        t.dtm = terrain;
        platform::Progress progress("ground: tiles (spill, thickness, fit, write)", 4 * declared);
        st = sim::classifyGroundTiled(files, out, o, t, {}, one.copc, [&](std::size_t n) { progress.advance(n); });
        progress.finish();
    }
    if (dtm) dtm->commit();
    if (!st.reader_warning.empty()) platform::printMessage("warning", st.reader_warning);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    printStats(cli, cli.in.front(), cli.out, st, units, tiled, seconds, nullptr, dtm ? &*dtm : nullptr);
    if (!tiled) noteSparseRaster(o, st, units);
}

// What `ground IN... --out-dir DIR` reads and writes: each input, its output under its
// name, with --dtm-dir its grid (.asc and its CRS's .prj, or .tif).
struct EachPaths {
    std::vector<std::filesystem::path> files, outs, grids;
};

EachPaths eachPaths(const GroundFileCli& cli) {
    EachPaths e;
    for (const std::string& in : cli.in) {
        e.files.emplace_back(in);
        e.outs.push_back(std::filesystem::path(cli.out_dir) / std::filesystem::path(in).filename());
    }
    if (!cli.dtm_dir.empty())
        for (const auto& f : e.files)
            e.grids.push_back(std::filesystem::path(cli.dtm_dir) /
                              f.filename().replace_extension("." + cli.dtm_format));
    return e;
}

// Refuses in one line (platform::checkDistinctPaths) a run where two of the inputs,
// outputs and grids of all its surveys name one file.
void checkEachPaths(const GroundFileCli& cli) {
    const EachPaths e = eachPaths(cli);
    std::vector<platform::RunPath> paths;
    for (const std::string& in : cli.in) paths.push_back({"input", in, platform::PathRole::Input, {}});
    for (const auto& p : e.outs) paths.push_back({"--out-dir", p, platform::PathRole::Output, {}});
    for (const auto& g : e.grids) {
        paths.push_back({"--dtm-dir", g.string(), platform::PathRole::Output, {}});
        if (const auto prj = prjFor(g)) paths.push_back({"--dtm-dir", prj->string(), platform::PathRole::Output, {}});
    }
    platform::checkDistinctPaths("ground", paths);
}

// One survey of `ground IN... --out-dir DIR` (inputs of one CRS and unit): each input a
// tile of its own, its neighbours its buffer; its outputs' --json objects go to `array`.
void runEach(GroundFileCli& cli, const sim::CoordinateUnits& units, const sim::GroundFileOptions& o,
             nlohmann::json& array) {
    const EachPaths each = eachPaths(cli);
    const std::vector<std::filesystem::path>& files = each.files;
    const std::vector<std::filesystem::path>& outs = each.outs;
    const std::vector<std::filesystem::path>& grids = each.grids;
    platform::InputSet inputs;
    for (const std::string& in : cli.in) {
        platform::checkInputFile(in, "ground: input " + core::printable(in, 400));
        inputs.addFile(in);
    }
    addTileFolders(inputs, cli.in_folders);
    std::vector<std::size_t> todo;
    for (std::size_t i = 0; i < files.size(); ++i)
        if (cli.only_tile < 0 || std::size_t(cli.only_tile) == i) todo.push_back(i);
    std::size_t side = 0, declared = 0, all = 0;
    std::vector<sim::GroundBox> boxes;
    for (std::size_t i = 0; i < files.size(); ++i) {
        const io::CloudFormat format = io::formatForPath(outs[i], "ground: --out-dir");
        side = std::max(side, sideBytes(cli.in[i], format));
        boxes.push_back(groundBox(files[i]));
        const std::size_t n = io::CloudReader(files[i]).declaredPoints();
        all += n;
        if (std::find(todo.begin(), todo.end(), i) != todo.end()) declared += n;
    }
    const int jobs = std::max(1, std::min<int>(cli.jobs, int(todo.size())));
    const io::CloudFormat first_format = io::formatForPath(outs[todo.empty() ? 0 : todo[0]], "ground: --out-dir");
    const MemoryPlan plan = planMemory(cli, first_format, side, jobs, all / 16 * sizeof(double));
    createParentFolders(outs[0], "ground: --out-dir");
    for (std::size_t i : todo) platform::checkWritableDestination(outs[i], inputs);
    // Each input's grid on the first input's cell lattice, over the input's own box.
    std::vector<std::unique_ptr<DtmOutput>> dtms(files.size());
    if (!grids.empty()) {
        const glm::dvec3 frame = sim::groundFrame(io::CloudReader(files[0]).origin(), o);
        for (std::size_t i : todo) {
            dtms[i] = std::make_unique<DtmOutput>(grids[i], files[i], tiffKind(cli));
            dtms[i]->prepare(inputs, "ground: --dtm-dir");
            dtms[i]->start(filterCell(o), frame);
        }
    }

    sim::GroundTiling t;
    t.buffer_m = sim::tileBuffer(o);
    t.threads = cli.threads;
    t.max_cells = plan.max_cells;
    t.jobs = jobs;
    platform::Progress progress("ground: the survey's ground thickness, then each tile",
                                all + (o.whiten ? 3 : 2) * declared);
    std::mutex mutex;
    // One thickness for every tile, as one run over the whole survey measures it.
    t.thickness_m = sim::surveyThickness(files, boxes, o, t, [&](std::size_t n) { progress.advance(n); });
    std::vector<sim::GroundFileStats> stats(files.size());
    std::vector<double> seconds(files.size(), 0.0);
    platform::runJobs(todo.size(), jobs, [&](std::size_t k) {
        const std::size_t i = todo[k];
        const auto t0 = std::chrono::steady_clock::now();
        stats[i] = sim::classifyGroundNeighbours(
            files, boxes, i, outs[i], o, t, {}, plan.copc,
            [&](std::size_t n) {
                const std::lock_guard lock(mutex);
                progress.advance(n);
            },
            dtms[i] ? dtms[i]->mosaic() : nullptr);
        if (dtms[i]) dtms[i]->commit();
        seconds[i] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    });
    progress.finish();
    for (std::size_t i : todo) {
        if (!stats[i].reader_warning.empty()) platform::printMessage("warning", stats[i].reader_warning);
        printStats(cli, cli.in[i], outs[i].string(), stats[i], units, false, seconds[i], &array, dtms[i].get());
    }
}

// Says that the options given in metres were converted to a survey's units; `survey`
// names its first input when the run holds several surveys.
void noteUnits(const sim::CoordinateUnits& units, const std::string& survey) {
    if (units.metres()) return;
    if (survey.empty())
        std::fprintf(stderr, "ground: coordinates in %s: options converted\n", sim::describe(units).c_str());
    else
        std::fprintf(stderr, "ground: %s and the inputs in its CRS: coordinates in %s: options converted\n",
                     core::printable(survey, 400).c_str(), sim::describe(units).c_str());
}

// `ground IN... --out-dir DIR`: the inputs split into surveys of one CRS and unit (a
// folder of downloads may mix them), each run as tiles of one another.
void runSurveys(GroundFileCli& cli) {
    std::set<std::string> names;
    std::vector<std::filesystem::path> files;
    for (const std::string& in : cli.in) {
        const std::string name = std::filesystem::path(in).filename().string();
        if (!names.insert(name).second)
            throw core::Error("ground: --out-dir: two inputs are named '" + core::printable(name, 400) +
                              "'; allowed inputs of distinct names (each output takes its input's name)");
        files.emplace_back(in);
    }
    if (cli.only_tile >= int(cli.in.size()))
        throw core::Error("ground: --only-tile " + std::to_string(cli.only_tile) + ": allowed [0, " +
                          std::to_string(cli.in.size() - 1) + "] (an index into the " + std::to_string(cli.in.size()) +
                          " inputs)");
    checkEachPaths(cli);  // no output of one survey may name an input or output of another
    const std::vector<std::vector<std::size_t>> surveys =
        files.size() > 1 ? sim::surveysOf(files) : std::vector<std::vector<std::size_t>>{{0}};
    nlohmann::json array = nlohmann::json::array();
    for (const std::vector<std::size_t>& survey : surveys) {
        GroundFileCli one = cli;
        one.in.clear();
        one.only_tile = -1;
        for (std::size_t k = 0; k < survey.size(); ++k) {
            one.in.push_back(cli.in[survey[k]]);
            if (int(survey[k]) == cli.only_tile) one.only_tile = int(k);
        }
        if (cli.only_tile >= 0 && one.only_tile < 0) continue;
        const sim::CoordinateUnits units = sim::readCoordinateUnits(one.in.front(), "ground");
        noteUnits(units, surveys.size() > 1 ? one.in.front() : std::string());
        runEach(one, units, sim::inUnits(cli.options, units), array);
    }
    if (cli.json) std::printf("%s\n", array.dump(2).c_str());
}

void run(GroundFileCli& cli) {
    // A name without an extension would be a PCD (io::formatForPath): a survey's CRS and classes lost.
    if (!cli.out.empty() && std::filesystem::path(cli.out).extension().empty())
        throw core::Error("ground: --out " + core::printable(cli.out, 400) +
                          ": no extension; allowed a name ending in .las, .laz, .copc.laz, .pcd or .ply (the name "
                          "gives the format)");
    cli.in_folders = folderInputs(cli.in);
    expandFolderInputs(cli.in, "ground", kMostInputs);
    cli.options.method = sim::parseGroundMethod(cli.method, "ground: --method");
    if (cli.options.method == sim::GroundMethod::Ransac)
        throw core::Error("ground: --method ransac: RANSAC works per view of a generated cloud; allowed smrf, csf");
    cli.options.returns = sim::parseGroundReturns(cli.returns, "ground: --returns");
    cli.options.smrf.low_outlier_m = cli.options.csf.low_outlier_m = cli.low_outlier_m;
    sim::validate(cli.options);
    if (cli.jobs < 1 || cli.jobs > 256)
        throw core::Error("ground: --jobs " + std::to_string(cli.jobs) + ": allowed [1, 256]");
    if (cli.threads < 0 || cli.threads > 1024)
        throw core::Error("ground: --threads " + std::to_string(cli.threads) +
                          ": allowed [0, 1024], 0 = the cores divided by --jobs");
    if (cli.threads == 0) cli.threads = std::max(1, int(std::max(1u, std::thread::hardware_concurrency())) / cli.jobs);
    if (!(cli.tile_m >= 0) || cli.tile_m > 1e6)
        throw core::Error("ground: --tile-m " + std::to_string(cli.tile_m) +
                          ": allowed [0, 1000000] metres, 0 = tiles only where needed");
    if (!cli.dtm.empty()) {
        if (!cli.out_dir.empty())
            throw core::Error(
                "ground: --dtm: allowed with --out (one DTM of every input); with --out-dir, --dtm-dir "
                "DIR writes one per input");
        checkDtmName(cli.dtm, "ground");
    }
    if (cli.dtm_tiff != "auto" && !(isGeoTiffName(cli.dtm) || (!cli.dtm_dir.empty() && cli.dtm_format == "tif")))
        throw core::Error("ground: --dtm-tiff " + cli.dtm_tiff +
                          ": allowed only with a GeoTIFF grid (--dtm NAME.tif, or --dtm-dir with --dtm-format tif)");
    if (cli.only_tile >= 0 && cli.out_dir.empty())
        throw core::Error("ground: --only-tile: allowed only with --out-dir (it names the input written there)");
    sim::memoryBudgetBytes(cli.memory_mb, "ground");
    for (const std::string& in : cli.in) platform::checkInputFile(in, "ground: input " + core::printable(in, 400));
    if (!cli.out_dir.empty()) return runSurveys(cli);
    // Options in metres to the file's units (the inputs share them, as checked later).
    const sim::CoordinateUnits units = sim::readCoordinateUnits(cli.in.front(), "ground");
    noteUnits(units, {});
    runOne(cli, units, sim::inUnits(cli.options, units));
}

}  // namespace

void registerGround(CLI::App& cli) {
    auto state = std::make_shared<GroundFileCli>();
    CLI::App* c = cli.add_subcommand(
        "ground",
        "classify the ground of clouds (real surveys' LAS/LAZ, or PCD, PLY, COPC) with a whole-cloud filter "
        "and write them with every point labelled ground (LAS class 2) or not (class 1)");
    c->add_option("in", state->in,
                  "the input clouds (a survey's tiles; a folder gives its .las/.laz files in name order); they are "
                  "never overwritten")
        ->required();
    CLI::Option_group* dest = c->add_option_group("output", "where the classified points go (one of)");
    dest->add_option("--out", state->out,
                     "the one cloud to write, every input merged; its name gives the format (.las, .laz, "
                     ".copc.laz, .pcd, .ply)");
    CLI::Option* out_dir = dest->add_option(
        "--out-dir", state->out_dir,
        "write one cloud per input into this folder, under the input's name; each input is classified with the "
        "inputs around it as its buffer");
    dest->require_option(1);
    c->add_option("--method", state->method,
                  "smrf (Pingel et al. 2013, the default: the best on the ISPRS samples with one parameter set) or "
                  "csf (Zhang et al. 2016)")
        ->capture_default_str();
    addSmrfOptions(*c, state->options.smrf);
    addCsfOptions(*c, state->options.csf);
    c->add_option("--low-outlier-m", state->low_outlier_m,
                  "a return this far below the ground around it (multipath, noise) is left out of the terrain and is "
                  "not ground, metres [0, 1000], 0 = keep every return")
        ->capture_default_str();
    c->add_option("--returns", state->returns,
                  "which returns may be ground: last (a return with a later one behind it is never ground), all, "
                  "or auto (last where the input is a discrete-return survey: some pulses with one return and some "
                  "with several; all where it holds no single returns, as files storing each pulse's first and last "
                  "echo as two full sets)")
        ->capture_default_str();
    c->add_option("--memory-mb", state->memory_mb,
                  "bound on memory: the terrain rasters, the points and side records in flight")
        ->capture_default_str();
    c->add_flag("--reclassify", state->options.reclassify,
                "a LAS/LAZ/COPC input's points that are not ground all become class 1 (by default its classes other "
                "than ground are kept)");
    c->add_flag("--noise", state->options.mark_noise,
                "a LAS/LAZ/COPC input's returns more than --low-outlier-m below the terrain (those the filter left "
                "out) become class 7, low point (noise)");
    c->add_flag("--whiten", state->options.whiten,
                "write the paper's colours as RGB: ground white, every other point by its height above the ground "
                "on the jet map (red low, blue at the highest)");
    c->add_option("--jobs", state->jobs, "tiles classified at once, [1, 256]; they share --memory-mb")
        ->capture_default_str();
    c->add_option("--threads", state->threads,
                  "threads of each tile's terrain fit, [0, 1024], 0 = the cores divided by --jobs")
        ->capture_default_str();
    c->add_option("--tile-m", state->tile_m,
                  "advanced: classify in square tiles this wide, metres (0: tiles only where one terrain raster "
                  "does not fit --memory-mb, sized to fit)")
        ->capture_default_str();
    c->add_option("--only-tile", state->only_tile,
                  "with --out-dir: classify and write only input I (0-based), the others read as its buffer: one "
                  "Slurm array task per input (scripts/slurm/ground.sbatch)")
        ->needs(out_dir);
    c->add_option("--dtm", state->dtm,
                  "with --out: also write the terrain the points were classified against (the DTM), a grid of the "
                  "filter's cells in the input's coordinates and units: an ESRI ASCII grid (.asc) with its CRS "
                  "beside it (.prj) when the input has one, or a GeoTIFF (.tif, .tiff) with its CRS in its keys; a "
                  "tiled run's tiles put together, -9999 where no tile held a point");
    auto* dtm_dir = c->add_option("--dtm-dir", state->dtm_dir,
                                  "with --out-dir: also write each input's terrain over its own bounds into this "
                                  "folder, under the input's name with --dtm-format's extension, as --dtm does")
                        ->needs(out_dir);
    c->add_option("--dtm-format", state->dtm_format,
                  "--dtm-dir's grids: asc (ESRI ASCII grid and .prj) or tif (GeoTIFF)")
        ->check(CLI::IsMember({"asc", "tif"}))
        ->needs(dtm_dir)
        ->capture_default_str();
    c->add_option("--dtm-tiff", state->dtm_tiff,
                  "a GeoTIFF grid as a classic TIFF (read by every TIFF reader, at most 4 GiB: a grid that might "
                  "pass it is refused), a BigTIFF (64-bit offsets, no such bound; GDAL, QGIS and libtiff 4 read "
                  "it), or auto: classic unless the grid might pass 4 GiB")
        ->check(CLI::IsMember({"auto", "classic", "bigtiff"}))
        ->capture_default_str();
    c->add_flag("--json", state->json, "print the run's figures as JSON on stdout");
    c->callback([state] { run(*state); });
}

}  // namespace app
