#include "core/point_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace wisp {

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
}

int PointGrid::nearest(const Vec3f& q) const {
    if (points_.empty()) return -1;
    const Vec3f g = (q - origin_) / cell_;
    int c[3];
    for (int a = 0; a < 3; ++a)
        c[a] = std::clamp(static_cast<int>(std::floor(g[a])), 0, dims_[a] - 1);
    // Distance from q to the outside of the clamped cell's block, so that rings grow until
    // no unvisited cell can hold a closer point.
    float best = std::numeric_limits<float>::infinity();
    int best_i = -1;
    const int max_ring = std::max({dims_.x(), dims_.y(), dims_.z()});
    for (int ring = 0; ring <= max_ring; ++ring) {
        for (int z = c[2] - ring; z <= c[2] + ring; ++z) {
            if (z < 0 || z >= dims_.z()) continue;
            for (int y = c[1] - ring; y <= c[1] + ring; ++y) {
                if (y < 0 || y >= dims_.y()) continue;
                for (int x = c[0] - ring; x <= c[0] + ring; ++x) {
                    if (x < 0 || x >= dims_.x()) continue;
                    if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) !=
                        ring)
                        continue;
                    const size_t cell = (static_cast<size_t>(z) * dims_.y() + y) * dims_.x() + x;
                    for (uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
                        const uint32_t i = items_[k];
                        const float d = (points_[i] - q).squaredNorm();
                        if (d < best || (d == best && static_cast<int>(i) < best_i)) {
                            best = d;
                            best_i = static_cast<int>(i);
                        }
                    }
                }
            }
        }
        // Every point in rings > ring is at least `ring * cell` away from q's cell block
        // (q may lie outside the grid box; measure from the clamped cell conservatively).
        if (best_i >= 0) {
            Vec3f lo = origin_ + cell_ * Vec3f(c[0] - ring, c[1] - ring, c[2] - ring);
            Vec3f hi = origin_ + cell_ * Vec3f(c[0] + ring + 1, c[1] + ring + 1, c[2] + ring + 1);
            float margin = std::numeric_limits<float>::infinity();
            for (int a = 0; a < 3; ++a)
                margin = std::min({margin, q[a] - lo[a], hi[a] - q[a]});
            if (margin > 0 && margin * margin >= best) break;
        }
    }
    return best_i;
}

}  // namespace wisp
