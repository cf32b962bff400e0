// bench/src/plain_loop.hpp: the ray-casting baseline that `bench generate` and `bench
// peers` measure in the same run: Embree's rtcIntersect1 per ray, nothing else.
#pragma once
#include <sim/raycaster.hpp>

#include <vector>

namespace bench {

/// RayCaster::intersect (rtcIntersect1 per ray) over `rays` on `threads` threads (>= 1)
/// taking 4096-ray chunks from a shared counter; `hits` is resized to match. Returns the
/// wall time in seconds.
double plainLoopSeconds(const sim::RayCaster& caster, const std::vector<sim::Ray>& rays,
                        std::vector<sim::Hit>& hits, int threads);

}  // namespace bench
