#include "core/grid.hpp"

#include <gtest/gtest.h>

#include "core/rng.hpp"

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

// The gradient overload returns the same value to the bit, and the derivative of the
// interpolant: a linear field's gradient exactly, and within a cell the central difference
// of trilinear() at any seeded point of a random field (the interpolant is a polynomial
// there, quadratic along no axis, so a central difference inside the cell is exact up to
// rounding). Outside the box the clamped value does not move along the clamped axes.
TEST(Grid3, GradientIsTheInterpolantsDerivative) {
    Grid3<float> g(Vec3f(-1, -2, -3), 0.5f, Vec3i(9, 10, 11));
    auto f = [](const Vec3f& p) { return 2 * p.x() - 3 * p.y() + 0.5f * p.z() + 1; };
    for (int k = 0; k < 11; ++k)
        for (int j = 0; j < 10; ++j)
            for (int i = 0; i < 9; ++i)
                g.at(i, j, k) = f(g.node(i, j, k));
    Vec3f grad;
    for (const Vec3f& p : {Vec3f(0.1f, 0.3f, -1.2f), Vec3f(-0.9f, 2.4f, 1.9f), Vec3f(3, 2.5f, 2)}) {
        EXPECT_EQ(g.trilinear(p, &grad), g.trilinear(p));
        EXPECT_LT((grad - Vec3f(2, -3, 0.5f)).norm(), 1e-4f);
    }
    Rng rng(7);
    for (float& v : g.data())
        v = rng.uniform(-1.f, 1.f);
    for (int n = 0; n < 200; ++n) {
        // A point inside a cell, at least h from its faces.
        const Vec3i c(int(rng.next() % 8), int(rng.next() % 9), int(rng.next() % 10));
        const Vec3f u(rng.uniform(0.1f, 0.9f), rng.uniform(0.1f, 0.9f), rng.uniform(0.1f, 0.9f));
        const Vec3f p = g.node(c.x(), c.y(), c.z()) + g.cell() * u;
        ASSERT_EQ(g.trilinear(p, &grad), g.trilinear(p)) << n;
        const float h = 0.02f;
        for (int a = 0; a < 3; ++a) {
            Vec3f e = Vec3f::Zero();
            e[a] = h;
            const float central = (g.trilinear(p + e) - g.trilinear(p - e)) / (2 * h);
            ASSERT_NEAR(grad[a], central, 2e-3f) << n << " axis " << a;
        }
    }
    g.trilinear(Vec3f(50, 0, 0), &grad);
    EXPECT_EQ(grad.x(), 0.f);
}

}  // namespace wisp
