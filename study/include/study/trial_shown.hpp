// study/trial_shown.hpp: shown_<N>.json in a study folder, what trial N showed and what the
// operator marked on it, so `--replay` shows the trial as the participant saw it without
// running a detector again:
//   {"colour": "height", "eye_dome": true,
//    "candidates": [{"id": "c1", "centre": [x, y, z], "size_m": [l, w, h], "yaw_deg": 20,
//                    "score": 0.9}, ...],
//    "marks": [{"t_s": 1.2, "designate": [x, y, z]}, {"t_s": 2.0, "designate": null},
//              {"t_s": 3.1, "candidate": "c1", "verdict": "confirmed"}],
//    "terrain": {"source": "the file's class 2 (35,318 points)"}}
// `colour` and `eye_dome` are left out where the trial's condition leaves them as they
// stand; `terrain` (where the ground of its above-ground colours came from, or
// {"failure": why}) where the trial had one coming; the candidates are the boxes shown, in the candidates file's format (world
// coordinates); the marks come in the order made, times from the start of the trial, a
// `designate` of null being a withdrawn designation. Meanings: docs/study.md.
#pragma once
#include <viewer/trial.hpp>
#include <viewer/viewer.hpp>

#include <core/candidates.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace study {

/// What one trial showed and what was marked on it.
struct TrialShown {
    std::optional<viewer::ColourMode> colour;
    std::optional<bool> eye_dome;
    std::vector<core::Candidate> candidates;
    std::vector<viewer::TrialMark> marks;
    /// The terrain its above-ground colours were drawn with, or why none came
    /// (viewer::TrialOutcome); both empty: none was coming.
    std::string terrain_source, terrain_failure;
};

/// "shown_<trial_number>.json"; trials are numbered 1.. in the order they ran.
std::string shownFileName(int trial_number);

/// The file's text (one JSON object, as above).
std::string formatTrialShown(const TrialShown& shown);

/// Reads `file` (a regular file of at most 64 MiB, not through a link): throws
/// core::Error("study: --replay FILE: <field>: ...; allowed ...") naming what is wrong.
TrialShown readTrialShown(const std::filesystem::path& file);

}  // namespace study
