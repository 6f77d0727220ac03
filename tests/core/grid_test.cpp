#include "core/grid.hpp"

#include <gtest/gtest.h>

namespace wisp {

TEST(Grid3, TrilinearReproducesALinearField) {
    Grid3<float> g(Vec3f(-1, -2, -3), 0.5f, Vec3i(9, 10, 11));
    auto f = [](const Vec3f& p) { return 2 * p.x() - 3 * p.y() + 0.5f * p.z() + 1; };
    for (int k = 0; k < 11; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 9; ++i)
                g.at(i, j, k) = f(g.node(i, j, k));
    for (const Vec3f& p : {Vec3f(0.1f, 0.3f, -1.2f), Vec3f(-0.9f, 2.4f, 1.9f), Vec3f(3, 2.5f, 2)})
        EXPECT_NEAR(g.trilinear(p), f(p), 1e-4f);
}

TEST(Grid3, OutsideIsClampedToTheBox) {
    Grid3<float> g(Vec3f::Zero(), 1.f, Vec3i(2, 2, 2), 1.f);
    g.at(1, 1, 1) = 9.f;
    EXPECT_FLOAT_EQ(g.trilinear(Vec3f(50, 50, 50)), 9.f);
    EXPECT_FLOAT_EQ(g.trilinear(Vec3f(-5, -5, -5)), 1.f);
}

}  // namespace wisp
