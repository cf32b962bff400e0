// app/src/cloud_index.cpp: the indexing that `index` and `view` share (cloud_index.hpp).
#include "cloud_index.hpp"

#include "cli_common.hpp"

#include <core/error.hpp>
#include <io/cloud_reader.hpp>

#include <glm/vec3.hpp>

#include <cmath>
#include <string>

namespace app {

namespace {

// Inputs further than this from the first one's origin would lose the millimetre in the
// points' float coordinates relative to that origin.
constexpr double kMaxOriginShift_m = 10000.0;

std::string fieldList(const core::CloudFields& f) {
    std::string s;
    for (const std::string& name : core::fieldNames(f)) s += (s.empty() ? "" : " ") + name;
    return s;
}

bool sameFields(const core::CloudFields& a, const core::CloudFields& b) {
    return a.rgb == b.rgb && a.label == b.label && a.view == b.view && a.range == b.range &&
           a.intensity == b.intensity && a.returns == b.returns && a.incidence == b.incidence &&
           a.scan_angle == b.scan_angle && a.height_above_ground == b.height_above_ground;
}

// Whether two inputs' side records and CRS are alike (both null: clouds we generated, or
// formats without them, or readers that drop them).
bool sameForeignHeader(const core::ForeignHeader* a, const core::ForeignHeader* b) {
    if (!a || !b) return a == b;
    return a->nir == b->nir && a->extra_bytes == b->extra_bytes && a->extra_bytes_vlr == b->extra_bytes_vlr &&
           a->wkt == b->wkt;
}

// An input's layout in words, for the refusal of unlike inputs.
std::string foreignLayout(const io::CloudReader& r) {
    const auto h = r.foreignHeader();
    if (!h) return "no side records: generated, PCD or PLY";
    return "point format " + std::to_string(h->point_format) + ", " + std::to_string(h->extra_bytes) +
           " extra bytes, " +
           (h->wkt.empty() ? std::string("no CRS") : "WKT of " + std::to_string(h->wkt.size()) + " bytes");
}

}  // namespace

void checkMergeable(const io::CloudReader& r, const io::CloudReader& first, std::string_view command) {
    const std::string head = std::string(command) + ": ";
    if (!sameForeignHeader(r.foreignHeader().get(), first.foreignHeader().get()))
        throw core::Error(head + r.where() + ": its LAS point layout or CRS (" + foreignLayout(r) + ") differs from " +
                          first.where() + "'s (" + foreignLayout(first) + "); merged inputs must be alike");
    if (!sameFields(r.fields(), first.fields()))
        throw core::Error(head + r.where() + ": its fields (" + fieldList(r.fields()) + ") differ from " +
                          first.where() + "'s (" + fieldList(first.fields()) +
                          "); merged inputs must carry the same fields");
    const glm::dvec3 shift = r.origin() - first.origin();
    if (!(std::fabs(shift.x) <= kMaxOriginShift_m && std::fabs(shift.y) <= kMaxOriginShift_m &&
          std::fabs(shift.z) <= kMaxOriginShift_m))
        throw core::Error(head + r.where() + ": its origin lies more than 10 km from " + first.where() +
                          "'s; merged inputs must lie within 10 km of each other");
}

IndexPlan planIndex(std::uint64_t budget_bytes, double memory_mb, int threads, std::string_view command,
                    bool fewer_threads, std::uint32_t max_node_points, std::size_t side_record_bytes) {
    // Plan-or-refuse: the reader's two chunks (one read while the other is written), and
    // the writer within the rest (past it, it spills the points to scratch files and
    // builds the octree a part at a time).
    const std::uint64_t reading = 2 * io::CloudReader::kChunkPoints * (sizeof(core::CloudPoint) + side_record_bytes);
    // The COPC writer gives a foreign file's side records their share of its bound (as many
    // bytes per point as the points' own share), so its minimum grows by as much.
    const std::uint64_t per_point = io::copcBytesPerPoint();
    const auto least = [&](int t) {
        return io::copcMinimumBytes(t - 1, max_node_points) * (per_point + side_record_bytes) / per_point + reading;
    };
    if (fewer_threads)
        while (threads > 1 && budget_bytes < least(threads)) --threads;
    if (budget_bytes < least(threads))
        throw core::Error(std::string(command) + ": --memory-mb " + core::shownNumber(memory_mb) + " is below the " +
                          std::to_string((least(threads) >> 20) + 1) + " MiB indexing needs with " +
                          std::to_string(threads) + (threads == 1 ? " thread" : " threads") +
                          (fewer_threads ? "; raise --memory-mb" : "; raise --memory-mb or lower --threads"));
    IndexPlan plan;
    plan.copc.memory_bytes = budget_bytes - reading;
    plan.copc.max_node_points = max_node_points;
    plan.las.threads = threads - 1;
    plan.threads = threads;
    return plan;
}

std::size_t writeIndex(std::vector<std::unique_ptr<io::CloudReader>>& readers, const std::filesystem::path& out,
                       const IndexPlan& plan, const std::function<void(std::size_t)>& advance,
                       const std::function<void()>& read_done) {
    const glm::dvec3 origin = readers.front()->origin();
    // Readers that keep a foreign file's side records give them to the writer (the
    // caller checked that every input has the same header facts), at the finest scale.
    io::LasOptions las = plan.las;
    las.foreign = io::mergedForeignHeader(readers);
    if (las.foreign && !las.foreign->crs_problem.empty()) warn(las.foreign->crs_problem + "; written without a CRS");
    io::CloudWriter writer(out, io::CloudFormat::Copc, origin, readers.front()->fields(), las, &plan.copc);
    for (auto& reader : readers) {
        const glm::dvec3 shift = reader->origin() - origin;
        io::forEachChunk(*reader, [&](std::vector<core::CloudPoint>& chunk, std::vector<unsigned char>& records) {
            if (shift != glm::dvec3(0.0))
                for (core::CloudPoint& p : chunk) p.position = glm::vec3(glm::dvec3(p.position) + shift);
            writer.append(chunk, records);
            advance(chunk.size());
        });
        if (const std::string w = reader->warning(); !w.empty()) warn(w);
        reader.reset();
    }
    read_done();
    const std::size_t points = writer.count();
    writer.commit();
    return points;
}

}  // namespace app
