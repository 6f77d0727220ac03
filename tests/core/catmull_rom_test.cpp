#include "core/catmull_rom.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace wisp {

TEST(CatmullRom, PassesThroughEveryControlPoint) {
    const std::vector<Vec3f> p = {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2}, {5, 0, 0}};
    for (size_t i = 0; i < p.size(); ++i) {
        const float s = static_cast<float>(i) / (p.size() - 1);
        EXPECT_LT((catmull_rom_eval(p, s) - p[i]).norm(), 1e-5f) << i;
    }
}

TEST(CatmullRom, StraightControlPointsGiveAStraightEvenCurve) {
    std::vector<Vec3f> p;
    for (int i = 0; i < 6; ++i)
        p.push_back(Vec3f(0, -2.f * i, 0));
    for (int k = 0; k <= 100; ++k) {
        const float s = k / 100.f;
        const Vec3f q = catmull_rom_eval(p, s);
        EXPECT_NEAR(q.x(), 0.f, 1e-6f);
        EXPECT_NEAR(q.y(), -10.f * s, 1e-4f);  // pinned ends keep the speed uniform
    }
}

TEST(CatmullRom, SampleMatchesEval) {
    const std::vector<Vec3f> p = {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2}};
    std::vector<Vec3f> out(3 * 4 + 1);
    catmull_rom_sample(p, 4, out);
    for (size_t k = 0; k < out.size(); ++k)
        EXPECT_LT((out[k] - catmull_rom_eval(p, k / 12.f)).norm(), 1e-5f);
}

TEST(CatmullRom, DerivativeMatchesFiniteDifference) {
    const std::vector<Vec3f> p = {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 4, 2}};
    for (float s : {0.1f, 0.4f, 0.77f}) {
        const float h = 1e-3f;
        const Vec3f fd = (catmull_rom_eval(p, s + h) - catmull_rom_eval(p, s - h)) / (2 * h);
        EXPECT_LT((fd - catmull_rom_derivative(p, s)).norm(), 2e-2f);
    }
}

}  // namespace wisp
