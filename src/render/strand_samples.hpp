#pragma once
// Walking a strand's Catmull-Rom curve (core/catmull_rom.hpp, pinned ends) in small
// straight pieces, shared by the shadow map and the rasterizer so both see the same curve
// and the same tapered width.
#include <algorithm>
#include <cmath>
#include <span>

#include "core/catmull_rom.hpp"
#include "core/hair.hpp"
#include "core/math.hpp"

namespace wisp {

// Width multiplier at curve parameter s in [0, 1] (0 root, 1 tip): 1 up to mid-length,
// then easing down to tip_fraction at the tip, as a hair fibre tapers.
inline float taper_factor(float s, float tip_fraction) {
    const float k = std::clamp(2.f * s - 1.f, 0.f, 1.f);
    return 1.f - (1.f - tip_fraction) * k * k;
}

// The four control points of segment i (between points[i] and points[i+1]) with the
// phantom end points of the pinned spline.
inline void catmull_rom_segment(std::span<const Vec3f> p, size_t i, Vec3f& a, Vec3f& b, Vec3f& c,
                                Vec3f& d) {
    const size_t n = p.size();
    b = p[i];
    c = p[i + 1];
    a = i > 0 ? p[i - 1] : Vec3f(2.f * b - c);
    d = i + 2 < n ? p[i + 2] : Vec3f(2.f * c - b);
}

// One sample of a strand: position (cm), tangent (unit, towards the tip), curve parameter s
// in [0, 1], diameter (cm, tapered), and where it lies: on segment `segment` (between control
// points segment and segment + 1 of the strand) at parameter u in [0, 1].
struct StrandSample {
    Vec3f p;
    Vec3f t;
    float s;
    float width;
    int segment;
    float u;
};

// Calls visit(const StrandSample&) for the samples of strand `strand` of `hair`: for each
// segment i, sub(i, p_i, p_i+1) ≥ 1 evenly spaced samples (u = j / sub, j < sub), then the
// tip. A strand of one point yields that point alone. Widths interpolate the per-point
// widths linearly and are multiplied by width_scale · taper_factor(s, tip_fraction).
// Tangents are computed only if kTangents (otherwise t is zero).
template <bool kTangents = true, typename Sub, typename Visit>
void for_each_strand_sample(const Hair& hair, size_t strand, float width_scale, float tip_fraction,
                            Sub&& sub, Visit&& visit) {
    const std::span<const Vec3f> p = hair.strand(strand);
    const size_t n = p.size(), first = hair.offsets[strand];
    if (n == 0) return;
    const bool has_widths = !hair.widths.empty();
    auto width_at = [&](size_t i) {
        return has_widths ? hair.widths[first + i] : hair.default_width;
    };
    if (n == 1) {
        visit(StrandSample{p[0], Vec3f::UnitY(), 0.f, width_at(0) * width_scale, 0, 0.f});
        return;
    }
    const float inv_segments = 1.f / static_cast<float>(n - 1);
    Vec3f last_t = Vec3f::Zero();
    auto unit = [&](const Vec3f& v) {
        const float len2 = v.squaredNorm();
        if (len2 > 1e-24f) last_t = v / std::sqrt(len2);
        return last_t;
    };
    if (kTangents) last_t = (p[1] - p[0]).normalized();
    for (size_t i = 0; i + 1 < n; ++i) {
        Vec3f a, b, c, d;
        catmull_rom_segment(p, i, a, b, c, d);
        // The segment as a cubic: b + k1 u + k2 u² + k3 u³ (core/catmull_rom.hpp).
        const Vec3f k1 = 0.5f * (c - a);
        const Vec3f k2 = a - 2.5f * b + 2.f * c - 0.5f * d;
        const Vec3f k3 = 0.5f * (d - a) + 1.5f * (b - c);
        const int m = std::max(1, static_cast<int>(sub(i, b, c)));
        const float w0 = width_at(i), w1 = width_at(i + 1);
        const float inv_m = 1.f / static_cast<float>(m);
        for (int j = 0; j < m; ++j) {
            const float u = static_cast<float>(j) * inv_m;
            const float s = (static_cast<float>(i) + u) * inv_segments;
            const Vec3f pos = b + u * (k1 + u * (k2 + u * k3));
            const Vec3f t = kTangents ? unit(k1 + u * (2.f * k2 + 3.f * u * k3)) : Vec3f::Zero();
            visit(StrandSample{pos, t, s,
                               (w0 + (w1 - w0) * u) * width_scale * taper_factor(s, tip_fraction),
                               static_cast<int>(i), u});
        }
        if (i + 2 == n) {
            const Vec3f t = kTangents ? unit(k1 + 2.f * k2 + 3.f * k3) : Vec3f::Zero();
            visit(
                StrandSample{c, t, 1.f, w1 * width_scale * tip_fraction, static_cast<int>(i), 1.f});
        }
    }
}

}  // namespace wisp
