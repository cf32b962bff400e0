// sim/ground.hpp: ground detection for whitening, paper §III-C's five-step iterative RANSAC.
#pragma once
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sim {

/// Thresholds of the iterative RANSAC; defaults are the paper's where it gives them.
struct GroundOptions {
    double band_m = 3.0;                // step 1: keep z in [z_min, z_min + band_m] (paper: 3 m)
    double distance_threshold_m = 0.2;  // RANSAC inlier distance (not given by the paper)
    double min_normal_z = 0.9;          // step 3: accept a plane when |normal.z| >= this
    double stop_fraction = 0.01;        // step 5: stop when under this fraction of PC is left
    /// Ours, not the paper's: a horizontal plane joins PG only if it holds at least this
    /// fraction of the band (step 1's PC). Rejects the tank's roof and the horizontal
    /// slabs RANSAC cuts through walls once the ground is gone. 0 = the paper's rule.
    double min_plane_fraction = 0.05;
    int max_planes = 25;                // cap on steps 2-5 (the paper's loop has none)
    int ransac_iterations = 1000;       // SACSegmentation's max iterations per plane
    /// Ours: RANSAC searches the plane on at most this many points of PC (a uniform
    /// sample: PC is shuffled), then every point of PC within distance_threshold_m of
    /// that plane is an inlier. Same planes on big views, ~10x faster. 0 = all of PC.
    int ransac_sample_points = 20000;
};

/// Throws engine::Error("ground: <parameter> = <value>: allowed ...").
void validate(const GroundOptions& o);

struct GroundStats {
    std::size_t band_points = 0;      // |PC| at step 1
    std::size_t ground_points = 0;    // |PG|
    int planes_accepted = 0;          // near-horizontal planes added to PG
    int planes_rejected = 0;          // planes removed from PC without joining PG (walls)
    int planes_too_small = 0;         // of those, horizontal but under min_plane_fraction
};

/// Paper §III-C steps 1-5 on one view's points: returns one flag per point, 1 when the
/// point is in PG (ground). PC is shuffled (engine::shuffle) with std::mt19937_64(seed) first (PCL's own RNG
/// is fixed-seed), so the result is a pure function of (points, options, seed).
/// Fewer than 3 points in the band: no RANSAC, no ground. Needs validate(o) passed.
std::vector<std::uint8_t> findGround(std::span<const glm::vec3> points, const GroundOptions& o,
                                     std::uint64_t seed, GroundStats* stats = nullptr);

}  // namespace sim
