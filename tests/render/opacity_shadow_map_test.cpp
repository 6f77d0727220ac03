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
}

}  // namespace
}  // namespace wisp
