// io/src/copc/writer/direct_sort.cpp: the points sorted into their buckets as they are
// appended, after the prescan (direct_sort.hpp).
#include "direct_sort.hpp"

#include <core/error.hpp>

#include <algorithm>
#include <string>

namespace io::detail::copc_writer {

using core::Error;

DirectSort::DirectSort(const WriterSetup& setup, PartTree& tree, const std::array<std::int32_t, 3>& lo,
                       const std::array<std::int32_t, 3>& hi, std::uint64_t points)
    : setup_(setup),
      tree_(tree),
      lo_(lo),
      hi_(hi),
      cube_(enclosingCube(lo, hi)),
      points_(points),
      sorter_(setup, tree, tree.buckets.size()) {
    for (Bucket& b : tree_.buckets) b.file.emplace(setup_.scratchFile());
}

bool DirectSort::within(const std::array<std::int32_t, 3>& xyz) const {
    for (std::size_t k = 0; k < 3; ++k)
        if (xyz[k] < lo_[k] || xyz[k] > hi_[k]) return false;
    return true;
}

void DirectSort::append(std::span<const core::CloudPoint> points) {
    const std::size_t size = setup_.packing.size();
    const std::size_t parts = std::size_t(setup_.threads) + 1;
    while (!points.empty()) {
        const std::size_t n = std::min(points.size(), kScratchBlock * parts);
        if (count_ + n > points_)
            throw Error(setup_.record.where() + ": more points appended than the " + std::to_string(points_) +
                        " prescanned");
        Round& r = rounds_[next_];  // the other may be being gathered
        r.first = count_;
        r.n = n;
        r.bytes.resize(n * size);
        r.bucket.resize(n);
        const std::size_t blocks = (n + kScratchBlock - 1) / kScratchBlock;
        parallelFor(blocks, setup_.threads, [&](std::size_t b, std::size_t) {
            for (std::size_t i = b * kScratchBlock; i < std::min(n, (b + 1) * kScratchBlock); ++i) {
                const std::array<std::int32_t, 3> xyz = setup_.record.quantize(points[i], r.first + i);
                if (!within(xyz))
                    throw Error(setup_.record.where() + ": point " + std::to_string(r.first + i) +
                                " lies outside the bounds of the points prescanned");
                r.bucket[i] = std::uint32_t(tree_.bucketOf(cube_, xyz));
                setup_.packing.packQuantized(points[i], xyz, r.bytes.data() + i * size);
            }
        });
        count_ += n;
        waitGather();
        if (setup_.threads == 0)
            sorter_.gather(r, 0, tree_.buckets.size());
        else
            gather_ = std::async(std::launch::async, [this, &r] { sorter_.gather(r, 0, tree_.buckets.size()); });
        next_ ^= 1;
        points = points.subspan(n);
    }
}

void DirectSort::waitGather() {
    if (gather_.valid()) gather_.get();
}

void DirectSort::finish() {
    waitGather();
    if (count_ != points_)
        throw Error(setup_.record.where() + ": " + std::to_string(count_) + " points appended of the " +
                    std::to_string(points_) + " prescanned");
    sorter_.close(0, tree_.buckets.size());
    for (const Bucket& b : tree_.buckets)
        if (b.filled != b.count)
            throw Error(setup_.record.where() + ": the points appended are not the points prescanned");
}

}  // namespace io::detail::copc_writer
