#pragma once
// Member strands from a master (Choe & Ko §2.1, eq. (1), Fig. 4).
#include <algorithm>
#include <cstdint>
#include <span>

#include "core/math.hpp"
#include "core/rng.hpp"

namespace wisp {

// Eq. (1) with the noise of Fig. 4: d_k = (r_k / r_{k-1}) d_{k-1} + y·x̄, with x̄ a random
// unit vector and y uniform in [0, min(L, σ·r_k)], L the distance from the point
// p_k^O = (r_k / r_{k-1}) d_{k-1} along x̄ to the sphere of radius r_k. Keeps |d_k| ≤ r_k
// whenever |d_{k-1}| ≤ r_{k-1}. Offsets are in the master's local frame.
inline Vec3f next_offset(const Vec3f& d_prev, float r_prev, float r, float fuzziness, Rng& rng) {
    const Vec3f o = r_prev > 0.f ? Vec3f(d_prev * (r / r_prev)) : Vec3f::Zero();
    const Vec3f x = rng.unit_vector();
    // Ray o + y·x against |p| = r: y² + 2(o·x)y + |o|² − r² = 0, the positive root.
    const float b = o.dot(x);
    const float c = o.squaredNorm() - r * r;
    const float disc = std::max(0.f, b * b - c);
    const float reach = std::max(0.f, -b + std::sqrt(disc));
    const float y = rng.uniform() * std::min(reach, fuzziness * r);
    return o + y * x;
}

// Grows one member strand.
//   master       #n control points of the master
//   frames       #n frames of the master at each control point
//   radius       #n deviation radius r_k at each master point, cm, > 0
//   root_offset  d_1 in the frame of the master root (|d_1| ≤ radius[0])
//   length_u     relative length u in (0, 1]
//   out          #member_point_count(n, u) control points
void grow_member(std::span<const Vec3f> master, std::span<const Frame> frames,
                 std::span<const float> radius, const Vec3f& root_offset, float length_u,
                 float fuzziness, Rng& rng, std::span<Vec3f> out);

// grow_member's points k0 ≤ k < k1 only (those of out), carrying on from where the call for
// the points before k0 left `offset` and `rng` (for k0 = 0: the root offset d_1 and the
// strand's fresh stream). It reads master points and frames below k1 alone, so a member can
// grow in bands of points as the solve makes its master's joints final; any split into bands
// gives grow_member's points to the bit. Point k of a member lies on master point k; the
// interpolated tip (member_point_count) also reads the point before it.
void grow_member_points(std::span<const Vec3f> master, std::span<const Frame> frames,
                        std::span<const float> radius, float length_u, float fuzziness, int k0,
                        int k1, Vec3f& offset, Rng& rng, std::span<Vec3f> out);

// How many of a member's leading points (of `count`, grown on a master of n points to relative
// length u) no later band of grow_member_points reads, once the points below k1 are grown: all
// of them but the last whole point while the interpolated tip after it is still to grow.
inline int member_points_settled(int n, float u, int count, int k1) {
    const int whole = static_cast<int>(std::clamp(u, 0.f, 1.f) * static_cast<float>(n - 1));
    const int last_whole = std::min(whole, count - 1);
    const int grown = std::min(k1, count);
    return grown == last_whole + 1 && last_whole + 1 < count ? grown - 1 : grown;
}

// Number of control points of a member of relative length u on a master of n points: the
// master points up to u·(n−1), plus one interpolated end point when u·(n−1) is fractional.
inline uint32_t member_point_count(int n, float u) {
    const float k = std::clamp(u, 0.f, 1.f) * static_cast<float>(n - 1);
    const int whole = static_cast<int>(k);
    const bool frac = k - static_cast<float>(whole) > 1e-3f;
    return static_cast<uint32_t>(std::max(2, whole + 1 + (frac ? 1 : 0)));
}

}  // namespace wisp
