#pragma once
// A hair reflectance with the lobes of real hair, cheap enough for every strand vertex: the
// three longitudinal lobes of Marschner et al. ("Light Scattering from Human Hair Fibers",
// SIGGRAPH 2003, §4) in the shifted Kajiya-Kay form that real-time hair renderers ship
// (Scheuermann, "Hair Rendering and Shading", GDC 2004), plus Kajiya-Kay's diffuse term.
//
//   R    the primary highlight, reflected off the cuticle: uncoloured and narrow. The
//        cuticle's scales tilt toward the tip, so the lobe is shifted toward the root.
//   TRT  the secondary highlight, refracted in, reflected off the back of the fibre and out:
//        tinted by the hair's colour, broader, shifted toward the tip.
//   TT   transmission, refracted through: light from behind the hair, seen through it,
//        tinted; it makes backlit hair glow.
//
// Angles are those of Marschner et al.: θ from the plane normal to the tangent t (which
// points from root to tip), positive toward the tip, so sin θ_i = t·l and sin θ_r = t·e.
// A lobe shifted by α peaks where θ_h = (θ_i + θ_r)/2 = α. It is cos(θ_i + θ_r − 2α)^n, a
// Gaussian in θ_h of width β = 1/(2√n) near its peak, computed from the two sines without
// trigonometry. Each lobe peaks at its weight; with the weights summing to at most 1 and
// colours in [0, 1], no channel reflects more than the light brings.
#include <algorithm>
#include <cmath>

#include "core/math.hpp"
#include "render/kajiya_kay.hpp"

namespace wisp {

struct HairLobes {
    float diffuse = 0.5f;             // k_d, times the strand's colour
    float primary = 0.12f;            // k_R, uncoloured
    float primary_shift = -5.f;       // α_R, degrees (negative: toward the root)
    float primary_width = 5.f;        // β_R, degrees
    float secondary = 0.22f;          // k_TRT, times the strand's colour
    float secondary_shift = 7.5f;     // α_TRT = −1.5 α_R, degrees (toward the tip)
    float secondary_width = 9.f;      // β_TRT, degrees
    float transmission = 0.08f;       // k_TT, times the strand's colour
    float transmission_shift = 2.5f;  // α_TT = −α_R / 2, degrees
    float transmission_width = 12.f;  // β_TT, degrees, and its spread around the back
    float sparkle = 0.35f;  // per-strand variation of the secondary: its strength varies by
                            // ± this fraction and its shift by ± this × its width
};

// The exponent n of cos(·)^n that gives a lobe of width β (degrees): n = 1 / (4 β²).
inline float lobe_exponent(float width_degrees) {
    const float beta = std::max(width_degrees, 0.1f) * kPi / 180.f;
    return 1.f / (4.f * beta * beta);
}

// One lobe's shift, prepared: cos 2α and sin 2α.
struct LobeShift {
    float c = 1.f, s = 0.f;
    static LobeShift degrees(float alpha) {
        const float a = 2.f * alpha * kPi / 180.f;
        return {std::cos(a), std::sin(a)};
    }
};

// cos(θ_i + θ_r − 2α) from sin θ_i = t·l and sin θ_r = t·e.
inline float shifted_cone_cosine(float sin_i, float sin_r, const LobeShift& shift) {
    const float cos_i = sin_from_cos(sin_i), cos_r = sin_from_cos(sin_r);
    const float cos_sum = cos_i * cos_r - sin_i * sin_r;  // cos(θ_i + θ_r)
    const float sin_sum = sin_i * cos_r + cos_i * sin_r;  // sin(θ_i + θ_r)
    return cos_sum * shift.c + sin_sum * shift.s;
}

// A lobe's value: max(0, cosine)^n, skipped (0) below `floor`, where it would be invisible.
inline float lobe(float cosine, float exponent, float floor = 0.f) {
    return cosine > floor && cosine > 0.f ? std::pow(cosine, exponent) : 0.f;
}

// The lobes prepared once per render (exponents, shifts, visibility floors), then varied per
// strand by with_sparkle().
struct HairLobeSet {
    float k_d = 0, k_r = 0, k_trt = 0, k_tt = 0;
    float n_r = 1, n_trt = 1, n_tt = 1;
    LobeShift r, trt, tt;
    float floor_r = 0, floor_trt = 0, floor_tt = 0;

    HairLobeSet() = default;
    explicit HairLobeSet(const HairLobes& h) {
        k_d = h.diffuse;
        k_r = h.primary;
        k_trt = h.secondary;
        k_tt = h.transmission;
        n_r = lobe_exponent(h.primary_width);
        n_trt = lobe_exponent(h.secondary_width);
        n_tt = lobe_exponent(h.transmission_width);
        r = LobeShift::degrees(h.primary_shift);
        trt = LobeShift::degrees(h.secondary_shift);
        tt = LobeShift::degrees(h.transmission_shift);
        // Below 1/4096 of its peak a lobe adds nothing an 8-bit picture shows.
        floor_r = std::pow(1.f / 4096.f, 1.f / n_r);
        floor_trt = std::pow(1.f / 4096.f, 1.f / n_trt);
        floor_tt = std::pow(1.f / 4096.f, 1.f / n_tt);
    }
    // These lobes with the secondary varied by a strand's `variation` in [−1, 1].
    HairLobeSet with_sparkle(const HairLobes& h, float variation) const {
        HairLobeSet out = *this;
        out.k_trt = h.secondary * (1.f + h.sparkle * variation);
        out.trt = LobeShift::degrees(h.secondary_shift + h.sparkle * variation * h.secondary_width);
        return out;
    }
    HairLobeSet(const HairLobes& h, float variation) {
        *this = HairLobeSet(h).with_sparkle(h, variation);
    }
};

// Reflectance of a strand with unit tangent t (root to tip) and colour `color` (linear, in
// [0, 1]) for a unit light from unit direction l seen from unit direction e.
inline Vec3f hair_reflectance(const Vec3f& t, const Vec3f& l, const Vec3f& e, const Vec3f& color,
                              const HairLobeSet& k) {
    const float sin_i = std::clamp(t.dot(l), -1.f, 1.f), sin_r = std::clamp(t.dot(e), -1.f, 1.f);
    const float r = lobe(shifted_cone_cosine(sin_i, sin_r, k.r), k.n_r, k.floor_r);
    const float trt = lobe(shifted_cone_cosine(sin_i, sin_r, k.trt), k.n_trt, k.floor_trt);
    float tt = 0.f;
    if (k.k_tt > 0.f) {
        // Transmission goes forward: the light and the eye on opposite sides of the strand
        // (azimuth φ = π), spreading over about the lobe's width around it.
        const Vec3f lp = l - sin_i * t, ep = e - sin_r * t;
        const float norm = std::sqrt(lp.squaredNorm() * ep.squaredNorm());
        const float back = norm > 1e-8f ? -lp.dot(ep) / norm : 0.f;  // −cos φ
        if (back > 0.f)
            tt = lobe(shifted_cone_cosine(sin_i, sin_r, k.tt), k.n_tt, k.floor_tt) *
                 std::pow(back, 0.25f * k.n_tt);
    }
    const float diffuse = k.k_d * sin_from_cos(sin_i);
    return Vec3f::Constant(k.k_r * r) + (diffuse + k.k_trt * trt + k.k_tt * tt) * color;
}

}  // namespace wisp
