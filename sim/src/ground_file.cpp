// sim/src/ground_file.cpp: see sim/ground_file.hpp. The file is read twice through
// io::CloudReader: pass 1 gives every point to the filter's TerrainFit, which keeps only
// per-cell lowest heights, pass 2 labels each chunk and appends it to the writer.
#include "ground_raster.hpp"

#include <sim/ground_file.hpp>

#include <core/error.hpp>
#include <io/cloud_reader.hpp>

#include <cstring>
#include <sstream>

namespace sim {

SmrfOptions surveySmrfOptions() {
    SmrfOptions o;
    o.low_outlier_m = kSurveyLowOutlier_m;
    return o;
}

CsfOptions surveyCsfOptions() {
    CsfOptions o;
    o.low_outlier_m = kSurveyLowOutlier_m;
    return o;
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
          << m.threshold_m << " m, scalar " << m.scalar << ", low outliers " << lowOutliers(m.low_outlier_m) << ")";
    }
    return s.str();
}

namespace {

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

}  // namespace

std::vector<std::uint8_t> classifyGround(std::span<const core::CloudPoint> points, const GroundFileOptions& o) {
    const std::unique_ptr<TerrainFit> fit = startFit(o, std::size_t(-1));
    fit->add(points);
    fit->fit();
    std::vector<std::uint8_t> ground(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        float height_m = 0;
        ground[i] = fit->classify(points[i], height_m);
    }
    return ground;
}

GroundFileStats classifyGroundFile(const std::filesystem::path& in, const std::filesystem::path& out,
                                   const GroundFileOptions& o, std::size_t max_cells, const io::LasOptions& las,
                                   const io::CopcOptions& copc, const std::function<void(std::size_t)>& progress) {
    GroundFileStats st;
    const std::unique_ptr<TerrainFit> fit = startFit(o, max_cells);
    {
        io::CloudReader reader(in);
        io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk) {
            fit->add(chunk);
            progress(chunk.size());
        });
    }
    fit->fit();
    st.nx = fit->surface().nx;
    st.ny = fit->surface().ny;
    st.cell_m = fit->surface().cell_m;

    const io::CloudFormat format = io::formatForPath(out, "ground: --out");
    const bool las_out =
        format == io::CloudFormat::Las || format == io::CloudFormat::Laz || format == io::CloudFormat::Copc;
    io::CloudReader reader(in, las_out ? io::SideRecords::Keep : io::SideRecords::Drop);
    core::CloudFields fields = reader.fields();
    fields.label = true;
    fields.height_above_ground = true;
    io::LasOptions with = las;
    with.foreign = reader.foreignHeader();
    io::CloudWriter writer(out, format, reader.origin(), fields, with,
                           format == io::CloudFormat::Copc ? &copc : nullptr);
    const std::size_t stride = with.foreign ? with.foreign->stride() : 0;
    io::forEachChunk(reader, [&](std::vector<core::CloudPoint>& chunk, std::vector<unsigned char>& records) {
        for (std::size_t i = 0; i < chunk.size(); ++i) {
            core::CloudPoint& p = chunk[i];
            const bool was_ground = p.label == core::Role::Ground;
            float height_m = 0;
            const bool ground = fit->classify(p, height_m);
            p.height_above_ground_m = height_m;
            if (stride > 0) {
                // The file's own class: ground 2, its ground that is not ground 1, the rest kept.
                core::ForeignPoint f;
                unsigned char* at = records.data() + i * stride;
                std::memcpy(&f, at, sizeof f);
                f.classification = ground                                  ? std::uint8_t(2)
                                   : f.classification == 2 || o.reclassify ? std::uint8_t(1)
                                                                           : f.classification;
                std::memcpy(at, &f, sizeof f);
                if (ground)
                    p.label = core::Role::Ground;
                else if (p.label == core::Role::Ground || o.reclassify)
                    p.label = core::Role::Environment;
            } else if (p.label != core::Role::Target) {
                p.label = ground ? core::Role::Ground : core::Role::Environment;
            }
            const bool is_ground = p.label == core::Role::Ground;
            st.was_ground += was_ground;
            st.still_ground += was_ground && is_ground;
            st.ground_points += is_ground;
        }
        st.points += chunk.size();
        writer.append(chunk, records);
        progress(chunk.size());
    });
    writer.commit();
    st.reader_warning = reader.warning();
    if (with.foreign && !with.foreign->crs_problem.empty())
        st.reader_warning +=
            (st.reader_warning.empty() ? "" : "; ") + with.foreign->crs_problem + "; written without a CRS";
    return st;
}

}  // namespace sim
