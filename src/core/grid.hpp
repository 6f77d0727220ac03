#pragma once
// A regular 3D grid of values over a box in head space with trilinear lookup (Choe & Ko
// §3.3). Node (i, j, k) sits at origin + cell · (i, j, k); dims are node counts.
#include <algorithm>
#include <cmath>
#include <concepts>
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
        const Corner c = corner(p);
        const T* v = data_.data() + c.index;
        const float* f = c.f;
        // The eight nodes by index steps from the first, sparing at()'s index arithmetic per
        // node (the solver and the push out of the head look up millions of points); the
        // textbook formula's operations in its order, so the value is the same to the bit.
        const T c00 = v[0] * (1 - f[0]) + v[c.step[0]] * f[0];
        const T c10 = v[c.step[1]] * (1 - f[0]) + v[c.step[1] + c.step[0]] * f[0];
        const T c01 = v[c.step[2]] * (1 - f[0]) + v[c.step[2] + c.step[0]] * f[0];
        const T c11 =
            v[c.step[2] + c.step[1]] * (1 - f[0]) + v[c.step[2] + c.step[1] + c.step[0]] * f[0];
        const T c0 = c00 * (1 - f[1]) + c10 * f[1];
        const T c1 = c01 * (1 - f[1]) + c11 * f[1];
        return c0 * (1 - f[2]) + c1 * f[2];
    }

    // The same value, and its exact gradient (per cm) in *gradient: the derivative of the
    // trilinear interpolant inside the cell holding p (one-sided on a cell face), zero along
    // an axis where p lies outside the box (the clamped value does not change there).
    T trilinear(const Vec3f& p, Vec3f* gradient) const requires std::same_as<T, float> {
        const Corner c = corner(p);
        const T* v = data_.data() + c.index;
        const float* f = c.f;
        const size_t x = c.step[0], y = c.step[1], z = c.step[2];
        const T v000 = v[0], v100 = v[x];
        const T v010 = v[y], v110 = v[y + x];
        const T v001 = v[z], v101 = v[z + x];
        const T v011 = v[z + y], v111 = v[z + y + x];
        // The same operations in the same order as trilinear(p), so the values agree exactly.
        const T c00 = v000 * (1 - f[0]) + v100 * f[0];
        const T c10 = v010 * (1 - f[0]) + v110 * f[0];
        const T c01 = v001 * (1 - f[0]) + v101 * f[0];
        const T c11 = v011 * (1 - f[0]) + v111 * f[0];
        const T c0 = c00 * (1 - f[1]) + c10 * f[1];
        const T c1 = c01 * (1 - f[1]) + c11 * f[1];
        if (gradient) {
            const T dx00 = v100 - v000, dx10 = v110 - v010, dx01 = v101 - v001, dx11 = v111 - v011;
            const T dx0 = dx00 * (1 - f[1]) + dx10 * f[1];
            const T dx1 = dx01 * (1 - f[1]) + dx11 * f[1];
            const T dy0 = c10 - c00, dy1 = c11 - c01;
            const float inv = 1.f / cell_;
            (*gradient)[0] = c.inside[0] ? (dx0 * (1 - f[2]) + dx1 * f[2]) * inv : T{};
            (*gradient)[1] = c.inside[1] ? (dy0 * (1 - f[2]) + dy1 * f[2]) * inv : T{};
            (*gradient)[2] = c.inside[2] ? (c1 - c0) * inv : T{};
        }
        return c0 * (1 - f[2]) + c1 * f[2];
    }

  private:
    // The cell a lookup at p reads: the index of its first node, the index step to its far
    // node along each axis (0 along an axis of one node, which the lookup then reads twice),
    // p's fractions within it (p clamped to the box) and whether p lay inside along each axis.
    // Always inline: where a caller looks up several points (push_out_of_head), GCC otherwise
    // calls it, and the call and the 56-byte result cost as much as the arithmetic.
    struct Corner {
        size_t index;
        size_t step[3];
        float f[3];
        bool inside[3];
    };
    [[gnu::always_inline]] Corner corner(const Vec3f& p) const {
        const Vec3f g = (p - origin_) / cell_;
        Corner c;
        int i[3];
        size_t stride = 1;
        for (int a = 0; a < 3; ++a) {
            const float x = std::clamp(g[a], 0.f, static_cast<float>(dims_[a] - 1));
            c.inside[a] = g[a] == x && dims_[a] > 1;
            i[a] = std::min(static_cast<int>(x), dims_[a] - 2);
            if (i[a] < 0) i[a] = 0;
            c.f[a] = dims_[a] > 1 ? x - static_cast<float>(i[a]) : 0.f;
            c.step[a] = dims_[a] > 1 ? stride : 0;
            stride *= static_cast<size_t>(dims_[a]);
        }
        c.index = index(i[0], i[1], i[2]);
        return c;
    }

    Vec3f origin_ = Vec3f::Zero();
    float cell_ = 1.f;
    Vec3i dims_ = Vec3i::Zero();
    std::vector<T> data_;
};

}  // namespace wisp
