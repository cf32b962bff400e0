// sim/src/ground_file.cpp: see sim/ground_file.hpp. The file is read twice through
// io::CloudReader: pass 1 gives every point to the filter's TerrainFit, which keeps only
// per-cell lowest heights, pass 2 labels each chunk and appends it to the writer.
#include "ground_label.hpp"
#include "ground_raster.hpp"

#include <sim/ground_file.hpp>

#include <core/error.hpp>
#include <core/jet.hpp>
#include <io/cloud_reader.hpp>
#include <io/copc.hpp>
#include <sim/colour.hpp>
#include <sim/dtm.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <mutex>
#include <sstream>
#include <thread>

namespace sim {

SmrfOptions surveySmrfOptions() {
    SmrfOptions o;
    o.low_outlier_m = kSurveyLowOutlier_m;
    o.raised_segments = true;
    o.sparse_openings = true;
    o.fill_sweeps = kSurveyFillSweeps;
    return o;
}

CsfOptions surveyCsfOptions() {
    CsfOptions o;
    o.low_outlier_m = kSurveyLowOutlier_m;
    return o;
}

GroundReturns parseGroundReturns(const std::string& name, const std::string& what) {
    if (name == "auto") return GroundReturns::Auto;
    if (name == "last") return GroundReturns::Last;
    if (name == "all") return GroundReturns::All;
    throw core::Error(what + " " + core::printable(name, 40) + ": allowed auto, last, all");
}

void ReturnCounts::add(std::span<const core::CloudPoint> points) {
    for (const core::CloudPoint& p : points) {
        single += p.returns == 1;
        not_last += notLastReturn(p);
    }
}

bool lastReturnsOnly(const GroundFileOptions& o, const ReturnCounts& counts) {
    return o.returns == GroundReturns::Last || (o.returns == GroundReturns::Auto && counts.discrete());
}

void validate(const GroundFileOptions& o) {
    if (o.method == GroundMethod::Ransac)
        throw core::Error("ground: method ransac works per view of a generated cloud; allowed smrf, csf");
    validate(o.smrf);
    validate(o.csf);
}

namespace {
std::string lowOutliers(double gap_m) {
    std::ostringstream s;
    if (gap_m > 0)
        s << gap_m << " m below";
    else
        s << "kept";
    return s.str();
}
}  // namespace

std::string describe(const GroundFileOptions& o) {
    std::ostringstream s;
    if (o.method == GroundMethod::Csf) {
        const CsfOptions& c = o.csf;
        s << "csf (cloth " << c.cloth_m << " m, rigidness " << c.rigidness << ", threshold " << c.threshold_m
          << " m, time step " << c.time_step << ", iterations " << c.iterations << ", low outliers "
          << lowOutliers(c.low_outlier_m) << ")";
    } else {
        const SmrfOptions& m = o.smrf;
        s << "smrf (cell " << m.cell_m << " m, slope " << m.slope << ", window " << m.window_m << " m, threshold "
          << m.threshold_m << " m, scalar " << m.scalar << ", low outliers " << lowOutliers(m.low_outlier_m)
          << (m.raised_segments ? ", raised segments" : "") << (m.sparse_openings ? ", sparse openings" : "") << ")";
    }
    return s.str();
}

double groundCell(const GroundFileOptions& o) { return o.method == GroundMethod::Csf ? o.csf.cloth_m : o.smrf.cell_m; }

glm::dvec3 groundFrame(const glm::dvec3& origin, const GroundFileOptions& o) {
    const double cell = groundCell(o);
    return {std::floor(origin.x / cell) * cell, std::floor(origin.y / cell) * cell, origin.z};
}

std::unique_ptr<TerrainFit> startFit(const GroundFileOptions& o, std::size_t max_cells) {
    if (o.method == GroundMethod::Csf) {
        CsfOptions c = o.csf;
        c.max_cells = std::min(c.max_cells, max_cells);
        return startCsf(c);
    }
    SmrfOptions m = o.smrf;
    m.max_cells = std::min(m.max_cells, max_cells);
    return startSmrf(m);
}

std::vector<std::uint8_t> classifyGround(std::span<const core::CloudPoint> points, const GroundFileOptions& o) {
    const std::unique_ptr<TerrainFit> fit = startFit(o, std::size_t(-1));
    fit->add(points);
    fit->fit();
    ReturnCounts counts;
    counts.add(points);
    const bool last_only = lastReturnsOnly(o, counts);
    std::vector<std::uint8_t> ground(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        float height_m = 0;
        ground[i] = fit->classify(points[i], height_m) && !(last_only && notLastReturn(points[i]));
    }
    return ground;
}

// ASPRS class 7: low point (noise).
constexpr std::uint8_t kLowNoiseClass = 7;

GroundLabeller::GroundLabeller(const GroundFileOptions& o, std::size_t stride, float colour_top_m, bool last_only)
    : o_(o), stride_(stride), top_m_(colour_top_m), last_only_(last_only) {
    if (o.whiten) jet_ = core::jetTable(ColourOptions{}.entries);
}

void GroundLabeller::apply(core::CloudPoint& p, unsigned char* record, bool ground, float height_m,
                           GroundFileStats& st) const {
    if (ground && last_only_ && notLastReturn(p)) {
        ground = false;
        ++st.not_last_points;
    }
    const bool was_ground = p.label == core::Role::Ground;
    p.height_above_ground_m = height_m;
    core::ForeignPoint f;
    if (stride_ > 0) {
        // The file's own class: ground 2, its ground that is not ground 1, the rest kept.
        std::memcpy(&f, record, sizeof f);
        f.classification = ground                                   ? std::uint8_t(2)
                           : f.classification == 2 || o_.reclassify ? std::uint8_t(1)
                                                                    : f.classification;
        if (o_.mark_noise && !ground) {
            const double gap = o_.method == GroundMethod::Csf ? o_.csf.low_outlier_m : o_.smrf.low_outlier_m;
            if (gap > 0.0 && double(height_m) < -gap) {
                f.classification = kLowNoiseClass;
                ++st.noise_points;
            }
        }
        if (ground)
            p.label = core::Role::Ground;
        else if (p.label == core::Role::Ground || o_.reclassify)
            p.label = core::Role::Environment;
    } else if (p.label != core::Role::Target) {
        p.label = ground ? core::Role::Ground : core::Role::Environment;
    }
    const bool is_ground = p.label == core::Role::Ground;
    if (o_.whiten) {
        // The generator's colours: white ground, the rest by height on the jet map.
        p.rgb = is_ground ? core::kWhite : heightColour(std::max(height_m, 0.0f), 0.0f, top_m_, jet_);
        f.rgb[0] = std::uint16_t(((p.rgb >> 16) & 0xFFu) * 257u);
        f.rgb[1] = std::uint16_t(((p.rgb >> 8) & 0xFFu) * 257u);
        f.rgb[2] = std::uint16_t((p.rgb & 0xFFu) * 257u);
    }
    if (stride_ > 0) std::memcpy(record, &f, sizeof f);
    st.was_ground += was_ground;
    st.still_ground += was_ground && is_ground;
    st.ground_points += is_ground;
}

namespace {

bool zeroShift(const glm::dvec3& shift) { return shift.x == 0.0 && shift.y == 0.0 && shift.z == 0.0; }

void moveBy(std::vector<core::CloudPoint>& chunk, const glm::dvec3& shift) {
    if (zeroShift(shift)) return;
    for (core::CloudPoint& p : chunk) p.position = glm::vec3(glm::dvec3(p.position) + shift);
}

}  // namespace

void addSource(TerrainFit& fit, const FitSource& source, const std::function<void(std::size_t)>& progress) {
    io::CloudReader reader(source.file, io::PointFields::Positions);
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
        if (progress) progress(chunk.size());
        moveBy(chunk, source.shift);
        std::erase_if(chunk, [&](const core::CloudPoint& p) {
            return p.position.x < source.min.x || p.position.x > source.max.x || p.position.y < source.min.y ||
                   p.position.y > source.max.y;
        });
        fit.add(chunk);
    });
}

namespace {

// Pass 1's points of a COPC file, its nodes (each a LAZ chunk of its own) decoded two at
// a time, each in its own decoding process: the fit keeps per-cell lowest heights, the
// same whatever the order its points come in. Two nodes in flight hold no more than the
// reader's two chunks. False, having added nothing, where `in` is not COPC, its nodes do
// not hold all its points, or a node is larger than a reader's chunk.
bool fitCopcNodes(TerrainFit& fit, const std::filesystem::path& in, const glm::dvec3& shift,
                  const std::function<void(std::size_t)>& progress, ReturnCounts& counts) {
    if (!io::isCopcFile(in)) return false;
    std::unique_ptr<io::CopcReader> copc;
    try {
        copc = std::make_unique<io::CopcReader>(in);
    } catch (const core::Error&) {
        return false;  // the LAS reader reads it in order, or says what is wrong
    }
    const std::vector<io::CopcNode>& nodes = copc->nodes();
    std::uint64_t points = 0;
    for (const io::CopcNode& node : nodes) {
        if (std::size_t(node.point_count) > io::CloudReader::kChunkPoints) return false;
        points += std::uint64_t(node.point_count);
    }
    if (points != copc->pointCount()) return false;
    std::mutex mutex;
    std::atomic<std::size_t> next{0};
    std::exception_ptr error;
    const auto work = [&] {
        try {
            for (std::size_t i = next++; i < nodes.size(); i = next++) {
                core::PointCloud cloud =
                    copc->readNodeEntry(nodes[i], io::SideRecords::Drop, io::PointFields::Positions);
                moveBy(cloud.points, shift);
                ReturnCounts mine;
                mine.add(cloud.points);
                const std::lock_guard lock(mutex);
                counts.add(mine);
                fit.add(cloud.points);
                progress(cloud.points.size());
            }
        } catch (...) {
            const std::lock_guard lock(mutex);
            if (!error) error = std::current_exception();
            next = nodes.size();
        }
    };
    std::thread other(work);
    work();
    other.join();
    if (error) std::rethrow_exception(error);
    return true;
}

// Pass 1: the terrain fitted on `in`'s points and `extra`'s within their boxes; `in`'s
// points counted by their returns into `counts`.
void fitOn(std::unique_ptr<TerrainFit>& fit, const std::filesystem::path& in, const glm::dvec3& shift,
           const std::vector<FitSource>& extra, int threads, double thickness_m,
           const std::function<void(std::size_t)>& progress, const FitOver& fit_over, ReturnCounts& counts) {
    if (!fitCopcNodes(*fit, in, shift, progress, counts)) {
        io::CloudReader reader(in, io::PointFields::Positions);
        io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
            counts.add(chunk);
            moveBy(chunk, shift);
            fit->add(chunk);
            progress(chunk.size());
        });
    }
    for (const FitSource& source : extra) addSource(*fit, source);
    fit->setFitThreads(threads);
    if (thickness_m >= 0) fit->setGroundThickness(thickness_m);
    if (fit_over)
        fit_over(fit);
    else
        fit->fit();
}

// The top of the jet map: the highest point above the terrain that is not ground, a few
// stray returns far above the rest left out (core::HeightSpan over every point's height,
// so that the strays may be a thousandth of the survey, not of its objects).
float colourTop(const TerrainFit& fit, const std::filesystem::path& in, const glm::dvec3& shift,
                const GroundFileOptions& o, const std::function<void(std::size_t)>& progress) {
    float top_m = 0;
    core::HeightSpan heights = aboveGroundHeights(o);
    io::CloudReader reader(in, io::PointFields::Positions);
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
        for (core::CloudPoint p : chunk) {
            if (!zeroShift(shift)) p.position = glm::vec3(glm::dvec3(p.position) + shift);
            float height_m = 0;
            if (!fit.classify(p, height_m)) top_m = std::max(top_m, height_m);
            heights.add(height_m);
        }
        progress(chunk.size());
    });
    return core::topWithoutStrays(heights.span(), top_m);
}

}  // namespace

GroundFileStats classifyOneFile(const std::filesystem::path& in, const glm::dvec3& shift,
                                const std::vector<FitSource>& extra, const std::filesystem::path& out,
                                const GroundFileOptions& o, std::size_t max_cells, int threads, double thickness_m,
                                const io::LasOptions& las, const io::CopcOptions& copc,
                                const std::function<void(std::size_t)>& progress, const FitOver& fit_over,
                                DtmMosaic* dtm, const glm::dvec2& dtm_lo, const glm::dvec2& dtm_hi) {
    GroundFileStats st;
    std::unique_ptr<TerrainFit> fit = startFit(o, max_cells);
    ReturnCounts counts;
    fitOn(fit, in, shift, extra, threads, thickness_m, progress, fit_over, counts);
    // [lo, hi] as add()'s half-open box: a cell whose centre lies on hi is kept too.
    if (dtm) dtm->add(fit->surface(), dtm_lo, dtm_hi + 1e-6 * fit->surface().cell_m);
    st.nx = fit->surface().nx;
    st.ny = fit->surface().ny;
    st.cell_m = fit->surface().cell_m;
    if (o.whiten) st.colour_top_m = colourTop(*fit, in, shift, o, progress);

    const io::CloudFormat format = io::formatForPath(out, "ground: --out");
    const bool las_out =
        format == io::CloudFormat::Las || format == io::CloudFormat::Laz || format == io::CloudFormat::Copc;
    io::CloudReader reader(in, las_out ? io::SideRecords::Keep : io::SideRecords::Drop);
    core::CloudFields fields = reader.fields();
    fields.label = true;
    fields.height_above_ground = true;
    if (o.whiten) fields.rgb = true;
    io::LasOptions with = las;
    with.foreign = reader.foreignHeader();
    io::CloudWriter writer(out, format, reader.origin(), fields, with,
                           format == io::CloudFormat::Copc ? &copc : nullptr);
    const std::size_t stride = with.foreign ? with.foreign->stride() : 0;
    st.last_returns_only = lastReturnsOnly(o, counts);
    const GroundLabeller labeller(o, stride, st.colour_top_m, st.last_returns_only);
    const bool moved = !zeroShift(shift);
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk, std::vector<unsigned char>& records) {
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            core::CloudPoint& p = chunk[i];
            float height_m = 0;
            bool ground = false;
            if (moved) {
                core::CloudPoint q = p;
                q.position = glm::vec3(glm::dvec3(p.position) + shift);
                ground = fit->classify(q, height_m);
            } else {
                ground = fit->classify(p, height_m);
            }
            labeller.apply(p, stride > 0 ? records.data() + i * stride : nullptr, ground, height_m, st);
        }
        st.points += chunk.size();
        writer.append(chunk, records);
        progress(chunk.size());
    });
    if (dtm) dtm->complete();
    writer.commit();
    st.reader_warning = reader.warning();
    if (with.foreign && !with.foreign->crs_problem.empty())
        st.reader_warning +=
            (st.reader_warning.empty() ? "" : "; ") + with.foreign->crs_problem + "; written without a CRS";
    return st;
}

GroundFileStats classifyGroundFile(const std::filesystem::path& in, const std::filesystem::path& out,
                                   const GroundFileOptions& o, std::size_t max_cells, const io::LasOptions& las,
                                   const io::CopcOptions& copc, const std::function<void(std::size_t)>& progress,
                                   int threads, DtmMosaic* dtm) {
    // The points moved from their reader's origin into the cell lattice's frame.
    const glm::dvec3 origin = io::CloudReader(in).origin();
    return classifyOneFile(in, origin - groundFrame(origin, o), {}, out, o, max_cells, std::max(1, threads), -1.0, las,
                           copc, progress, {}, dtm);
}

}  // namespace sim
