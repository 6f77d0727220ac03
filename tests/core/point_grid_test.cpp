#include "core/point_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
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

// Scanning rows of cells in sorted order (not in index order) never loses a tie: on a
// lattice of duplicated points at cell corners, with queries on the lattice, on cell faces
// and at equal distances from several points, the answer is the lowest index among the
// nearest, as a brute force scan in index order gives.
TEST(PointGrid, RowRunsKeepTiesToTheLowestIndex) {
    std::vector<Vec3f> pts;
    for (int copy = 0; copy < 2; ++copy)
        for (int z = 0; z < 6; ++z)
            for (int y = 0; y < 6; ++y)
                for (int x = 0; x < 6; ++x)
                    pts.emplace_back(0.5f * x, 0.5f * y, 0.5f * z);
    Rng rng(5);
    for (const float cell : {0.5f, 0.37f, 1.f}) {
        const PointGrid grid(pts, cell);
        for (int q = 0; q < 3000; ++q) {
            // Coordinates on the lattice, halfway between its points, or anywhere.
            Vec3f x;
            for (int a = 0; a < 3; ++a) {
                const int kind = static_cast<int>(rng.uniform(0, 3));
                const float k = std::floor(rng.uniform(-1, 7));
                x[a] = kind == 0 ? 0.5f * k : kind == 1 ? 0.5f * k + 0.25f : rng.uniform(-1, 4);
            }
            int best = 0;
            for (size_t i = 1; i < pts.size(); ++i)
                if ((pts[i] - x).squaredNorm() < (pts[best] - x).squaredNorm()) best = i;
            ASSERT_EQ(grid.nearest(x), best) << x.transpose();
            ASSERT_EQ(grid.nearest(x, static_cast<int>(pts.size()) - 1 - q % 216), best);
        }
    }
}

// Queries below the points' box (negative offsets from its corner, where truncation and
// floor differ), above it and far beyond it search the edge cells they clamp to, with and
// without a hint.
TEST(PointGrid, QueriesOutsideTheBoxClampToItsEdgeCells) {
    std::vector<Vec3f> pts;
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x)
                pts.emplace_back(1.f * x, 1.f * y, 1.f * z);
    const PointGrid grid(pts, 1.f);
    Rng rng(8);
    for (int q = 0; q < 3000; ++q) {
        Vec3f x;
        for (int a = 0; a < 3; ++a) {
            const int kind = static_cast<int>(rng.uniform(0, 4));
            x[a] = kind == 0   ? rng.uniform(-1.f, 0.f)
                   : kind == 1 ? rng.uniform(3.f, 5.f)
                   : kind == 2 ? rng.uniform(-1e6f, 1e6f)
                               : rng.uniform(0.f, 3.f);
        }
        int best = 0;
        for (size_t i = 1; i < pts.size(); ++i)
            if ((pts[i] - x).squaredNorm() < (pts[best] - x).squaredNorm()) best = i;
        ASSERT_EQ(grid.nearest(x), best) << x.transpose();
        ASSERT_EQ(grid.nearest(x, q % 64), best) << x.transpose();
    }
}

TEST(PointGrid, EmptySetAnswersMinusOne) {
    const PointGrid grid(std::vector<Vec3f>{}, 1.f);
    EXPECT_EQ(grid.nearest(Vec3f::Zero()), -1);
}

}  // namespace wisp
