// io/src/copc/writer/top_sets.hpp (internal): out of core, the points of the nodes above
// the buckets, kept as runs of Lifted records in one scratch file (each run ascending by
// input index), and their grid sampling bottom-up, as the in-memory octree samples
// (copc_octree.hpp) but streaming each node's children's runs from the file, so memory
// holds one node's chosen points, never the whole top of the tree.
#pragma once
#include "../copc_octree.hpp"
#include "part_tree.hpp"
#include "setup.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace io::detail::copc_writer {

class TopSets {
  public:
    /// An empty scratch file in the output's folder.
    explicit TopSets(const WriterSetup& setup);

    /// Appends a run; returns the offset it starts at (a Top's set_at).
    std::uint64_t append(std::span<const Lifted> run);
    /// Makes what was appended readable by read().
    void flush() { file_.flush(); }
    /// Reads out.size() records at `at`; several threads may read at once.
    void read(std::span<Lifted> out, std::uint64_t at) const { file_.readAt(out.data(), out.size_bytes(), at); }

    /// Gives every upper node at and below `t` its set, bottom-up: per occupied cell of its
    /// grid the point of the lowest input index among its children's sets, the grid
    /// coarsened until at most the cap are kept (gridSample's rule). The chosen points
    /// leave the children, whose sets are written anew. A bucket's root has its set already.
    void sample(PartTree& tree, const OctreeCube& cube, int t, Marks& marks);

  private:
    template <typename Fn>
    void merge(const std::vector<Top>& tops, std::span<const int> which, Fn fn);

    const WriterSetup& setup_;
    platform::ScratchFile file_;
    std::uint64_t end_ = 0;
};

}  // namespace io::detail::copc_writer
