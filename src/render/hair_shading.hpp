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
#include <cstdint>
#include <cstring>

#include "core/math.hpp"
#include "render/kajiya_kay.hpp"

namespace wisp {

struct HairLobes {
    float diffuse = 0.5f;             // k_d, times the strand's colour
    float primary = 0.05f;            // k_R, uncoloured: Marschner's R at its peak, ¼ F(η = 1.55)
                                      // g(0; β_R) ≈ ¼ · 0.046 · 4.6 (β_R = 5°), ≈ 0.05
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
    // Per-strand variation of the primary's shift, ± this × its width: neighbouring fibres
    // tilt by a few degrees, so a sheet of hair shows its sheen strand by strand instead of as
    // one even grey film.
    float primary_jitter = 1.f;
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

// x^n for x in (0, 1] and n ≥ 0, within 10⁻⁶ of std::pow (absolute; 5·10⁻⁶ relative to the
// value where it is above 1/4096, tested for n up to 1000 in hair_shading_test.cpp), in
// about a third of its instructions: exp2(n · log2 x), each from a short series.
// log2 x = e + log2 m with m in [√½, √2), log m = 2 atanh s, s = (m − 1)/(m + 1), |s| < 0.172
// (four terms, error < 2·10⁻⁸); 2^y = 2^i · 2^f with f in [−½, ½] (Taylor to f⁶, relative
// error < 2·10⁻⁷). Results below 2⁻¹²⁶ are 0.
[[gnu::always_inline]] inline float pow_unit(float x, float n) {
    if (!(x > 0.f)) return 0.f;
    uint32_t bits;
    std::memcpy(&bits, &x, 4);
    // Split x = 2^e · m, m in [√½, √2): move the mantissa's top half down an octave.
    const uint32_t shifted = bits - 0x3f3504f3u;  // bits of √½
    const int e = static_cast<int>(shifted) >> 23;
    bits -= static_cast<uint32_t>(e) << 23;
    float m;
    std::memcpy(&m, &bits, 4);
    const float s = (m - 1.f) / (m + 1.f), s2 = s * s;
    const float ln_m = 2.f * s * (1.f + s2 * (1.f / 3.f + s2 * (1.f / 5.f + s2 * (1.f / 7.f))));
    const float y = n * (static_cast<float>(e) + ln_m * 1.44269504f);  // n · log2 x
    if (y < -126.f) return 0.f;
    // Round to nearest by the float adder (1.5·2²³ leaves no fraction bits): no libm call.
    const float i = (y + 12582912.f) - 12582912.f, f = (y - i) * 0.693147181f;  // 2^(y−i) = e^f
    const float ef =
        1.f + f * (1.f + f * (0.5f + f * (1.f / 6.f + f * (1.f / 24.f + f * (1.f / 120.f +
                                                                             f * (1.f / 720.f))))));
    const uint32_t scale = static_cast<uint32_t>(static_cast<int>(i) + 127) << 23;
    float two_i;
    std::memcpy(&two_i, &scale, 4);
    return ef * two_i;
}

// A lobe's value: max(0, cosine)^n, skipped (0) below `floor`, where it would be invisible.
inline float lobe(float cosine, float exponent, float floor = 0.f) {
    return cosine > floor && cosine > 0.f ? pow_unit(std::min(cosine, 1.f), exponent) : 0.f;
}

// The lobes prepared once per render (exponents, shifts, visibility floors), then varied per
// strand by with_sparkle().
struct HairLobeSet {
    float k_d = 0, k_r = 0, k_trt = 0, k_tt = 0;
    float n_r = 1, n_trt = 1, n_tt = 1;
    LobeShift r, trt, tt;
    float floor_r = 0, floor_trt = 0, floor_tt = 0;
    // With `azimuthal`, R and TRT are weighted by Marschner's azimuthal spread of reflection,
    // cos(φ/2) (φ the azimuth between the light and the eye around the fibre: 1 with the
    // light beside the eye, 0 with it straight behind the fibre), and there is no diffuse
    // term (it has no azimuth). For a back light, which lights a strand's far side: the
    // renderer's rim light.
    bool azimuthal = false;

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
    // These lobes with the secondary varied by a strand's `variation` in [−1, 1], and the
    // primary's shift by its `primary_variation` in [−1, 1].
    HairLobeSet with_sparkle(const HairLobes& h, float variation,
                             float primary_variation = 0.f) const {
        HairLobeSet out = *this;
        if (primary_variation != 0.f)
            out.r = LobeShift::degrees(h.primary_shift +
                                       h.primary_jitter * primary_variation * h.primary_width);
        out.k_trt = h.secondary * (1.f + h.sparkle * variation);
        out.trt = LobeShift::degrees(h.secondary_shift + h.sparkle * variation * h.secondary_width);
        return out;
    }
    HairLobeSet(const HairLobes& h, float variation) {
        *this = HairLobeSet(h).with_sparkle(h, variation);
    }
};

// The terms of hair_reflectance that depend on the eye and not on the light, computed once
// per shaded point and shared by every light: the tangent t (unit, root to tip), sin θ_r =
// t·e, cos θ_r, and e's projection on the plane normal to t (the azimuth's reference) with its
// squared length.
struct HairView {
    Vec3f t;
    float sin_r, cos_r;
    Vec3f ep;
    float ep2;
    HairView(const Vec3f& tangent, const Vec3f& e)
        : t(tangent),
          sin_r(std::clamp(tangent.dot(e), -1.f, 1.f)),
          cos_r(sin_from_cos(sin_r)),
          ep(e - sin_r * tangent),
          ep2(ep.squaredNorm()) {}
};

// Reflectance of a strand seen as `v` (HairView: tangent t, eye direction e) with colour `color`
// (linear, in [0, 1]) for a unit light from unit direction l. The lobes (R, TRT, TT), not the
// diffuse term, are scaled by lobe_scale.
inline Vec3f hair_reflectance(const HairView& v, const Vec3f& l, const Vec3f& color,
                              const HairLobeSet& k, float lobe_scale = 1.f) {
    const Vec3f& t = v.t;
    const float sin_i = std::clamp(t.dot(l), -1.f, 1.f), sin_r = v.sin_r;
    // The three lobes share cos(θ_i + θ_r) and sin(θ_i + θ_r) (shifted_cone_cosine, inlined).
    const float cos_i = sin_from_cos(sin_i), cos_r = v.cos_r;
    const float cos_sum = cos_i * cos_r - sin_i * sin_r;
    const float sin_sum = sin_i * cos_r + cos_i * sin_r;
    auto cone = [&](const LobeShift& shift) { return cos_sum * shift.c + sin_sum * shift.s; };
    float r = lobe(cone(k.r), k.n_r, k.floor_r);
    float trt = lobe(cone(k.trt), k.n_trt, k.floor_trt);
    const float tt_cosine = k.k_tt > 0.f ? cone(k.tt) : 0.f;
    float tt = 0.f, diffuse = k.k_d * cos_i;
    if (tt_cosine > k.floor_tt || (k.azimuthal && r + trt > 0.f)) {
        const Vec3f lp = l - sin_i * t;
        const float norm2 = lp.squaredNorm() * v.ep2;
        const float back = norm2 > 1e-16f ? -lp.dot(v.ep) / std::sqrt(norm2) : 0.f;  // −cos φ
        // Transmission goes forward: the light and the eye on opposite sides of the strand
        // (azimuth φ = π), spreading over about the lobe's width around it.
        if (back > 0.f && tt_cosine > k.floor_tt)
            tt = lobe(tt_cosine, k.n_tt) * pow_unit(back, 0.25f * k.n_tt);
        if (k.azimuthal) {
            const float spread = std::sqrt(std::max(0.f, 0.5f * (1.f - back)));  // cos(φ/2)
            r *= spread;
            trt *= spread;
        }
    }
    if (k.azimuthal) diffuse = 0.f;
    return Vec3f::Constant(lobe_scale * k.k_r * r) +
           (diffuse + lobe_scale * (k.k_trt * trt + k.k_tt * tt)) * color;
}

// The same for unit tangent t (root to tip) seen from unit direction e.
inline Vec3f hair_reflectance(const Vec3f& t, const Vec3f& l, const Vec3f& e, const Vec3f& color,
                              const HairLobeSet& k, float lobe_scale = 1.f) {
    return hair_reflectance(HairView(t, e), l, color, k, lobe_scale);
}

}  // namespace wisp
