#include "render/fiber_scattering.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace wisp {
namespace {

// A direction at longitudinal angle θ (from the plane normal to the fibre along +X, positive
// toward the tip) and azimuth φ around it.
Vec3f direction(float theta, float phi) {
    return {std::sin(theta), std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi)};
}

// ∫ S(ω_i, ω_o) dω_i over the sphere: the radiance leaving under unit radiance from every
// direction (a white furnace).
Vec3f furnace(const FiberScattering& fiber, float theta_o, float phi_o, const Vec3f& sigma_a) {
    const Vec3f t = Vec3f::UnitX(), eye = direction(theta_o, phi_o);
    const FiberScattering::View view = fiber.view(t, eye);
    constexpr int kTheta = 720, kAzimuth = 360;
    Vec3d sum = Vec3d::Zero();
    for (int i = 0; i < kTheta; ++i) {
        const float theta = kPi * ((i + 0.5f) / kTheta - 0.5f);
        for (int j = 0; j < kAzimuth; ++j) {
            const float phi = 2.f * kPi * (j + 0.5f) / kAzimuth;
            const double d_omega = std::cos(theta) * (kPi / kTheta) * (2 * kPi / kAzimuth);
            sum += fiber.eval(view, direction(theta, phi), sigma_a).cast<double>() * d_omega;
        }
    }
    return sum.cast<float>();
}

// The published absorption of the two melanins (Chiang et al. 2016 §4.1, pbrt-v4): the
// colour of hair follows from them.
TEST(FiberScattering, MelaninAbsorptionIsThePublishedCoefficients) {
    const Vec3f eu = melanin_absorption({1.f, 0.f}), pheo = melanin_absorption({0.f, 1.f});
    EXPECT_NEAR(eu.x(), 0.419f, 1e-6f);
    EXPECT_NEAR(eu.y(), 0.697f, 1e-6f);
    EXPECT_NEAR(eu.z(), 1.37f, 1e-6f);
    EXPECT_NEAR(pheo.x(), 0.187f, 1e-6f);
    EXPECT_NEAR(pheo.y(), 0.4f, 1e-6f);
    EXPECT_NEAR(pheo.z(), 1.05f, 1e-6f);
    // Both absorb blue most: hair is never blue; pheomelanin is the redder.
    EXPECT_GT(pheo.z() / pheo.x(), eu.z() / eu.x());
}

// A colour is made of the melanin whose hair has it: a melanin's own colour gives it back; a
// colour no melanin makes keeps its lightness; darker is more eumelanin, redder more
// pheomelanin.
TEST(FiberScattering, MelaninFromColorFindsThePigmentsOfAColor) {
    for (const Melanin m : {Melanin{4.f, 0.f}, Melanin{1.3f, 0.f}, Melanin{0.5f, 1.2f},
                            Melanin{0.f, 0.4f}, Melanin{0.3f, 0.1f}}) {
        const Vec3f c = color_from_absorption(melanin_absorption(m), 0.3f);
        const Melanin back = melanin_from_color(c, 0.3f);
        EXPECT_NEAR(back.eumelanin, m.eumelanin, 2e-3f * (1.f + m.eumelanin));
        EXPECT_NEAR(back.pheomelanin, m.pheomelanin, 2e-3f * (1.f + m.pheomelanin));
    }
    const auto luminance = [](const Vec3f& c) {
        return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
    };
    for (const Vec3f grey : {Vec3f(0.006f, 0.006f, 0.006f), Vec3f(0.3f, 0.3f, 0.3f)}) {
        const Melanin m = melanin_from_color(grey, 0.3f);
        const Vec3f c = color_from_absorption(melanin_absorption(m), 0.3f);
        EXPECT_NEAR(std::log(luminance(c)), std::log(luminance(grey)), 0.01f);
    }
    const Melanin black = melanin_from_color({0.0075f, 0.0056f, 0.0048f}, 0.3f);
    const Melanin brown = melanin_from_color({0.073f, 0.039f, 0.016f}, 0.3f);
    const Melanin auburn = melanin_from_color({0.09f, 0.026f, 0.012f}, 0.3f);
    EXPECT_GT(black.eumelanin, brown.eumelanin);
    EXPECT_GT(auburn.pheomelanin / (auburn.eumelanin + auburn.pheomelanin),
              brown.pheomelanin / (brown.eumelanin + brown.pheomelanin + 1e-6f));
}

// Chiang et al. eq. 9: a darker colour is more absorption, white none.
TEST(FiberScattering, AbsorptionFromColorIsZeroForWhiteAndGrowsAsTheColorDarkens) {
    EXPECT_NEAR(absorption_from_color(Vec3f::Ones(), 0.3f).norm(), 0.f, 1e-6f);
    const Vec3f brown = absorption_from_color({0.25f, 0.12f, 0.06f}, 0.3f);
    const Vec3f dark = absorption_from_color({0.05f, 0.03f, 0.02f}, 0.3f);
    for (int k = 0; k < 3; ++k)
        EXPECT_GT(dark[k], brown[k]);
    EXPECT_GT(brown.z(), brown.x());  // blue absorbed most: the hair is red-brown
}

// A fibre that absorbs nothing sends out all the light it receives (Chiang et al. §4: the
// model conserves energy, a white furnace), from any direction, at any roughness; one that
// absorbs sends out less, and less for the channel it absorbs most. Without the cuticle's
// tilt, which moves the lobes off the measure they are normalized in (as in Chiang et al.'s
// and pbrt's furnace tests).
TEST(FiberScattering, WhiteFurnaceSendsOutAllTheLight) {
    for (const FiberParams params :
         {FiberParams{1.55f, 0.3f, 0.3f, 0.f}, FiberParams{1.55f, 0.15f, 0.2f, 0.f},
          FiberParams{1.55f, 0.6f, 0.8f, 0.f}}) {
        const FiberScattering fiber(params);
        for (const float theta_o : {0.f, 0.4f, -0.9f, 1.2f}) {
            const Vec3f white = furnace(fiber, theta_o, 0.3f, Vec3f::Zero());
            EXPECT_NEAR(white.x(), 1.f, 0.02f)
                << "β_m " << params.beta_m << ", β_n " << params.beta_n << ", θ_o " << theta_o;
            const Vec3f brown = furnace(fiber, theta_o, 0.3f, melanin_absorption({1.3f, 0.f}));
            EXPECT_LT(brown.x(), white.x());
            EXPECT_LT(brown.z(), brown.x());
            // At least the surface reflection R, which absorption does not touch.
            EXPECT_GT(brown.z(), 0.03f);
        }
    }
}

// The scales tilt toward the tip, so the reflection off the cuticle (R, all that black hair
// shows) peaks shifted toward the root: lit at θ_i, by 2α from where an untilted fibre's
// peaks (near θ_o = −θ_i, a little beyond, where Fresnel reflects more).
float reflection_peak(float alpha_degrees) {
    const FiberScattering fiber(FiberParams{1.55f, 0.2f, 0.3f, alpha_degrees});
    const Vec3f black = melanin_absorption({40.f, 0.f});
    const float theta_i = 0.5f;
    float best = 0.f, best_theta = 0.f;
    for (int k = -800; k <= 800; ++k) {
        const float theta_o = 0.001f * k;
        const float value =
            fiber.eval(Vec3f::UnitX(), direction(theta_i, 0.f), direction(theta_o, 0.2f), black)
                .x();
        if (value > best) best = value, best_theta = theta_o;
    }
    return best_theta;
}

TEST(FiberScattering, TheCuticleShiftsTheReflectionTowardTheRoot) {
    const float untilted = reflection_peak(0.f);
    EXPECT_NEAR(untilted, -0.5f, 0.05f);
    EXPECT_NEAR(reflection_peak(4.f) - untilted, -2.f * 4.f * kPi / 180.f, 0.02f);
}

// Transmission (TT) goes forward: a backlit light fibre glows, a dark one does not.
TEST(FiberScattering, LightHairTransmitsTowardTheEyeOppositeTheLight) {
    const FiberScattering fiber;
    const Vec3f light = direction(0.1f, 0.f), behind = direction(-0.1f, kPi);
    const Vec3f side = direction(-0.1f, 0.5f * kPi);
    const Vec3f blonde = melanin_absorption({0.3f, 0.1f}), black = melanin_absorption({8.f, 0.f});
    const Vec3f t = Vec3f::UnitX();
    EXPECT_GT(fiber.eval(t, light, behind, blonde).x(),
              3.f * fiber.eval(t, light, side, blonde).x());
    EXPECT_LT(fiber.eval(t, light, behind, black).x(),
              0.1f * fiber.eval(t, light, behind, blonde).x());
}

// Dual scattering's back-scatter sums the fibres behind a point: light hair (forward albedo
// near 1) takes many layers to send back all it will, dark hair only the first few; with no
// hair behind, only the point's own return of the light scattered on to it is left.
TEST(FiberScattering, BackScatterGrowsWithTheHairBehind) {
    const FiberScattering fiber;
    const Vec3f t = Vec3f::UnitX();
    const FiberScattering::View view = fiber.view(t, direction(-0.2f, 0.4f));
    const Vec3f light = direction(0.3f, 0.f);
    const auto back = [&](const Vec3f& sigma_a, float behind) {
        return fiber.multiple(view, light, fiber.albedo(sigma_a), 0.f, behind).x();
    };
    const Vec3f blonde = melanin_absorption({0.05f, 0.03f}), dark = melanin_absorption({2.f, 0.f});
    EXPECT_EQ(back(blonde, 0.f), 0.f);
    EXPECT_LT(back(blonde, 1.f), back(blonde, 4.f));
    EXPECT_LT(back(blonde, 4.f), 0.9f * back(blonde, INFINITY));
    EXPECT_NEAR(back(blonde, 200.f), back(blonde, INFINITY), 1e-3f * back(blonde, INFINITY));
    EXPECT_GT(back(dark, 4.f), 0.97f * back(dark, INFINITY));
    // Behind defaults to hair without end.
    EXPECT_EQ(fiber.multiple(view, light, fiber.albedo(blonde), 0.f).x(), back(blonde, INFINITY));
}

}  // namespace
}  // namespace wisp
