// bench/src/synthetic_survey.hpp: a synthetic survey written straight to COPC, node by
// node (io::CopcNodeWriter), for clouds too large for the generator's spool and the COPC
// writer's scratch files on a small disk (10^9 points take about 2.3 GB as COPC, against
// some 50 GB of scratch through `generate` or `index`).
//
// The survey: a square of terrain (gentle hills, flat-roofed blocks) filling the
// octree's cube across, centred on the cube's centre. Each node of level d holds, per
// cell of a 128 x 128 grid over its footprint, one point (a jittered sample of the
// surface); the deepest level holds more per cell so that the total reaches the count
// asked for. Levels add up as COPC's do: a node's points are a coarser sample of the
// surface beneath it. A node's xy footprint becomes one node per z cell its points fall
// in, so every point lies in its node's cube. The fields are the generator's (x y z rgb
// label view range); the points are deterministic.
#pragma once
#include <glm/vec3.hpp>

#include <cstddef>
#include <filesystem>

namespace bench {

struct SyntheticSurvey {
    std::size_t points = 0;  // written
    std::size_t nodes = 0;   // with points
    int leaf_level = 0;
};

/// Writes about `points` points (within one leaf cell's rounding) as COPC at `path`: the
/// cube of edge 2^bits mm centred on `origin`, on `threads` threads. Progress on stderr.
SyntheticSurvey writeSyntheticSurvey(const std::filesystem::path& path, std::size_t points, const glm::dvec3& origin,
                                     int bits, int threads);

}  // namespace bench
