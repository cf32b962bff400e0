// io/src/copc/copc_octree.hpp (internal): the octree a COPC file stores, built over the
// points' integer LAS coordinates (millimetres from the origin).
//
// The cube: an edge of 2^bits mm, the smallest power of two longer than the points' widest
// extent, centred on their bounds, its faces half a millimetre off the integer grid so that
// no point ever lies on a node's face (a point's node is the same whether a reader tests it
// in integers or in double-precision world coordinates).
// The nodes: a node whose subtree holds at most max_node_points points, or whose cube is
// 1 mm wide, is a leaf holding all of them. Otherwise its points are split among its eight
// children, the children's subtrees are built, and then the node takes a grid sample of its
// children's points: over a grid of 128^3 cells on its cube (cells of the node's spacing,
// 2 * halfsize / 128 at the root, halved per level) it keeps, per occupied cell, the point
// that came first in the input, and those points leave the children. When that sample
// would exceed max_node_points the grid is coarsened (64^3, 32^3, ...) until it does not.
// Every point ends in exactly one node, inside that node's cube; a node's points, with
// those of its ancestors, cover every cell of its grid that any point below it occupies.
#pragma once
#include <io/copc.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace io::detail {

struct OctreeCube {
    /// Integer coordinates of the cube's low corner plus half a millimetre: a point at
    /// integer x lies in cell (x - corner) >> (bits - level) of a level.
    std::array<std::int64_t, 3> corner{};
    int bits = 0;  // the edge is 2^bits mm
};

/// The cube for points whose integer coordinates lie in [min, max] (each axis).
OctreeCube enclosingCube(const std::array<std::int32_t, 3>& min, const std::array<std::int32_t, 3>& max);

struct OctreeNode {
    CopcKey key;
    std::vector<std::uint32_t> points;  // indices into the input, ascending
};

inline constexpr int kGridBits = 7;  // a node's sampling grid: 2^7 = 128 cells per axis

/// Marks of the occupied grid cells (2^21 of them, 8 MiB once used), one per thread,
/// cleared by a new generation.
struct Marks {
    std::vector<std::uint32_t> cell;
    std::uint32_t generation = 0;
    void reset();
};

/// The grid sample of the node at `level` whose children hold `children` (indices into
/// `xyz`, ascending): per occupied cell of its grid the point of the lowest index, the grid
/// coarsened until at most `cap` are kept. The chosen points leave the children. Returns
/// them, ascending.
std::vector<std::uint32_t> gridSample(std::span<const std::array<std::int32_t, 3>> xyz, const OctreeCube& cube,
                                      int level, std::span<std::vector<std::uint32_t>* const> children, std::size_t cap,
                                      Marks& marks);

/// Builds the octree of `xyz` (all inside `cube`) on `threads` threads besides the caller's
/// (the result is the same for any count). Returns every node, those left with no points
/// (whose descendants hold points) included, in depth-first order: a node, then its
/// children's subtrees in the order of their octant (x the lowest bit, then y, then z).
/// `marks`, when given, holds the threads' marks from one call to the next (a caller that
/// builds many trees saves clearing and faulting in 8 MiB a thread each time).
std::vector<OctreeNode> buildOctree(std::span<const std::array<std::int32_t, 3>> xyz, const OctreeCube& cube,
                                    std::uint32_t max_node_points, int threads, std::vector<Marks>* marks = nullptr);

/// Runs fn(i, worker) for i in [0, n) on `threads` threads besides the caller's, `worker`
/// in [0, threads] naming the thread (0 the caller); rethrows the error of the lowest i
/// that threw, after all have finished.
void parallelFor(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& fn);

/// Runs work(i) for i in [0, n) on `threads` threads besides the caller's, and emit(i) on
/// the caller's thread in ascending order of i as soon as work(i) and every emit before it
/// are done. The items begun and not yet emitted weigh at most `window` together, except
/// that an item begins alone whatever its weight: so what they hold is bounded. An item
/// weighs weight(i, false) from its beginning and weight(i, true) once its work is done
/// (what its result holds from then until its emit), or 1 throughout
/// without `weight`. No thread waits at the end of a batch: a thread that finishes takes
/// the next item while the window allows. After an error (the lowest i's work, or an
/// emit) no item is begun, those begun finish, and the error is rethrown.
void orderedParallel(std::size_t n, int threads, std::size_t window, const std::function<void(std::size_t)>& work,
                     const std::function<void(std::size_t)>& emit,
                     const std::function<std::size_t(std::size_t, bool)>& weight = {});

}  // namespace io::detail
