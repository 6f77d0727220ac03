#pragma once
// Uniform Catmull-Rom splines, the strand representation of Choe & Ko §2.1: the curve
// passes through every control point p1..pn, p(0) = p1 (root), p(1) = pn (tip). The end
// segments use phantom points p0 = 2 p1 - p2 and p(n+1) = 2 pn - p(n-1), which is what
// USD's `wrap = "pinned"` catmullRom curves do, so exported curves match exactly.
#include <span>

#include "core/math.hpp"

namespace wisp {

// Point on the segment between p1 and p2 at t in [0, 1].
inline Vec3f catmull_rom(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, const Vec3f& p3,
                         float t) {
    const float t2 = t * t, t3 = t2 * t;
    return 0.5f * ((2.f * p1) + (-p0 + p2) * t + (2.f * p0 - 5.f * p1 + 4.f * p2 - p3) * t2 +
                   (-p0 + 3.f * p1 - 3.f * p2 + p3) * t3);
}

// Derivative d/dt of the segment above.
inline Vec3f catmull_rom_tangent(const Vec3f& p0, const Vec3f& p1, const Vec3f& p2, const Vec3f& p3,
                                 float t) {
    const float t2 = t * t;
    return 0.5f * ((-p0 + p2) + 2.f * (2.f * p0 - 5.f * p1 + 4.f * p2 - p3) * t +
                   3.f * (-p0 + 3.f * p1 - 3.f * p2 + p3) * t2);
}

// Point of the pinned spline through `points` (#n ≥ 1) at s in [0, 1].
Vec3f catmull_rom_eval(std::span<const Vec3f> points, float s);

// Tangent (not normalized, per unit s) of the pinned spline at s in [0, 1].
Vec3f catmull_rom_derivative(std::span<const Vec3f> points, float s);

// Samples the pinned spline through `points` (#n ≥ 2) with `per_segment` samples per
// segment into out (#(n-1)·per_segment + 1), first = p1, last = pn.
void catmull_rom_sample(std::span<const Vec3f> points, int per_segment, std::span<Vec3f> out);

// Resamples a strand (points #n >= 1; widths #n, or empty for the constant `width`) to
// out_points and out_widths (#N each): N points evenly spaced in arc length along the pinned
// spline through the points (measured on 8 samples per segment), root and tip exact; widths
// are linear in the spline parameter between control points. A 1-point strand repeats its
// point. Uses a per-thread scratch, no allocation per call once warm.
void catmull_rom_resample(std::span<const Vec3f> points, std::span<const float> widths, float width,
                          std::span<Vec3f> out_points, std::span<float> out_widths);

}  // namespace wisp
