// sim/src/ground_reconstruct.cpp: see ground_reconstruct.hpp. Vincent's hybrid
// reconstruction (paper §V, algorithm "hybrid grayscale reconstruction"): a raster sweep
// and an anti-raster sweep each carry the marker forward under the mask from the
// neighbours already visited; the cells that could still raise a later neighbour go into
// a FIFO, which propagates until nothing rises.
#include "ground_reconstruct.hpp"

#include <algorithm>
#include <cassert>
#include <cstddef>

namespace sim {
namespace {

// The 8 neighbours as (di, dj); the first 4 come before a cell in raster order (N+), the
// last 4 after it (N-).
// Below every level a raster holds: a cell that no seed reaches.
constexpr float kFar_m = 1e30f;

constexpr int kNeighbours[8][2] = {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}};

}  // namespace

void reconstructByDilation(std::vector<float>& marker, const std::vector<float>& mask, int w, int h) {
    assert(marker.size() == mask.size() && marker.size() == std::size_t(w) * std::size_t(h));
    const std::size_t n = marker.size();
    for (std::size_t c = 0; c < n; ++c) marker[c] = std::min(marker[c], mask[c]);
    const auto at = [&](int i, int j) { return std::size_t(j) * std::size_t(w) + std::size_t(i); };
    const auto inside = [&](int i, int j) { return i >= 0 && i < w && j >= 0 && j < h; };
    // Raster sweep over N+, anti-raster sweep over N-.
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            float v = marker[at(i, j)];
            for (int k = 0; k < 4; ++k) {
                const int ii = i + kNeighbours[k][0], jj = j + kNeighbours[k][1];
                if (inside(ii, jj)) v = std::max(v, marker[at(ii, jj)]);
            }
            marker[at(i, j)] = std::min(v, mask[at(i, j)]);
        }
    // The FIFO: a ring of at most n cells, `queued` so that a cell is in it once at a time
    // (when it comes out it spreads its level as it is then, the highest it was given).
    std::vector<std::uint32_t> ring(std::max<std::size_t>(n, 1));
    std::vector<std::uint8_t> queued(n, 0);
    std::size_t head = 0, size = 0;
    const auto push = [&](std::size_t c) {
        if (queued[c]) return;
        queued[c] = 1;
        ring[(head + size) % ring.size()] = std::uint32_t(c);
        ++size;
    };
    for (int j = h - 1; j >= 0; --j)
        for (int i = w - 1; i >= 0; --i) {
            float v = marker[at(i, j)];
            for (int k = 4; k < 8; ++k) {
                const int ii = i + kNeighbours[k][0], jj = j + kNeighbours[k][1];
                if (inside(ii, jj)) v = std::max(v, marker[at(ii, jj)]);
            }
            v = std::min(v, mask[at(i, j)]);
            marker[at(i, j)] = v;
            for (int k = 4; k < 8; ++k) {
                const int ii = i + kNeighbours[k][0], jj = j + kNeighbours[k][1];
                if (!inside(ii, jj)) continue;
                const std::size_t q = at(ii, jj);
                if (marker[q] < v && marker[q] < mask[q]) {
                    push(at(i, j));
                    break;
                }
            }
        }
    while (size > 0) {
        const std::size_t p = ring[head];
        head = (head + 1) % ring.size();
        --size;
        queued[p] = 0;
        const int i = int(p % std::size_t(w)), j = int(p / std::size_t(w));
        const float v = marker[p];
        for (const auto& d : kNeighbours) {
            const int ii = i + d[0], jj = j + d[1];
            if (!inside(ii, jj)) continue;
            const std::size_t q = at(ii, jj);
            if (marker[q] < v && marker[q] != mask[q]) {
                marker[q] = std::min(v, mask[q]);
                push(q);
            }
        }
    }
}

void geodesicDilation(std::vector<float>& marker, const std::vector<float>& mask, int w, int h, int steps) {
    if (steps <= 0) {
        reconstructByDilation(marker, mask, w, h);
        return;
    }
    for (std::size_t c = 0; c < marker.size(); ++c) marker[c] = std::min(marker[c], mask[c]);
    std::vector<float> next(marker.size());
    for (int s = 0; s < steps; ++s) {
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const std::size_t c = std::size_t(j) * std::size_t(w) + std::size_t(i);
                float v = marker[c];
                for (int jj = std::max(0, j - 1); jj <= std::min(h - 1, j + 1); ++jj)
                    for (int ii = std::max(0, i - 1); ii <= std::min(w - 1, i + 1); ++ii)
                        v = std::max(v, marker[std::size_t(jj) * std::size_t(w) + std::size_t(ii)]);
                next[c] = std::min(v, mask[c]);
            }
        marker.swap(next);
    }
}

std::vector<float> hDomes(const std::vector<float>& surface, int w, int h, float h_m) {
    std::vector<float> lowered(surface.size());
    for (std::size_t c = 0; c < surface.size(); ++c) lowered[c] = surface[c] - h_m;
    reconstructByDilation(lowered, surface, w, h);
    for (std::size_t c = 0; c < surface.size(); ++c) lowered[c] = surface[c] - lowered[c];
    return lowered;
}

void domeGroundBack(const std::vector<float>& surface, const std::vector<std::uint8_t>& observed,
                    std::vector<std::uint8_t>& ground, int w, int h, float h_m, float tolerance_m) {
    const std::vector<float> dome = hDomes(surface, w, h, h_m);
    for (std::size_t c = 0; c < surface.size(); ++c)
        if (observed[c] && !ground[c] && dome[c] <= tolerance_m) ground[c] = 1;
}

void topHatObjects(const std::vector<float>& surface, std::vector<float>& eroded, std::vector<std::uint8_t>& ground,
                   int w, int h, float h_m) {
    reconstructByDilation(eroded, surface, w, h);
    for (std::size_t c = 0; c < surface.size(); ++c)
        if (surface[c] - eroded[c] > h_m) ground[c] = 0;
}

std::size_t stepGroundBack(const std::vector<float>& surface, const std::vector<float>& terrain,
                           const std::vector<std::uint8_t>& observed, std::vector<std::uint8_t>& ground, int w, int h,
                           float tolerance_m, float max_rise_m, int steps, bool from_ground) {
    std::vector<float> reached(surface.size());
    for (std::size_t c = 0; c < surface.size(); ++c)
        reached[c] = from_ground ? (observed[c] && ground[c] ? surface[c] : -kFar_m)
                                 : std::min(terrain[c] + tolerance_m, surface[c]);
    geodesicDilation(reached, surface, w, h, steps);
    std::size_t given = 0;
    for (std::size_t c = 0; c < surface.size(); ++c)
        if (observed[c] && !ground[c] && reached[c] >= surface[c] - tolerance_m &&
            surface[c] - terrain[c] <= max_rise_m) {
            ground[c] = 1;
            ++given;
        }
    return given;
}

}  // namespace sim
