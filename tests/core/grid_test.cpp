#include "core/grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>

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

// The textbook trilinear formula, each node found by at(): what trilinear() computed before it
// stepped between nodes by index.
template <typename T>
T textbook_trilinear(const Grid3<T>& g, const Vec3f& p) {
    const Vec3f x = (p - g.origin()) / g.cell();
    const Vec3i& dims = g.dims();
    int i[3];
    float f[3];
    for (int a = 0; a < 3; ++a) {
        const float c = std::clamp(x[a], 0.f, static_cast<float>(dims[a] - 1));
        i[a] = std::min(static_cast<int>(c), dims[a] - 2);
        if (i[a] < 0) i[a] = 0;
        f[a] = dims[a] > 1 ? c - static_cast<float>(i[a]) : 0.f;
    }
    const int i1 = std::min(i[0] + 1, dims[0] - 1), j1 = std::min(i[1] + 1, dims[1] - 1),
              k1 = std::min(i[2] + 1, dims[2] - 1);
    const T c00 = g.at(i[0], i[1], i[2]) * (1 - f[0]) + g.at(i1, i[1], i[2]) * f[0];
    const T c10 = g.at(i[0], j1, i[2]) * (1 - f[0]) + g.at(i1, j1, i[2]) * f[0];
    const T c01 = g.at(i[0], i[1], k1) * (1 - f[0]) + g.at(i1, i[1], k1) * f[0];
    const T c11 = g.at(i[0], j1, k1) * (1 - f[0]) + g.at(i1, j1, k1) * f[0];
    const T c0 = c00 * (1 - f[1]) + c10 * f[1];
    const T c1 = c01 * (1 - f[1]) + c11 * f[1];
    return c0 * (1 - f[2]) + c1 * f[2];
}

// Seeded grids of every shape from one node per axis up, scalar and vector, looked up at
// random points inside, at nodes and on the box's faces and far outside (clamped): the same
// floats, to the bit, as the textbook formula, and the gradient overload's value with them.
TEST(Grid3, TrilinearIsTheTextbookFormulaToTheBit) {
    Rng rng(16);
    for (int shape = 0; shape < 40; ++shape) {
        const Vec3i dims(1 + int(rng.next() % 6), 1 + int(rng.next() % 6), 1 + int(rng.next() % 6));
        const Vec3f origin(rng.uniform(-5.f, 5.f), rng.uniform(-5.f, 5.f), rng.uniform(-5.f, 5.f));
        const float cell = rng.uniform(0.1f, 2.f);
        Grid3<float> g(origin, cell, dims);
        Grid3<Vec3f> v(origin, cell, dims, Vec3f::Zero());  // Vec3f{} is uninitialised
        for (float& x : g.data())
            x = rng.uniform(-10.f, 10.f);
        for (Vec3f& x : v.data())
            x = Vec3f(rng.uniform(-1.f, 1.f), rng.uniform(-1.f, 1.f), rng.uniform(-1.f, 1.f));
        const Vec3f top = cell * (dims - Vec3i::Ones()).cast<float>();
        for (int n = 0; n < 300; ++n) {
            Vec3f u;
            for (int a = 0; a < 3; ++a) {
                switch (rng.next() % 4) {
                    case 0:  // a node, its faces included
                        u[a] = cell * float(rng.next() % dims[a]);
                        break;
                    case 1:  // outside, clamped
                        u[a] = rng.next() % 2 ? -rng.uniform(0.01f, 5.f)
                                              : top[a] + rng.uniform(0.01f, 5.f);
                        break;
                    default:  // inside
                        u[a] = rng.uniform(0.f, 1.f) * top[a];
                }
            }
            const Vec3f p = origin + u;
            const float expected = textbook_trilinear(g, p);
            const float got = g.trilinear(p);
            ASSERT_EQ(std::bit_cast<uint32_t>(got), std::bit_cast<uint32_t>(expected))
                << shape << " " << n;
            Vec3f grad;
            ASSERT_EQ(std::bit_cast<uint32_t>(g.trilinear(p, &grad)),
                      std::bit_cast<uint32_t>(expected))
                << shape << " " << n;
            const Vec3f ve = textbook_trilinear(v, p), vg = v.trilinear(p);
            for (int a = 0; a < 3; ++a)
                ASSERT_EQ(std::bit_cast<uint32_t>(vg[a]), std::bit_cast<uint32_t>(ve[a]))
                    << shape << " " << n << " axis " << a;
        }
    }
}

}  // namespace wisp
