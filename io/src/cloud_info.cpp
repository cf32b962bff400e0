// io/src/cloud_info.cpp: io::inspectCloud: the reader the content calls for (as
// CloudReader chooses it), the LAS part in las/las_info.cpp, and here the PCD and PLY
// part: the header's version and encoding, the points' count, bounds and fields.
#include "cloud_decode.hpp"
#include "las/las_facts.hpp"

#include <core/error.hpp>
#include <core/point_cloud.hpp>
#include <io/cloud_info.hpp>

#include <glm/common.hpp>

#include <cmath>
#include <string_view>

namespace io {
namespace {

constexpr std::size_t kChunkPoints = 1u << 16;

// The version and encoding the header states (PCD: VERSION and DATA; PLY: format), read
// once the reader has checked the header.
void headerWords(detail::ByteSource& source, bool ply, CloudInfo& info) {
    const std::string head = detail::headerPrefix(source);
    detail::LineReader lines{head};
    std::string_view line;
    while (lines.next(line)) {
        const std::vector<std::string_view> w = detail::splitWords(line);
        if (w.empty()) continue;
        if (ply && w[0] == "format" && w.size() >= 3) {
            info.encoding = core::printable(w[1], 40);
            info.version = core::printable(w[2], 20);
        } else if (!ply && w[0] == "VERSION" && w.size() >= 2) {
            info.version = core::printable(w[1], 20);
        } else if (!ply && w[0] == "DATA" && w.size() >= 2) {
            info.encoding = core::printable(w[1], 40);
        }
        if ((ply && w[0] == "end_header") || (!ply && w[0] == "DATA")) break;
    }
    if (!ply && info.version.rfind(".", 0) == 0) info.version = "0" + info.version;  // "VERSION .7"
}

void inspectPointFile(detail::ByteSource& source, const std::string& prefix, bool ply, CloudInfo& info,
                      const InspectProgress& progress) {
    const std::unique_ptr<detail::FormatReader> reader =
        ply ? detail::openPly(source, prefix) : detail::openPcd(source, prefix);
    info.format = ply ? "PLY" : "PCD";
    headerWords(source, ply, info);
    info.fields = core::fieldNames(reader->fields);
    std::vector<core::CloudPoint> chunk;
    chunk.reserve(kChunkPoints);
    while (reader->next(chunk, kChunkPoints) > 0) {
        for (const core::CloudPoint& p : chunk) {
            const glm::dvec3 world = reader->origin + glm::dvec3(p.position);
            if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) {
                ++info.non_finite;
                continue;
            }
            info.min = info.has_bounds ? glm::min(info.min, world) : world;
            info.max = info.has_bounds ? glm::max(info.max, world) : world;
            info.has_bounds = true;
        }
        info.points += chunk.size();
        chunk.clear();
        if (progress) progress(info.points, reader->declared);
    }
}

}  // namespace

CloudInfo inspectCloud(const std::filesystem::path& file, const char* context, const InspectProgress& progress) {
    const std::unique_ptr<detail::ByteSource> source = detail::fileSource(file, context);
    const std::string prefix = std::string(context) + ": " + file.string();
    CloudInfo info;
    info.file = file;
    info.file_bytes = source->size();
    const std::string module = detail::moduleOf(*source, file);
    if (module == "las")
        detail::inspectLas(*source, prefix, file, info, progress);
    else
        inspectPointFile(*source, prefix, module == "ply", info, progress);
    return info;
}

CloudBounds readCloudBounds(const std::filesystem::path& file, const char* context) {
    const std::unique_ptr<detail::ByteSource> source = detail::fileSource(file, context);
    if (std::string_view(detail::moduleOf(*source, file)) != "las") {
        const CloudInfo info = inspectCloud(file, context);
        return {info.has_bounds, info.min, info.max};
    }
    // inspectLas's prefix, so a damaged header reads the same as there.
    detail::LasFacts facts;
    detail::LasTally tally;
    detail::openLasCounted(*source, std::string(context) + ": " + file.string(), facts, tally);
    return {true, facts.min, facts.max};
}

LasCrs readCloudCrs(const std::filesystem::path& file, const char* context) {
    const std::unique_ptr<detail::ByteSource> source = detail::fileSource(file, context);
    const std::string module = detail::moduleOf(*source, file);
    if (module != "las") return {};
    // The reader's own prefix, so a damaged header reads the same here as when its points are read.
    return detail::readLasCrs(*source, module + ": " + file.string());
}

}  // namespace io
