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

// The same, with each point that eq. (1) places at master point k moved to place(k, p) (the
// clumps, groom/clumps.hpp) before it is written; the offsets d_k carry on unmoved, so eq. (1)
// is the paper's. The interpolated tip lies between the placed points on either side of it.
template <typename Place>
void grow_member_points(std::span<const Vec3f> master, std::span<const Frame> frames,
                        std::span<const float> radius, float length_u, float fuzziness, int k0,
                        int k1, Vec3f& offset, Rng& rng, std::span<Vec3f> out, Place&& place) {
    const int n = static_cast<int>(master.size());
    const float k_end = std::clamp(length_u, 0.f, 1.f) * static_cast<float>(n - 1);
    const int count = static_cast<int>(out.size());
    // Whole master points first; the last output point may be a fractional one.
    const int whole = static_cast<int>(k_end);
    const int last_whole = std::min(whole, count - 1);
    // In registers for the loop (`out` could alias `offset` as far as the compiler knows).
    Vec3f d = offset;
    Rng r = rng;
    const int end = std::min(k1, count);
    int k = std::max(k0, 0);
    if (k == 0 && end > 0) {
        out[0] = place(0, master[0] + frames[0].to_world(d));
        k = 1;
    }
    for (; k < std::min(end, last_whole + 1); ++k) {
        d = next_offset(d, radius[k - 1], radius[k], fuzziness, r);
        out[k] = place(k, master[k] + frames[k].to_world(d));
    }
    if (k < end) {
        // k = last_whole + 1: the tip interpolated between master points `whole` and
        // `whole + 1` (or a very short member whose whole part is 0).
        const int m = std::min(k, n - 1);
        const Vec3f d_next = next_offset(d, radius[m - 1], radius[m], fuzziness, r);
        const Vec3f a = out[last_whole];
        const Vec3f b = place(m, master[m] + frames[m].to_world(d_next));
        const float f = std::clamp(k_end - static_cast<float>(last_whole), 0.f, 1.f);
        out[k] = a + f * (b - a);
    }
    offset = d;
    rng = r;
}

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
