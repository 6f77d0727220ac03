#include "core/point_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wisp {
namespace {

// clamp(int(floor(x)), 0, n - 1), the grid coordinate of a scaled offset x, without floor
// (a libm call, or a long sequence on baseline x86-64: it was a fifth of a query's
// instructions). Above 0 truncation is the floor; at or below 0 (and NaN) both give 0.
inline int cell_coord(float x, int n) {
    if (!(x > 0.f)) return 0;
    if (x >= static_cast<float>(n - 1)) return n - 1;
    return static_cast<int>(x);
}

}  // namespace

PointGrid::PointGrid(std::span<const Vec3f> points, float cell)
    : points_(points.begin(), points.end()) {
    if (points_.empty()) return;
    Box3 box;
    for (const Vec3f& p : points_)
        box.extend(p);
    // Bound the cell count so that a tiny cell on a large set cannot exhaust memory.
    const Vec3f size = box.size() + Vec3f::Constant(1e-3f);
    const float max_cells = 4.f * static_cast<float>(points_.size()) + 64.f;
    cell_ = std::max(cell, std::cbrt(size.prod() / max_cells));
    origin_ = box.lo;
    for (int a = 0; a < 3; ++a)
        dims_[a] = std::max(1, static_cast<int>(size[a] / cell_) + 1);
    const size_t ncells = static_cast<size_t>(dims_.x()) * dims_.y() * dims_.z();
    cell_start_.assign(ncells + 1, 0);
    std::vector<uint32_t> cell_of(points_.size());
    for (size_t i = 0; i < points_.size(); ++i) {
        const Vec3f g = (points_[i] - origin_) / cell_;
        int c[3];
        for (int a = 0; a < 3; ++a)
            c[a] = std::clamp(static_cast<int>(g[a]), 0, dims_[a] - 1);
        cell_of[i] = static_cast<uint32_t>(
            (static_cast<size_t>(c[2]) * dims_.y() + c[1]) * dims_.x() + c[0]);
        ++cell_start_[cell_of[i] + 1];
    }
    for (size_t c = 0; c < ncells; ++c)
        cell_start_[c + 1] += cell_start_[c];
    items_.resize(points_.size());
    std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (size_t i = 0; i < points_.size(); ++i)
        items_[fill[cell_of[i]]++] = static_cast<uint32_t>(i);
    sorted_.resize(points_.size());
    for (size_t k = 0; k < items_.size(); ++k)
        sorted_[k] = points_[items_[k]];
}

int PointGrid::nearest(const Vec3f& q, int hint) const {
    if (points_.empty()) return -1;
    float best = std::numeric_limits<float>::infinity();
    int best_i = -1;
    // The points of cells first … last (one run of sorted_): the nearest is the least
    // (distance, index) pair over every point visited, whatever the order of the visits.
    auto visit_run = [&](size_t first, size_t last) {
        for (uint32_t k = cell_start_[first], end = cell_start_[last + 1]; k < end; ++k) {
            const float d = (sorted_[k] - q).squaredNorm();
            if (d < best || (d == best && static_cast<int>(items_[k]) < best_i)) {
                best = d;
                best_i = static_cast<int>(items_[k]);
            }
        }
    };
    auto visit = [&](size_t cell) { visit_run(cell, cell); };
    auto cell_index = [&](int x, int y, int z) {
        return (static_cast<size_t>(z) * dims_.y() + y) * dims_.x() + x;
    };
    if (hint >= 0 && static_cast<size_t>(hint) < points_.size()) {
        best = (points_[hint] - q).squaredNorm();
        best_i = hint;
    } else {
        int c[3];
        for (int a = 0; a < 3; ++a)
            c[a] = cell_coord((q[a] - origin_[a]) / cell_, dims_[a]);
        // Grow rings of cells around q's (clamped) cell until some point is found.
        const int max_ring = std::max({dims_.x(), dims_.y(), dims_.z()});
        for (int ring = 0; ring <= max_ring && best_i < 0; ++ring) {
            for (int z = std::max(c[2] - ring, 0); z <= std::min(c[2] + ring, dims_.z() - 1); ++z)
                for (int y = std::max(c[1] - ring, 0); y <= std::min(c[1] + ring, dims_.y() - 1);
                     ++y)
                    for (int x = std::max(c[0] - ring, 0);
                         x <= std::min(c[0] + ring, dims_.x() - 1); ++x)
                        if (std::max({std::abs(x - c[0]), std::abs(y - c[1]),
                                      std::abs(z - c[2])}) == ring)
                            visit(cell_index(x, y, z));
        }
    }
    // Every point closer than the best so far lies in the box of that radius around q.
    const float r = std::sqrt(best);
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = cell_coord((q[a] - r - origin_[a]) / cell_, dims_[a]);
        hi[a] = cell_coord((q[a] + r - origin_[a]) / cell_, dims_[a]);
    }
    // Row by row along x: a row's cells are one run of sorted_.
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
            visit_run(cell_index(lo[0], y, z), cell_index(hi[0], y, z));
    return best_i;
}

}  // namespace wisp
