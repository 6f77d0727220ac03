#include "render/hair_shading.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.hpp"

namespace wisp {
namespace {

float radians(float degrees) {
    return degrees * kPi / 180.f;
}

// A strand along +X (root to tip), the light and the eye in the XY plane at longitudinal
// angles θ_i and θ_r (radians, positive toward the tip) on opposite sides of the normal plane
// as seen along the fibre: the eye looks at the front of the strand (φ = 0 for the lobes).
struct Geometry {
    Vec3f t = Vec3f::UnitX();
    Vec3f l, e;
    Geometry(float theta_i, float theta_r)
        : l(std::sin(theta_i), std::cos(theta_i), 0.f),
          e(std::sin(theta_r), std::cos(theta_r), 0.f) {}
};

// The θ_h (degrees) at which a lobe peaks, scanning θ_r for a fixed θ_i.
float peak_half_angle(const HairLobeSet& k, float which_r, float which_trt) {
    const float theta_i = radians(30.f);
    float best = -1.f, best_h = 0.f;
    for (int step = 0; step <= 4000; ++step) {
        const float theta_r = radians(-80.f + 0.04f * step);
        const Geometry s(theta_i, theta_r);
        HairLobeSet only = k;
        only.k_d = 0.f;
        only.k_tt = 0.f;
        only.k_r *= which_r;
        only.k_trt *= which_trt;
        const float v = hair_reflectance(s.t, s.l, s.e, Vec3f::Ones(), only).x();
        if (v > best) {
            best = v;
            best_h = 0.5f * (theta_i + theta_r) * 180.f / kPi;
        }
    }
    return best_h;
}

}  // namespace

TEST(HairShading, NeverReflectsMoreThanTheLightBrings) {
    const HairLobes lobes;
    Rng rng(3);
    for (int i = 0; i < 20000; ++i) {
        const float variation = 2.f * static_cast<float>(rng.uniform_double()) - 1.f;
        const HairLobeSet k(lobes, variation);
        const Vec3f t = rng.unit_vector(), l = rng.unit_vector(), e = rng.unit_vector();
        const Vec3f c(static_cast<float>(rng.uniform_double()),
                      static_cast<float>(rng.uniform_double()),
                      static_cast<float>(rng.uniform_double()));
        const Vec3f r = hair_reflectance(t, l, e, c, k);
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(r[a], 0.f);
            EXPECT_LE(r[a], 1.f);
        }
    }
    // Even white hair on the mirror cone of both highlights.
    EXPECT_LE(lobes.diffuse + lobes.primary + lobes.secondary * (1.f + lobes.sparkle) +
                  lobes.transmission,
              1.f);
}

TEST(HairShading, PrimaryHighlightIsShiftedTowardTheRoot) {
    const HairLobes lobes;
    const HairLobeSet k(lobes, 0.f);
    EXPECT_NEAR(peak_half_angle(k, 1.f, 0.f), lobes.primary_shift, 0.1f);
    EXPECT_LT(lobes.primary_shift, 0.f);  // toward the root: the tangent points to the tip
}

TEST(HairShading, SecondaryHighlightIsShiftedTowardTheTipAndBroader) {
    const HairLobes lobes;
    const HairLobeSet k(lobes, 0.f);
    EXPECT_NEAR(peak_half_angle(k, 0.f, 1.f), lobes.secondary_shift, 0.1f);
    EXPECT_GT(lobes.secondary_shift, 0.f);
    EXPECT_LT(k.n_trt, k.n_r);  // a smaller exponent: a broader lobe
    // The lobe's half width at half its peak: 1/(2√n) rad ≈ β.
    EXPECT_NEAR(1.f / (2.f * std::sqrt(k.n_r)), radians(lobes.primary_width), 1e-4f);
}

TEST(HairShading, PrimaryIsUncolouredSecondaryTinted) {
    HairLobes lobes;
    lobes.diffuse = lobes.transmission = 0.f;
    const Vec3f brown(0.30f, 0.15f, 0.06f);
    // On the primary's peak, the secondary's weight is small: the reflected light is nearly
    // white whatever the hair's colour.
    HairLobes only_r = lobes;
    only_r.secondary = 0.f;
    const Geometry at_r(radians(30.f), radians(2.f * lobes.primary_shift - 30.f));
    const Vec3f r = hair_reflectance(at_r.t, at_r.l, at_r.e, brown, HairLobeSet(only_r, 0.f));
    EXPECT_NEAR(r.x(), lobes.primary, 1e-3f);  // on its peak
    EXPECT_FLOAT_EQ(r.x(), r.y());
    EXPECT_FLOAT_EQ(r.y(), r.z());
    HairLobes only_trt = lobes;
    only_trt.primary = 0.f;
    const Geometry at_trt(radians(30.f), radians(2.f * lobes.secondary_shift - 30.f));
    const Vec3f s =
        hair_reflectance(at_trt.t, at_trt.l, at_trt.e, brown, HairLobeSet(only_trt, 0.f));
    EXPECT_GT(s.x(), 0.f);
    EXPECT_NEAR(s.y() / s.x(), brown.y() / brown.x(), 1e-5f);
    EXPECT_NEAR(s.z() / s.x(), brown.z() / brown.x(), 1e-5f);
}

TEST(HairShading, TransmissionLightsHairFromBehind) {
    HairLobes lobes;
    lobes.diffuse = lobes.primary = lobes.secondary = 0.f;
    const HairLobeSet k(lobes, 0.f);
    const Vec3f t = Vec3f::UnitY();  // hanging hair
    const Vec3f e = Vec3f::UnitZ();  // the eye in front
    const Vec3f c(0.6f, 0.4f, 0.2f);
    const Vec3f behind = hair_reflectance(t, Vec3f(0, 0.05f, -1).normalized(), e, c, k);
    const Vec3f in_front = hair_reflectance(t, Vec3f(0, 0.05f, 1).normalized(), e, c, k);
    EXPECT_GT(behind.x(), 0.02f);
    EXPECT_EQ(in_front.x(), 0.f);
}

TEST(HairShading, FastPowerStaysWithinItsStatedError) {
    // pow_unit against std::pow (in double) over the lobes' range: x in (0, 1], n up to 1000,
    // within 10⁻⁶ absolute everywhere and 5·10⁻⁶ relative where x^n is above 1/4096.
    Rng rng(11);
    double worst_abs = 0, worst_rel = 0;
    for (int i = 0; i < 200000; ++i) {
        const float n = i % 4 == 0 ? static_cast<float>(1 + i % 997)
                                   : static_cast<float>(1000.0 * rng.uniform_double());
        // x spread toward 1, where the lobes are: 1 − u^4.
        const double u = rng.uniform_double();
        const float x = i % 3 == 0 ? static_cast<float>(rng.uniform_double())
                                   : static_cast<float>(1.0 - u * u * u * u);
        if (!(x > 0.f)) continue;
        const double want = std::pow(static_cast<double>(x), static_cast<double>(n));
        const double got = pow_unit(x, n);
        worst_abs = std::max(worst_abs, std::abs(got - want));
        if (want > 1.0 / 4096) worst_rel = std::max(worst_rel, std::abs(got - want) / want);
    }
    EXPECT_LT(worst_abs, 1e-6);  // measured 1.8·10⁻⁷
    EXPECT_LT(worst_rel, 5e-6);  // measured 2.0·10⁻⁶
    EXPECT_EQ(pow_unit(1.f, 37.f), 1.f);
    EXPECT_EQ(pow_unit(0.f, 3.f), 0.f);
    EXPECT_EQ(pow_unit(0.5f, 1000.f), 0.f);  // 2^−1000 underflows to 0, not to garbage
    EXPECT_NEAR(pow_unit(0.5f, 2.f), 0.25f, 1e-6f);
}

TEST(HairShading, ZeroVariationIsTheSetLobes) {
    const HairLobes lobes;
    const HairLobeSet a(lobes, 0.f), b(lobes, 1.f), c(lobes, -1.f);
    EXPECT_FLOAT_EQ(a.k_trt, lobes.secondary);
    EXPECT_FLOAT_EQ(b.k_trt, lobes.secondary * (1.f + lobes.sparkle));
    EXPECT_FLOAT_EQ(c.k_trt, lobes.secondary * (1.f - lobes.sparkle));
    EXPECT_FLOAT_EQ(a.k_r, b.k_r);  // the primary's strength does not sparkle
}

TEST(HairShading, PrimaryShiftVariesPerStrandByItsJitter) {
    // A strand's primary_variation v moves its primary's peak by v × jitter × width, so the
    // sheen of a sheet of hair breaks into strands; the secondary is left as it was.
    const HairLobes lobes;
    const HairLobeSet base(lobes);
    for (float v : {-1.f, -0.5f, 0.5f, 1.f}) {
        const HairLobeSet k = base.with_sparkle(lobes, 0.f, v);
        EXPECT_NEAR(peak_half_angle(k, 1.f, 0.f),
                    lobes.primary_shift + v * lobes.primary_jitter * lobes.primary_width, 0.1f)
            << "variation " << v;
        EXPECT_NEAR(peak_half_angle(k, 0.f, 1.f), peak_half_angle(base, 0.f, 1.f), 0.05f);
    }
    EXPECT_NEAR(peak_half_angle(base.with_sparkle(lobes, 0.f, 0.f), 1.f, 0.f), lobes.primary_shift,
                0.1f);
}

}  // namespace wisp
