#include "core/point_grid.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "core/rng.hpp"

namespace wisp {

TEST(PointGrid, NearestMatchesBruteForce) {
    Rng rng(11);
    std::vector<Vec3f> pts(500);
    for (Vec3f& p : pts)
        p = Vec3f(rng.uniform(-10, 10), rng.uniform(-3, 3), rng.uniform(0, 20));
    const PointGrid grid(pts, 1.5f);
    for (int q = 0; q < 2000; ++q) {
        // Queries inside and well outside the points' box.
        const Vec3f x(rng.uniform(-15, 15), rng.uniform(-8, 8), rng.uniform(-5, 25));
        int best = 0;
        for (size_t i = 1; i < pts.size(); ++i)
            if ((pts[i] - x).squaredNorm() < (pts[best] - x).squaredNorm()) best = i;
        EXPECT_EQ(grid.nearest(x), best);
        EXPECT_EQ(grid.nearest(x, q % 500), best);  // any hint gives the same answer
    }
}

TEST(PointGrid, EmptySetAnswersMinusOne) {
    const PointGrid grid(std::vector<Vec3f>{}, 1.f);
    EXPECT_EQ(grid.nearest(Vec3f::Zero()), -1);
}

}  // namespace wisp
