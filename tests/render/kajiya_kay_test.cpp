#include "render/kajiya_kay.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.hpp"

namespace wisp {
namespace {

Vec3f random_unit(Rng& rng) {
    while (true) {
        const Vec3f v(2.f * static_cast<float>(rng.uniform_double()) - 1.f,
                      2.f * static_cast<float>(rng.uniform_double()) - 1.f,
                      2.f * static_cast<float>(rng.uniform_double()) - 1.f);
        if (v.squaredNorm() > 1e-3f && v.squaredNorm() <= 1.f) return v.normalized();
    }
}

TEST(KajiyaKay, DiffuseIsSineOfTangentAndLight) {
    Rng rng(7);
    for (int i = 0; i < 200; ++i) {
        const Vec3f t = random_unit(rng), l = random_unit(rng);
        const float angle = std::acos(std::clamp(t.dot(l), -1.f, 1.f));
        EXPECT_NEAR(kajiya_kay_diffuse(t, l), std::sin(angle), 1e-5f);
    }
    EXPECT_NEAR(kajiya_kay_diffuse(Vec3f::UnitX(), Vec3f::UnitY()), 1.f, 1e-6f);  // across
    EXPECT_NEAR(kajiya_kay_diffuse(Vec3f::UnitX(), Vec3f::UnitX()), 0.f, 1e-6f);  // along
    EXPECT_NEAR(kajiya_kay_diffuse(Vec3f::UnitX(), -Vec3f::UnitX()), 0.f, 1e-6f);
}

TEST(KajiyaKay, SpecularPeaksOnTheMirrorCone) {
    // Light at 60° to the tangent: the mirror cone holds every e with t·e = -t·l.
    const Vec3f t = Vec3f::UnitX();
    const Vec3f l = Vec3f(std::cos(kPi / 3), std::sin(kPi / 3), 0.f);
    for (float phi = 0.f; phi < 2.f * kPi; phi += 0.3f) {
        const Vec3f e(-std::cos(kPi / 3), std::sin(kPi / 3) * std::cos(phi),
                      std::sin(kPi / 3) * std::sin(phi));
        EXPECT_NEAR(kajiya_kay_cone_cosine(t, l, e), 1.f, 1e-5f);
        EXPECT_NEAR(kajiya_kay_specular(t, l, e, 50.f), 1.f, 1e-4f);
    }
    // Moving the eye off the cone lowers the highlight monotonically.
    float previous = 2.f;
    for (float off = 0.f; off < 1.2f; off += 0.1f) {
        const float a = kPi / 3 + off;  // angle between t and e is π − a
        const Vec3f e(-std::cos(a), std::sin(a), 0.f);
        const float s = kajiya_kay_specular(t, l, e, 20.f);
        EXPECT_LT(s, previous + 1e-6f);
        previous = s;
    }
    EXPECT_LT(previous, 0.01f);
}

TEST(KajiyaKay, SpecularIsSymmetricInLightAndEyeAndBounded) {
    Rng rng(11);
    for (int i = 0; i < 200; ++i) {
        const Vec3f t = random_unit(rng), l = random_unit(rng), e = random_unit(rng);
        const float a = kajiya_kay_specular(t, l, e, 30.f), b = kajiya_kay_specular(t, e, l, 30.f);
        EXPECT_NEAR(a, b, 1e-5f);
        EXPECT_GE(a, 0.f);
        EXPECT_LE(a, 1.f + 1e-5f);
        // Flipping the tangent (a strand has no direction) changes nothing.
        EXPECT_NEAR(kajiya_kay_specular(-t, l, e, 30.f), a, 1e-5f);
        EXPECT_NEAR(kajiya_kay_diffuse(-t, l), kajiya_kay_diffuse(t, l), 1e-6f);
    }
}

TEST(KajiyaKay, HigherExponentNarrowsTheHighlight) {
    const Vec3f t = Vec3f::UnitX(), l = Vec3f(0.5f, 0.866025f, 0.f);
    const Vec3f e = Vec3f(-0.3f, 0.953939f, 0.f);  // near the cone, not on it
    EXPECT_GT(kajiya_kay_specular(t, l, e, 10.f), kajiya_kay_specular(t, l, e, 100.f));
}

TEST(Lambert, CosineClampedAtZero) {
    EXPECT_NEAR(lambert(Vec3f::UnitY(), Vec3f::UnitY()), 1.f, 1e-6f);
    EXPECT_NEAR(lambert(Vec3f::UnitY(), Vec3f(0, 0.5f, 0.866025f)), 0.5f, 1e-5f);
    EXPECT_EQ(lambert(Vec3f::UnitY(), -Vec3f::UnitY()), 0.f);
}

}  // namespace
}  // namespace wisp
