// bench/src/plain_loop.hpp: the ray-casting baselines that `bench generate` and `bench
// peers` measure in the same run: Embree's rtcIntersect1 per ray, or rtcIntersect16 per
// packet of 16 consecutive pixels of a row, over precomputed rays, nothing else.
#pragma once
#include <sim/raycaster.hpp>

#include <vector>

namespace bench {

/// RayCaster::intersect (rtcIntersect1 per ray) over `rays` on `threads` threads (>= 1)
/// taking 4096-ray chunks from a shared counter; `hits` is resized to match. Returns the
/// wall time in seconds.
double plainLoopSeconds(const sim::RayCaster& caster, const std::vector<sim::Ray>& rays, std::vector<sim::Hit>& hits,
                        int threads);

/// RayCaster::intersect16 (rtcIntersect16 packets of 16 consecutive rays, coherent) over
/// `rays`, taken as rows of `row_px` rays (row-major pixels; the packets never straddle
/// two rows, as in the generator), on `threads` threads (>= 1) taking whole rows, about
/// 4096 rays at a time, from a shared counter; `hits` is resized to match. Returns the
/// wall time in seconds.
double plainPacketLoopSeconds(const sim::RayCaster& caster, const std::vector<sim::Ray>& rays,
                              std::vector<sim::Hit>& hits, int threads, std::size_t row_px);

}  // namespace bench
