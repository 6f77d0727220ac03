#include "render/strand_samples.hpp"

#include <gtest/gtest.h>

#include "core/catmull_rom.hpp"
#include "synthetic_hair.hpp"

namespace wisp {
namespace {

TEST(StrandSamples, FollowTheCatmullRomSpline) {
    test::SyntheticHairSpec spec;
    spec.strands = 20;
    spec.points = 9;
    const Hair hair = test::synthetic_hair(spec);
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const auto p = hair.strand(s);
        int count = 0;
        for_each_strand_sample(
            hair, s, 1.f, 1.f, [](size_t i, const Vec3f&, const Vec3f&) { return 1 + i % 3; },
            [&](const StrandSample& x) {
                EXPECT_LT((x.p - catmull_rom_eval(p, x.s)).norm(), 1e-4f);
                const Vec3f d = catmull_rom_derivative(p, std::min(x.s, 0.9999f)).normalized();
                EXPECT_GT(x.t.dot(d), 0.999f);
                EXPECT_NEAR(x.t.norm(), 1.f, 1e-5f);
                ++count;
            });
        EXPECT_EQ(count, 1 + 8 + (0 + 1 + 2 + 0 + 1 + 2 + 0 + 1));  // tip + Σ sub(i)
    }
}

TEST(StrandSamples, WidthsInterpolateAndTaper) {
    Hair hair;
    const Vec3f pts[3] = {Vec3f(0, 0, 0), Vec3f(0, -1, 0), Vec3f(0, -2, 0)};
    hair.add_strand(pts);
    std::vector<float> widths;
    for_each_strand_sample(
        hair, 0, 2.f, 0.25f, [](size_t, const Vec3f&, const Vec3f&) { return 2; },
        [&](const StrandSample& x) { widths.push_back(x.width); });
    ASSERT_EQ(widths.size(), 5u);
    EXPECT_FLOAT_EQ(widths[0], 2.f * hair.default_width);          // root: no taper
    EXPECT_FLOAT_EQ(widths[2], 2.f * hair.default_width);          // mid-length: none yet
    EXPECT_FLOAT_EQ(widths[4], 2.f * hair.default_width * 0.25f);  // tip
    EXPECT_LT(widths[3], widths[2]);
    EXPECT_FLOAT_EQ(taper_factor(0.f, 0.3f), 1.f);
    EXPECT_FLOAT_EQ(taper_factor(1.f, 0.3f), 0.3f);
}

}  // namespace
}  // namespace wisp
