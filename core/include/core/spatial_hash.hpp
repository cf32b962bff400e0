// core/spatial_hash.hpp: the project's one spatial binning of points into cubic cells,
// used for the GPU culling chunks of render's splat renderer and the metric's images.
#pragma once
#include <core/point_cloud.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace core {

/// Integer coordinates of the cubic cell of side cell_m holding p: floor(p / cell_m).
struct CellKey {
    std::int64_t x = 0, y = 0, z = 0;
    bool operator==(const CellKey&) const = default;
};
CellKey cellOf(const glm::vec3& p, double cell_m);

/// Hash of a key (the usual large-prime spatial hash, xor of the products).
struct CellKeyHash {
    std::size_t operator()(const CellKey& k) const;
};

/// Point indices grouped by cell. Cells come in the order of their first point and each
/// cell lists its points in input order, so the grouping is the same on every platform.
struct CellBins {
    std::vector<std::uint32_t> order;    // every point index once, grouped by cell
    std::vector<std::size_t> starts{0};  // cell c is order[starts[c], starts[c + 1])
    std::vector<CellKey> keys;           // per cell
    std::size_t cells() const { return keys.size(); }
    std::span<const std::uint32_t> cell(std::size_t c) const {
        return std::span(order).subspan(starts[c], starts[c + 1] - starts[c]);
    }
};

/// Bins `points` (fewer than 2^32 - 1 of them) into cubic cells of side cell_m > 0 (local
/// frame; infinity gives one cell per octant). Throws core::Error("spatial hash: ...")
/// for a cell size that is not > 0 or too many points.
CellBins binByCell(std::span<const CloudPoint> points, double cell_m);

}  // namespace core
