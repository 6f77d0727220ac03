#pragma once
// The broad phase of hair–hair interactions (Bertails et al. 2003 §4.1: "a space voxel grid
// is used to store the active wisp segments"): which axis-aligned boxes overlap.
//
// A hierarchical grid (Ericson, Real-Time Collision Detection §7.2): cell widths double from
// level to level, and each box goes into one cell, the one holding its centre, at the first
// level whose cells are at least as wide as the box. Two boxes overlap only if their centres
// are closer than half the sum of their widths on every axis, so a box meets every box it may
// touch among the cells within half a cell width of it at its own level and at every coarser
// one. Looking only there, and at its own level only at entries after its own, visits each
// pair once: no pair is enumerated twice, whatever the boxes' sizes.
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace wisp {

struct Box4 {
    Eigen::Vector4f lo, hi;  // x, y, z, 0
};

// SSE where the target has it (every x86-64 does): the test runs for every candidate pair.
inline bool boxes_overlap(const Box4& a, const Box4& b) {
#if defined(__SSE2__)
    const __m128 apart =
        _mm_or_ps(_mm_cmpgt_ps(_mm_loadu_ps(a.lo.data()), _mm_loadu_ps(b.hi.data())),
                  _mm_cmpgt_ps(_mm_loadu_ps(b.lo.data()), _mm_loadu_ps(a.hi.data())));
    return _mm_movemask_ps(apart) == 0;
#else
    return !((a.lo.array() > b.hi.array()) || (b.lo.array() > a.hi.array())).any();
#endif
}

class BoxGrid {
  public:
    static constexpr int kLevels = 16;

    // Bins `boxes` with finest cells `cell` wide (> 0). Boxes that are not finite, are over
    // 2¹⁵ cells wide or lie over 2¹⁹ cells from the origin are left out (they meet nothing).
    void build(std::span<const Box4> boxes, float cell);

    // The binned boxes in grid order: the index, in the boxes given to build(), of each.
    // Data laid out in this order is read in sequence by for_each_overlap().
    std::span<const uint32_t> order() const { return index_; }

    // Calls visit(a, b) once for every pair of overlapping boxes, a ≠ b given as positions in
    // order(), in an order that depends only on the boxes: every pair of a before the next
    // a. A visit that returns bool ends a's pairs by returning false.
    template <class Visit>
    void for_each_overlap(Visit&& visit) const {
        for_each_overlap(0, order().size(), visit);
    }
    // The same for the pairs whose first box a is in [begin, end): disjoint ranges visit
    // disjoint sets of pairs, so ranges can run in parallel.
    template <class Visit>
    void for_each_overlap(size_t begin, size_t end, Visit&& visit) const;

  private:
    struct Entry {
        uint64_t key;
        uint32_t index;
    };
    // A cell's key: level, then z, y, x (kCellBits each), so that cells neighbouring along x
    // are adjacent in key order.
    static constexpr int kCellBits = 20;
    static constexpr int64_t kCellOffset = int64_t{1} << (kCellBits - 1);
    static constexpr int64_t kCellMax = (int64_t{1} << kCellBits) - 1;
    static uint64_t key(int level, int64_t x, int64_t y, int64_t z) {
        return (static_cast<uint64_t>(level) << (3 * kCellBits)) |
               (static_cast<uint64_t>(z) << (2 * kCellBits)) |
               (static_cast<uint64_t>(y) << kCellBits) | static_cast<uint64_t>(x);
    }
    static int level_of(uint64_t key) { return static_cast<int>(key >> (3 * kCellBits)); }
    // The cells, at `level` (cells `width` wide), holding the centre of a box that may meet `box`.
    void cell_range(const Box4& box, float width, int64_t from[3], int64_t to[3]) const;

    float cell_ = 1;
    std::vector<Entry> entries_;
    // In grid order: keys, boxes and the boxes' indices.
    std::vector<uint64_t> keys_;
    std::vector<Box4> boxes_;
    std::vector<uint32_t> index_;
    std::array<size_t, kLevels + 1> level_begin_{};
};

template <class Visit>
void BoxGrid::for_each_overlap(size_t first, size_t last, Visit&& visit) const {
    last = std::min(last, keys_.size());
    for (size_t i = first; i < last; ++i) {
        bool more = true;
        const Box4& a = boxes_[i];
        const int own = level_of(keys_[i]);
        float width = cell_ * static_cast<float>(1 << own);
        for (int l = own; l < kLevels && more; ++l, width *= 2) {
            const size_t begin = level_begin_[l], end = level_begin_[l + 1];
            if (begin == end) continue;
            int64_t from[3], to[3];
            cell_range(a, width, from, to);
            size_t j = begin;
            for (int64_t z = from[2]; z <= to[2] && more; ++z)
                for (int64_t y = from[1]; y <= to[1] && more; ++y) {
                    // A row of cells along x is contiguous in key order, and rows come in
                    // increasing order: each search starts where the last one ended.
                    const uint64_t first = key(l, from[0], y, z), last = key(l, to[0], y, z);
                    j = static_cast<size_t>(
                        std::lower_bound(keys_.begin() + static_cast<std::ptrdiff_t>(j),
                                         keys_.begin() + static_cast<std::ptrdiff_t>(end), first) -
                        keys_.begin());
                    for (size_t k = l == own ? std::max(j, i + 1) : j;
                         more && k < end && keys_[k] <= last; ++k) {
                        if (!boxes_overlap(a, boxes_[k])) continue;
                        if constexpr (std::is_same_v<decltype(visit(i, k)), bool>)
                            more = visit(i, k);
                        else
                            visit(i, k);
                    }
                }
        }
    }
}

}  // namespace wisp
