// io/src/copc/writer/parts_output.hpp (internal): out of core, the file written once every
// part is built, in the in-memory writer's depth-first order (the same file, byte for
// byte): an upper node's chunk compressed from its set (top_sets.hpp), a batch of them at
// once on the threads; a bucket's nodes' chunks copied from the scratch file of chunks
// (bucket_builder.hpp), whose pages are freed as they are copied.
#pragma once
#include "assembler.hpp"
#include "part_tree.hpp"
#include "setup.hpp"
#include "top_sets.hpp"

#include <platform/scratch_file.hpp>

#include <cstddef>
#include <vector>

namespace io::detail::copc_writer {

class PartsOutput {
  public:
    /// `chunks` rewound, holding the buckets' chunks in bucket order.
    PartsOutput(const WriterSetup& setup, PartTree& tree, TopSets& sets, platform::ScratchFile& chunks)
        : setup_(setup), tree_(tree), sets_(sets), chunks_(chunks) {}

    /// Hands every node to `out`, depth first from the root.
    void write(Assembler& out);

  private:
    // An upper node's chunk, compressed a batch at a time (compressTops).
    struct TopChunk {
        LaszipFile file;
        LasInventory inventory;
    };

    void orderTops(int t);
    void compressTops(std::size_t from);
    void emit(Assembler& out, int t);

    const WriterSetup& setup_;
    PartTree& tree_;
    TopSets& sets_;
    platform::ScratchFile& chunks_;
    std::vector<int> top_order_;  // the upper nodes with points, in emit()'s order
    std::size_t top_next_ = 0, top_batch_from_ = 0;
    std::vector<TopChunk> top_batch_;
};

}  // namespace io::detail::copc_writer
