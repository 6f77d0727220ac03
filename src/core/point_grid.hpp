#pragma once
// Nearest-neighbour queries over a fixed set of 3D points with a uniform hash grid.
// Used to assign member roots to the Voronoi region of the nearest master root (Choe &
// Ko §2.3) and for Lloyd relaxation. Queries are const and thread-safe.
#include <span>
#include <vector>

#include "core/math.hpp"

namespace wisp {

class PointGrid {
  public:
    PointGrid() = default;
    // points  #N positions; cell  the grid spacing (about the typical spacing), > 0.
    PointGrid(std::span<const Vec3f> points, float cell);

    // Index of the point nearest to q (ties: the lowest index); -1 if the set is empty.
    // `hint`, a point likely to be near (e.g. last iteration's answer), only speeds it up.
    int nearest(const Vec3f& q, int hint = -1) const;

  private:
    std::vector<Vec3f> points_;
    Vec3f origin_ = Vec3f::Zero();
    float cell_ = 1.f;
    Vec3i dims_ = Vec3i::Zero();
    std::vector<uint32_t> cell_start_;  // #cells+1, CSR into items_ and sorted_
    std::vector<uint32_t> items_;       // point indices sorted by cell
    // points_[items_[k]]: the points in cell order, so that a row of cells along x is one
    // contiguous run that a query scans without indirection.
    std::vector<Vec3f> sorted_;
};

}  // namespace wisp
