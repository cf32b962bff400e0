// fuzz/check_cloud_reader.hpp: the contract every cloud reader target checks (one
// copy for fuzz_cloud_reader and fuzz_las_reader).
#pragma once
#include <core/error.hpp>
#include <io/cloud_io.hpp>
#include <io/cloud_reader.hpp>
#include "check_message.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace fuzz {

inline bool samePoint(const core::CloudPoint& a, const core::CloudPoint& b) {
    return std::memcmp(&a.position, &b.position, sizeof a.position) == 0 && a.rgb == b.rgb &&
           std::memcmp(&a.range_m, &b.range_m, 4) == 0 && a.view == b.view && a.label == b.label;
}

/// The reader's contract over `bytes` (see fuzz_cloud_reader.cpp); aborts when broken.
inline void checkCloudReader(std::string_view bytes) {
    const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
    const std::size_t size = bytes.size();
    std::string whole_error;
    core::PointCloud whole;
    try {
        whole = io::readCloudData(bytes, "fuzz.pcd");
        // A cloud that was accepted must be usable: labels in range, everything finite.
        for (const core::CloudPoint& p : whole.points)
            if (static_cast<int>(p.label) > 2 || !std::isfinite(p.position.x) || !std::isfinite(p.position.y) ||
                !std::isfinite(p.position.z) || (whole.fields.range && !std::isfinite(p.range_m)))
                std::abort();
        if (!std::isfinite(whole.origin.x) || !std::isfinite(whole.origin.y) || !std::isfinite(whole.origin.z))
            std::abort();
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what(), true);
        whole_error = e.what();
        // The documented way to refuse bad input. LADARVR_FUZZ_VERBOSE=1 shows why (seeds).
        if (std::getenv("LADARVR_FUZZ_VERBOSE")) std::fprintf(stderr, "refused: %s\n", e.what());
    }

    // The chunked path: a chunk size from the input's last byte (1..256 points).
    const std::size_t chunk = size == 0 ? 1 : std::size_t(data[size - 1]) + 1;
    std::vector<core::CloudPoint> points;
    std::string chunk_error;
    try {
        io::CloudReader reader(bytes, "fuzz.pcd");
        if (whole_error.empty() && (reader.origin() != whole.origin || reader.declaredPoints() < whole.points.size()))
            std::abort();
        while (reader.nextChunk(points, chunk)) {
            if (points.size() > reader.pointsRead()) std::abort();
        }
        if (reader.pointsRead() != reader.declaredPoints() ||
            reader.pointsRead() != points.size() + reader.droppedNonFinite())
            std::abort();
    } catch (const core::Error& e) {
        chunk_error = e.what();
    }
    if (chunk_error != whole_error) {
        std::fprintf(stderr, "chunks of %zu: '%s' but whole: '%s'\n", chunk, chunk_error.c_str(), whole_error.c_str());
        std::abort();
    }
    if (whole_error.empty()) {
        if (points.size() != whole.points.size()) std::abort();
        for (std::size_t i = 0; i < points.size(); ++i)
            if (!samePoint(points[i], whole.points[i])) std::abort();
    }

    // With a foreign file's side records kept (index and ground writing its fields back):
    // a refusal is one line; where the whole read succeeded, the same points, each with
    // one side record.
    std::vector<core::CloudPoint> kept;
    try {
        io::CloudReader reader(bytes, "fuzz.pcd", io::SideRecords::Keep);
        const std::shared_ptr<const core::ForeignHeader> header = reader.foreignHeader();
        std::vector<unsigned char> records;
        while (reader.nextChunk(kept, records, chunk)) {}
        const std::size_t stride = header ? header->stride() : 0;
        if (records.size() != kept.size() * stride) {
            std::fprintf(stderr, "%zu side record bytes for %zu points of stride %zu\n", records.size(), kept.size(),
                         stride);
            std::abort();
        }
        if (whole_error.empty()) {
            if (kept.size() != whole.points.size()) std::abort();
            for (std::size_t i = 0; i < kept.size(); ++i)
                if (!samePoint(kept[i], whole.points[i])) std::abort();
        }
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what(), true);
        if (whole_error.empty()) {
            std::fprintf(stderr, "side records kept: '%s' but whole: read\n", e.what());
            std::abort();
        }
    }

    // Positions only (the ground fit's passes): where the whole read succeeded, the same
    // points in the same order at the same positions.
    std::vector<core::CloudPoint> located;
    try {
        io::CloudReader reader(bytes, "fuzz.pcd", io::SideRecords::Drop, io::PointFields::Positions);
        while (reader.nextChunk(located, chunk)) {}
        if (whole_error.empty()) {
            if (located.size() != whole.points.size()) std::abort();
            for (std::size_t i = 0; i < located.size(); ++i)
                if (std::memcmp(&located[i].position, &whole.points[i].position, sizeof located[i].position) != 0)
                    std::abort();
        }
    } catch (const core::Error& e) {
        fuzz::checkMessage(e.what(), true);
        if (whole_error.empty()) {
            std::fprintf(stderr, "positions only: '%s' but whole: read\n", e.what());
            std::abort();
        }
    }
}

}  // namespace fuzz
