#include "groom/member.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace wisp {

TEST(Member, NextOffsetStaysInsideTheSphere) {
    // Fig. 4: the ray-sphere rule keeps |d_k| ≤ r_k for any fuzziness.
    Rng rng(2);
    for (float sigma : {0.1f, 1.f, 5.f}) {
        Vec3f d(0.9f, 0.f, 0.f);
        float r_prev = 1.f;
        for (int k = 0; k < 20000; ++k) {
            const float r = 0.5f + rng.uniform() * 2.f;
            d = next_offset(d, r_prev, r, sigma, rng);
            ASSERT_LE(d.norm(), r * (1.f + 1e-5f));
            r_prev = r;
        }
    }
}

TEST(Member, ZeroFuzzinessScalesTheRootOffset) {
    Rng rng(3);
    const Vec3f d = next_offset(Vec3f(0.5f, 0.2f, 0.f), 1.f, 2.f, 0.f, rng);
    EXPECT_LT((d - Vec3f(1.f, 0.4f, 0.f)).norm(), 1e-6f);
}

TEST(Member, LargerFuzzinessSpreadsMore) {
    // Fig. 3: σ = 0.1 gives members close to the master's shape, σ = 1 a wide variation.
    auto spread = [](float sigma) {
        Rng rng(4);
        double sum = 0;
        for (int s = 0; s < 2000; ++s) {
            Vec3f d = Vec3f::Zero();
            Vec3f prev = d;
            for (int k = 0; k < 16; ++k) {
                d = next_offset(d, 1.f, 1.f, sigma, rng);
                sum += (d - prev).norm();
                prev = d;
            }
        }
        return sum;
    };
    EXPECT_LT(spread(0.1f), 0.5 * spread(1.f));
}

TEST(Member, PointCountFollowsTheRelativeLength) {
    EXPECT_EQ(member_point_count(32, 1.f), 32u);
    EXPECT_EQ(member_point_count(32, 0.5f), 17u);  // 15.5 → 16 whole + 1 fractional
    EXPECT_EQ(member_point_count(32, 0.01f), 2u);  // never fewer than a segment
}

TEST(Member, GrowMemberKeepsEveryPointWithinTheRadius) {
    const int n = 12;
    std::vector<Vec3f> master(n);
    std::vector<Frame> frames(n);
    std::vector<float> radius(n);
    for (int k = 0; k < n; ++k) {
        master[k] = Vec3f(0.3f * k, -1.f * k, 0.1f * k * k);
        frames[k] = frame_from(Vec3f(0.3f, -1.f, 0.2f * k).normalized(), Vec3f::UnitX());
        radius[k] = 0.4f + 0.1f * k;
    }
    Rng rng(8);
    for (int s = 0; s < 500; ++s) {
        const float u = 0.3f + 0.7f * rng.uniform();
        std::vector<Vec3f> out(member_point_count(n, u));
        const Vec3f d1 = 0.4f * rng.uniform() * rng.unit_vector();
        grow_member(master, frames, radius, d1, u, 0.8f, rng, out);
        EXPECT_LT((out[0] - master[0] - frames[0].to_world(d1)).norm(), 1e-5f);
        for (size_t k = 0; k + 1 < out.size(); ++k)
            ASSERT_LE((out[k] - master[k]).norm(), radius[k] * 1.0001f) << k;
    }
}

}  // namespace wisp
