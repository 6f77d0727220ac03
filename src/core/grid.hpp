#pragma once
// A regular 3D grid of values over a box in head space with trilinear lookup (Choe & Ko
// §3.3). Node (i, j, k) sits at origin + cell · (i, j, k); dims are node counts.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/math.hpp"

namespace wisp {

// The most nodes a grid sized from the input (the solver's field and density grids, sized by
// the hair's reach and solve.cell) may have: 2^27, about 2 GiB for a vector field and its
// density. Callers check grid_nodes against it before allocating, naming the fields that
// drive the size.
inline constexpr double kMaxGridNodes = double(1 << 27);

// How many nodes a grid over `size` (cm) at `cell` has, counted as the grids count them
// (ceil(size / cell) + 1 per axis, at least 2), in double so that it cannot overflow.
inline double grid_nodes(const Vec3f& size, float cell) {
    double n = 1;
    for (int a = 0; a < 3; ++a)
        n *= std::max(2.0, std::ceil(double(size[a]) / cell) + 1);
    return n;
}

template <typename T>
class Grid3 {
  public:
    Grid3() = default;
    Grid3(const Vec3f& origin, float cell, const Vec3i& dims, const T& fill = T{})
        : origin_(origin),
          cell_(cell),
          dims_(dims),
          data_(static_cast<size_t>(dims.x()) * dims.y() * dims.z(), fill) {}

    const Vec3f& origin() const { return origin_; }
    float cell() const { return cell_; }
    const Vec3i& dims() const { return dims_; }
    size_t size() const { return data_.size(); }
    std::vector<T>& data() { return data_; }
    const std::vector<T>& data() const { return data_; }

    size_t index(int i, int j, int k) const {
        return (static_cast<size_t>(k) * dims_.y() + j) * dims_.x() + i;
    }
    T& at(int i, int j, int k) { return data_[index(i, j, k)]; }
    const T& at(int i, int j, int k) const { return data_[index(i, j, k)]; }
    Vec3f node(int i, int j, int k) const { return origin_ + cell_ * Vec3f(i, j, k); }

    // Trilinear interpolation of the eight nodes around p; p outside is clamped to the box.
    T trilinear(const Vec3f& p) const {
        const Vec3f g = (p - origin_) / cell_;
        int i[3];
        float f[3];
        for (int a = 0; a < 3; ++a) {
            const float x = std::clamp(g[a], 0.f, static_cast<float>(dims_[a] - 1));
            i[a] = std::min(static_cast<int>(x), dims_[a] - 2);
            if (i[a] < 0) i[a] = 0;
            f[a] = dims_[a] > 1 ? x - static_cast<float>(i[a]) : 0.f;
        }
        const int i1 = std::min(i[0] + 1, dims_[0] - 1), j1 = std::min(i[1] + 1, dims_[1] - 1),
                  k1 = std::min(i[2] + 1, dims_[2] - 1);
        const T c00 = at(i[0], i[1], i[2]) * (1 - f[0]) + at(i1, i[1], i[2]) * f[0];
        const T c10 = at(i[0], j1, i[2]) * (1 - f[0]) + at(i1, j1, i[2]) * f[0];
        const T c01 = at(i[0], i[1], k1) * (1 - f[0]) + at(i1, i[1], k1) * f[0];
        const T c11 = at(i[0], j1, k1) * (1 - f[0]) + at(i1, j1, k1) * f[0];
        const T c0 = c00 * (1 - f[1]) + c10 * f[1];
        const T c1 = c01 * (1 - f[1]) + c11 * f[1];
        return c0 * (1 - f[2]) + c1 * f[2];
    }

  private:
    Vec3f origin_ = Vec3f::Zero();
    float cell_ = 1.f;
    Vec3i dims_ = Vec3i::Zero();
    std::vector<T> data_;
};

}  // namespace wisp
