#include "render/opacity_shadow_map.hpp"

#include <gtest/gtest.h>

#include "core/parallel.hpp"
#include "render/shadow_depth_map.hpp"
#include "synthetic_hair.hpp"

namespace wisp {
namespace {

// A horizontal mat of parallel strands in the plane y = 0, lit from above.
Hair mat(int strands) {
    Hair hair;
    for (int i = 0; i < strands; ++i) {
        const float z = -5.f + 10.f * (i + 0.5f) / strands;
        const Vec3f pts[4] = {Vec3f(-5, 0, z), Vec3f(-1.7f, 0, z), Vec3f(1.7f, 0, z),
                              Vec3f(5, 0, z)};
        hair.add_strand(pts);
    }
    return hair;
}

Box3 mat_box() {
    Box3 b;
    b.extend(Vec3f(-6, -6, -6));
    b.extend(Vec3f(6, 6, 6));
    return b;
}

TEST(OpacityShadowMap, HairShadowsWhatLiesBehindItOnly) {
    const Hair hair = mat(400);
    const LightFrame light = LightFrame::towards(Vec3f::UnitY());
    const OpacityShadowMap map(hair, light, mat_box(), {});
    EXPECT_NEAR(map.transmittance(Vec3f(0, 3, 0)), 1.f, 1e-6f);  // above the mat
    const float below = map.transmittance(Vec3f(0, -3, 0));
    EXPECT_LT(below, 0.9f);                                             // below it
    EXPECT_NEAR(map.transmittance(Vec3f(0, -5, 0)), below, 1e-5f);      // no more hair further
    EXPECT_NEAR(map.transmittance(Vec3f(5.9f, -3, 5.9f)), 1.f, 0.05f);  // beside the mat
    // τ is the hair's projected density: width · length / area · strand_opacity, here
    // 400 strands × 0.008 cm × 10 cm over 100 cm² × 0.5 = 0.16 (on average over the mat:
    // locally it varies with the strands' and the deposits' positions on the texel grid).
    auto mean_tau = [](const OpacityShadowMap& m) {
        double sum = 0;
        int n = 0;
        for (float x = -4.f; x <= 4.f; x += 0.1f)
            for (float z = -4.f; z <= 4.f; z += 0.1f, ++n)
                sum += m.optical_depth(Vec3f(x, -3, z));
        return sum / n;
    };
    OpacityShadowMapOptions uniform;
    uniform.tip_width = 1.f;
    const OpacityShadowMap flat(hair, light, mat_box(), uniform);
    EXPECT_NEAR(mean_tau(flat), 0.16, 0.005);
    const OpacityShadowMap denser(mat(800), light, mat_box(), uniform);
    EXPECT_NEAR(mean_tau(denser), 0.32, 0.01);
}

TEST(OpacityShadowMap, IndependentOfThreadCountAndOrder) {
    test::SyntheticHairSpec spec;
    spec.strands = 2000;
    const Hair hair = test::synthetic_hair(spec);
    const LightFrame light = LightFrame::towards(Vec3f(-0.3f, 0.8f, 0.5f).normalized());
    OpacityShadowMapOptions options;
    options.resolution = 64;
    options.slices = 16;
    std::vector<float> one, two;
    {
        ThreadLimit limit(1);
        const OpacityShadowMap map(hair, light, hair.bounds(), options);
        for (size_t i = 0; i < hair.points.size(); i += 13)
            one.push_back(map.optical_depth(hair.points[i]));
    }
    {
        ThreadLimit limit(2);
        std::vector<uint32_t> reversed(hair.strand_count());
        for (size_t i = 0; i < reversed.size(); ++i)
            reversed[i] = static_cast<uint32_t>(reversed.size() - 1 - i);
        const OpacityShadowMap map(hair, light, hair.bounds(), options, reversed);
        for (size_t i = 0; i < hair.points.size(); i += 13)
            two.push_back(map.optical_depth(hair.points[i]));
    }
    EXPECT_EQ(one, two);
}

// A crown: strands lying on shells 10 to 10.6 cm from the origin over the upper half, running
// from the top down the sides, a layer of hair like the top of a head.
Hair crown() {
    Hair hair;
    uint64_t state = 7;
    auto next = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<float>(state >> 40) / 16777216.f;
    };
    for (int i = 0; i < 6000; ++i) {
        const float r = 10.f + 0.6f * next();
        const float azimuth = 2.f * kPi * next();
        const float start = 0.05f + 0.1f * next();  // polar angle of the root
        std::vector<Vec3f> pts;
        for (int k = 0; k < 12; ++k) {
            const float polar = start + 1.4f * k / 11.f;
            pts.emplace_back(r * std::sin(polar) * std::cos(azimuth), r * std::cos(polar),
                             r * std::sin(polar) * std::sin(azimuth));
        }
        hair.add_strand(pts);
    }
    return hair;
}

// The optical depth of a map of `slices` slabs at points 0.3 cm under the crown's surface, on
// its lit side.
std::vector<float> crown_depths(int slices) {
    static const Hair hair = crown();
    const Vec3f to_light = Vec3f(0.5f, 1.f, 0.3f).normalized();
    Box3 box;
    box.extend(Vec3f(-12, -2, -12));
    box.extend(Vec3f(12, 12, 12));
    OpacityShadowMapOptions options;
    options.resolution = 192;
    options.slices = slices;
    options.strand_opacity = 0.4f;
    const OpacityShadowMap map(hair, LightFrame::towards(to_light), box, options);
    std::vector<float> out;
    for (int i = 0; i < 300; ++i)
        for (int j = 0; j < 300; ++j) {
            const float polar = 0.2f + 1.2f * i / 299.f, azimuth = 2.f * kPi * j / 299.f;
            const Vec3f n(std::sin(polar) * std::cos(azimuth), std::cos(polar),
                          std::sin(polar) * std::sin(azimuth));
            if (n.dot(to_light) > 0.3f) out.push_back(map.optical_depth(10.3f * n));
        }
    return out;
}

// The slabs do not show as stripes across a crown. Slabs cut by planes crossed its surface,
// so the hair just under it entered a slab at its start in some places and at its end in
// others and was shadowed more or less in stripes across the hair ("tiger stripes"). Measured
// against a map of ten times as many slabs: the ratio of the two optical depths under the
// surface may be off by its half-slab bias, the same everywhere, but must not vary from point
// to point (its coefficient of variation: 0.28 with planar slabs of even depth, 0.05 with
// slabs that start at the surface and grow with depth).
TEST(OpacityShadowMap, SlabsDoNotBandACrown) {
    const std::vector<float> reference = crown_depths(480);
    auto variation = [&](int slices) {
        const std::vector<float> depths = crown_depths(slices);
        double sum = 0, sum2 = 0, n = 0;
        for (size_t k = 0; k < depths.size(); ++k) {
            if (reference[k] < 0.05f) continue;
            const double r = depths[k] / reference[k];
            sum += r;
            sum2 += r * r;
            n += 1;
        }
        const double mean = sum / n;
        return std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
    };
    EXPECT_LT(variation(48), 0.1);
    EXPECT_LT(variation(96), variation(24));  // converging
}

TEST(ShadowDepthMap, SphereShadowsBehindItself) {
    const Mesh sphere = test::sphere_mesh(Vec3f::Zero(), 5.f);
    const LightFrame light = LightFrame::towards(Vec3f::UnitY());
    Box3 box;
    box.extend(Vec3f(-10, -10, -10));
    box.extend(Vec3f(10, 10, 10));
    const ShadowDepthMap map(sphere, light, box, 256);
    EXPECT_NEAR(map.visibility(Vec3f(0, 7, 0)), 1.f, 1e-6f);
    EXPECT_NEAR(map.visibility(Vec3f(0, 5.05f, 0)), 1.f, 1e-6f);  // its own lit surface
    EXPECT_NEAR(map.visibility(Vec3f(0, -7, 0)), 0.f, 1e-6f);
    EXPECT_NEAR(map.visibility(Vec3f(8, -7, 0)), 1.f, 1e-6f);
    // The way to the lit surface along the light (down −y), none beside the sphere, and none
    // from behind it.
    EXPECT_NEAR(map.distance_to_surface(Vec3f(0, 7, 0)), 2.f, 0.1f);
    EXPECT_NEAR(map.distance_to_surface(Vec3f(3, 7, 0)), 3.f, 0.1f);  // surface at y = 4
    EXPECT_EQ(map.distance_to_surface(Vec3f(8, 7, 0)), INFINITY);
    EXPECT_EQ(map.distance_to_surface(Vec3f(0, -7, 0)), 0.f);
}

}  // namespace
}  // namespace wisp
