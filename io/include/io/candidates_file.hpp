// io/candidates_file.hpp: the candidates file: candidate detections (core/candidates.hpp) as JSON.
//
// File format (JSON, written by `ladarvr detect`, read by `ladarvr view --candidates` and
// by study plans):
//   {"candidates": [{"id": "c1", "centre": [x, y, z], "size_m": [l, w, h],
//                    "yaw_deg": 30.0, "score": 0.8}, ...]}
// centre in world coordinates (metres, z up, the box's centre); size_m the box's length
// along its own x, width along its y, height; yaw_deg counter-clockwise about +z from +x;
// score in [0, 1], higher is more likely a target. Ids are unique, non-empty strings.
// Centre coordinates are bounded like scene positions (|c| <= kMaxWorldCoordinate_m) and
// sizes like local coordinates (<= kMaxLocalCoordinate_m), core/frames.hpp.
#pragma once
#include <core/candidates.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace io {

/// Reads a candidates file (regular file, bounded size). Throws core::Error naming the
/// file and the field, e.g. "candidates: a.json: candidates[2].score 1.5 is not in [0, 1]".
std::vector<core::Candidate> readCandidates(const std::filesystem::path& file);
/// As readCandidates, from text already read (at most 16 MiB); `name` begins every message
/// ("candidates: a.json").
std::vector<core::Candidate> parseCandidates(std::string_view text, const std::string& name);
/// The text writeCandidates writes: parseCandidates reads the same candidates back.
std::string candidatesJson(const std::vector<core::Candidate>& candidates);
/// Writes a candidates file atomically (platform/atomic_file.hpp).
void writeCandidates(const std::filesystem::path& file, const std::vector<core::Candidate>& candidates);

}  // namespace io
