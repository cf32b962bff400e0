// bench/src/view_pick.hpp: the pointer's pick (viewer/pick_index.hpp) timed on a cloud,
// against a scan of every point, for `ladarvr bench view --paths pick`.
#pragma once
#include <core/point_cloud.hpp>

#include <cstdio>

namespace bench {

/// Builds the pick index over `cloud` and times `rays` picks from the automatic orbit's
/// eye positions towards random points of the cloud (seeded), and a few scans of every
/// point for the same rays. Prints one Markdown table row to `out`.
void measurePicking(const core::PointCloud& cloud, int rays, std::FILE* out);
/// The header of measurePicking's table.
void printPickingHeader(std::FILE* out);

}  // namespace bench
