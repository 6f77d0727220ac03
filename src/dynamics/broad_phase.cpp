#include "dynamics/broad_phase.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>

namespace wisp {

void BoxGrid::build(std::span<const Box4> boxes, float cell) {
    cell_ = cell;
    entries_.clear();
    entries_.reserve(boxes.size());
    for (size_t i = 0; i < boxes.size(); ++i) {
        const Box4& box = boxes[i];
        if (!box.lo.allFinite() || !box.hi.allFinite()) continue;
        const float extent = (box.hi - box.lo).head<3>().maxCoeff();
        int level = 0;
        float width = cell;
        while (width < extent && level + 1 < kLevels) {
            width *= 2;
            ++level;
        }
        if (width < extent) continue;
        int64_t xyz[3];
        bool inside = true;
        for (int axis = 0; axis < 3; ++axis) {
            xyz[axis] =
                static_cast<int64_t>(std::floor(0.5f * (box.lo[axis] + box.hi[axis]) / width)) +
                kCellOffset;
            inside = inside && xyz[axis] >= 0 && xyz[axis] <= kCellMax;
        }
        if (inside) entries_.push_back({key(level, xyz[0], xyz[1], xyz[2]), uint32_t(i)});
    }
    // (key, index) pairs are distinct: the order is total, the same whoever sorts.
    tbb::parallel_sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
        return a.key != b.key ? a.key < b.key : a.index < b.index;
    });
    const size_t count = entries_.size();
    keys_.resize(count);
    boxes_.resize(count);
    index_.resize(count);
    for (size_t e = 0; e < count; ++e) {
        keys_[e] = entries_[e].key;
        index_[e] = entries_[e].index;
        boxes_[e] = boxes[entries_[e].index];
    }
    for (size_t l = 0, e = 0; l <= kLevels; ++l) {
        while (e < count && level_of(keys_[e]) < static_cast<int>(l))
            ++e;
        level_begin_[l] = e;
    }
}

void BoxGrid::cell_range(const Box4& box, float width, int64_t from[3], int64_t to[3]) const {
    // Boxes at this level are at most `width` wide: the centres of those that may meet `box`
    // lie within half a cell of it.
    const float inv = 1 / width, half = 0.5f * width;
    for (int axis = 0; axis < 3; ++axis) {
        const float lo = std::floor((box.lo[axis] - half) * inv);
        const float hi = std::floor((box.hi[axis] + half) * inv);
        from[axis] = std::max<int64_t>(0, static_cast<int64_t>(lo) + kCellOffset);
        to[axis] = std::min(kCellMax, static_cast<int64_t>(hi) + kCellOffset);
    }
}

}  // namespace wisp
