// io/candidates_file.hpp: the candidates file: candidate detections (core/candidates.hpp) as JSON.
//
// File format (JSON, written by `ladarvr detect`, read by `ladarvr view --candidates` and
// by study plans):
//   {"candidates": [{"id": "c1", "centre": [x, y, z], "size_m": [l, w, h],
//                    "yaw_deg": 30.0, "score": 0.8}, ...]}
// centre in world coordinates (metres, z up, the box's centre); size_m the box's length
// along its own x, width along its y, height, in metres; yaw_deg counter-clockwise about
// +z from +x; score in [0, 1], higher is more likely a target. Ids are unique, non-empty
// strings. Candidates found in a survey whose coordinates are not in metres (US survey
// feet) keep their centres in its coordinates, and the file says so at the top:
//   "units": {"horizontal_m": 0.3048006, "vertical_m": 0.3048006}
// the length of the centres' horizontal and vertical units, in metres (each in
// [1e-6, 1e6]); without it both are 1. size_m stays in metres either way.
// Centre coordinates are bounded like scene positions (|c| <= kMaxWorldCoordinate_m) and
// sizes like local coordinates (<= kMaxLocalCoordinate_m), core/frames.hpp.
#pragma once
#include <core/candidates.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace io {

/// The units of a candidates file's centres: metres per horizontal (x, y) and vertical
/// (z) unit of the cloud they were found in.
struct CandidateUnits {
    double horizontal_m = 1.0;
    double vertical_m = 1.0;
    bool metres() const { return horizontal_m == 1.0 && vertical_m == 1.0; }
};

/// Reads a candidates file (regular file, bounded size), and its "units" into `units`
/// when given. Throws core::Error naming the file and the field, e.g. "candidates:
/// a.json: candidates[2].score 1.5 is not in [0, 1]".
std::vector<core::Candidate> readCandidates(const std::filesystem::path& file, CandidateUnits* units = nullptr);
/// As readCandidates, from text already read (at most 16 MiB); `name` begins every message
/// ("candidates: a.json").
std::vector<core::Candidate> parseCandidates(std::string_view text, const std::string& name,
                                             CandidateUnits* units = nullptr);
/// The text writeCandidates writes: parseCandidates reads the same candidates and units
/// back. "units" is written only when they are not metres.
std::string candidatesJson(const std::vector<core::Candidate>& candidates, const CandidateUnits& units = {});
/// Writes a candidates file atomically (platform/atomic_file.hpp).
void writeCandidates(const std::filesystem::path& file, const std::vector<core::Candidate>& candidates,
                     const CandidateUnits& units = {});

}  // namespace io
