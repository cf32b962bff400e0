// app/src/cloud_index.cpp: the indexing that `index` and `view` share (cloud_index.hpp).
#include "cloud_index.hpp"

#include "cli_common.hpp"

#include <core/error.hpp>
#include <io/cloud_reader.hpp>

#include <glm/vec3.hpp>

#include <string>

namespace app {

IndexPlan planIndex(std::uint64_t budget_bytes, double memory_mb, int threads, std::string_view command,
                    bool fewer_threads, std::uint32_t max_node_points, std::size_t side_record_bytes) {
    // Plan-or-refuse: the reader's two chunks (one read while the other is written), and
    // the writer within the rest (past it, it spills the points to scratch files and
    // builds the octree a part at a time).
    const std::uint64_t reading = 2 * io::CloudReader::kChunkPoints * (sizeof(core::CloudPoint) + side_record_bytes);
    const auto least = [&](int t) { return io::copcMinimumBytes(t - 1, max_node_points) + reading; };
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
    // caller checked that every input has the same header facts).
    io::LasOptions las = plan.las;
    las.foreign = readers.front()->foreignHeader();
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
