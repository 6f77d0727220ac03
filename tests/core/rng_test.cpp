#include "core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace wisp {

TEST(Rng, SameSeedAndIdGiveSameStream) {
    Rng a(42, Stream::kMember, 7), b(42, Stream::kMember, 7);
    for (int i = 0; i < 100; ++i)
        EXPECT_EQ(a.next(), b.next());
}

TEST(Rng, DomainsAndIdsGiveDifferentStreams) {
    Rng a(42, Stream::kMember, 7), b(42, Stream::kColor, 7), c(42, Stream::kMember, 8);
    const uint64_t x = a.next();
    EXPECT_NE(x, b.next());
    EXPECT_NE(x, c.next());
}

TEST(Rng, UniformMomentsAndRange) {
    Rng rng(1);
    double sum = 0, sum2 = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const float u = rng.uniform();
        ASSERT_GE(u, 0.f);
        ASSERT_LT(u, 1.f);
        sum += u;
        sum2 += u * u;
    }
    EXPECT_NEAR(sum / n, 0.5, 0.005);
    EXPECT_NEAR(sum2 / n - (sum / n) * (sum / n), 1.0 / 12.0, 0.002);
}

TEST(Rng, NormalMoments) {
    Rng rng(3);
    double sum = 0, sum2 = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double x = rng.normal();
        sum += x;
        sum2 += x * x;
    }
    EXPECT_NEAR(sum / n, 0.0, 0.01);
    EXPECT_NEAR(sum2 / n, 1.0, 0.02);
}

TEST(Rng, UnitVectorsAreUnitAndUnbiased) {
    Rng rng(5);
    Vec3f mean = Vec3f::Zero();
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        const Vec3f v = rng.unit_vector();
        ASSERT_NEAR(v.norm(), 1.f, 1e-5f);
        mean += v;
    }
    EXPECT_LT((mean / n).norm(), 0.01f);
}

TEST(Rng, BelowStaysInRange) {
    Rng rng(9);
    int counts[7] = {};
    for (int i = 0; i < 70000; ++i) {
        const uint32_t k = rng.below(7);
        ASSERT_LT(k, 7u);
        ++counts[k];
    }
    for (int c : counts)
        EXPECT_NEAR(c, 10000, 400);
}

}  // namespace wisp
