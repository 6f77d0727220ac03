#include "geometry/mesh_distance.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <filesystem>

#include "core/parallel.hpp"
#include "core/rng.hpp"
#include "core/timer.hpp"
#include "geometry/builtin_head.hpp"

namespace wisp {
namespace {

const std::string kHeadNeckShoulders =
    WISP_SHARED_DIR "/data/heads/makehuman/makehuman_hm08_head_neck_shoulders.obj";

const Mesh& head() {
    static const Mesh mesh = builtin_head_mesh();
    return mesh;
}

// A closed torus around the y axis: major radius R, minor radius r, outward normals.
Mesh torus(float R, float r, int nu, int nv) {
    Mesh m;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const float u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
            m.vertices.emplace_back((R + r * std::cos(v)) * std::cos(u), r * std::sin(v),
                                    (R + r * std::cos(v)) * std::sin(u));
        }
    auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            m.faces.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
            m.faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
        }
    return m;
}

float torus_distance(const Vec3f& p, float R, float r) {
    return std::hypot(std::hypot(p.x(), p.z()) - R, p.y()) - r;
}

float brute_force_distance(const Mesh& m, const Vec3f& p) {
    // Dense sampling is not exact; use the BVH-free closest point of every triangle instead,
    // through a one-triangle MeshDistance (exercises the same kernel without the hierarchy).
    float best = INFINITY;
    for (size_t f = 0; f < m.faces.size(); ++f) {
        Mesh one;
        for (int k = 0; k < 3; ++k)
            one.vertices.push_back(m.vertices[m.faces[f][k]]);
        one.faces.emplace_back(0, 1, 2);
        best = std::min(best, MeshDistance(one).unsigned_distance(p));
    }
    return best;
}

TEST(MeshDistance, TorusOrientationAndTheHole) {
    const float R = 5.f, r = 1.5f;
    const Mesh m = torus(R, r, 96, 48);
    const MeshDistance d(m);
    // The triangle torus is inscribed: tessellation error under r·(1-cos(π/48)) + ....
    EXPECT_FALSE(d.inside({0, 0, 0}));  // the hole
    EXPECT_NEAR(d.unsigned_distance({0, 0, 0}), R - r, 0.02f);
    EXPECT_NEAR(d.signed_distance({0, 0, 0}), R - r, 0.02f);
    EXPECT_TRUE(d.inside({R, 0, 0}));
    EXPECT_NEAR(d.signed_distance({0, 0, R}), -r, 0.02f);
    // The far-field expansion (β = 2, second order) is accurate to a few percent.
    EXPECT_NEAR(d.winding_number({0, 0, -R}), 1.f, 0.05f);
    EXPECT_NEAR(d.winding_number({0, 10, 0}), 0.f, 0.05f);
    Rng rng(1);
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3f p(rng.uniform(-8, 8), rng.uniform(-3, 3), rng.uniform(-8, 8));
        const float exact = torus_distance(p, R, r);
        if (std::abs(exact) < 0.05f) continue;
        ++checked;
        ASSERT_EQ(d.inside(p), exact < 0) << p.transpose() << " winding " << d.winding_number(p);
        ASSERT_NEAR(d.signed_distance(p), exact, 0.03f) << p.transpose();
    }
    EXPECT_GT(checked, 19000);
}

TEST(MeshDistance, ClosestPointMatchesBruteForce) {
    const Mesh m = torus(4.f, 1.f, 24, 12);
    const MeshDistance d(m);
    Rng rng(2);
    for (int i = 0; i < 300; ++i) {
        const Vec3f p(rng.uniform(-7, 7), rng.uniform(-4, 4), rng.uniform(-7, 7));
        uint32_t face = 0;
        const Vec3f q = d.closest_point(p, &face);
        const float brute = brute_force_distance(m, p);
        ASSERT_NEAR((q - p).norm(), brute, 1e-4f);
        // The reported face holds the point.
        Mesh one;
        for (int k = 0; k < 3; ++k)
            one.vertices.push_back(m.vertices[m.faces[face][k]]);
        one.faces.emplace_back(0, 1, 2);
        ASSERT_LT(MeshDistance(one).unsigned_distance(q), 1e-4f);
    }
}

TEST(MeshDistance, BuiltinHeadInsideOutside) {
    const MeshDistance d(head());
    for (const Vec3f& p : {Vec3f(0, 2, -1), Vec3f(0, -12, -1), Vec3f(0, -30, 0), Vec3f(12, -25, -1),
                           Vec3f(0, -45, 0), Vec3f(18.4f, -45, -2), Vec3f(0, -2.5f, 10.f)})
        EXPECT_TRUE(d.inside(p)) << p.transpose();
    for (const Vec3f& p : {Vec3f(0, 20, 0), Vec3f(30, 0, 0), Vec3f(12, -5, 0), Vec3f(0, -8, 12),
                           Vec3f(0, -70, 0), Vec3f(0, 0, -15), Vec3f(14, -50, -1)})
        EXPECT_FALSE(d.inside(p)) << p.transpose();
    // Points at a known offset along the face normal of random faces.
    Rng rng(3);
    int good = 0, n = 0;
    for (int i = 0; i < 2000; ++i) {
        const uint32_t f = rng.below(static_cast<uint32_t>(head().faces.size()));
        const Vec3i& t = head().faces[f];
        const Vec3f c =
            (head().vertices[t[0]] + head().vertices[t[1]] + head().vertices[t[2]]) / 3.f;
        const Vec3f nrm = head().face_normal(f);
        for (float off : {-0.3f, 0.3f}) {
            const float sd = d.signed_distance(c + off * nrm);
            ++n;
            ASSERT_LE(std::abs(sd), 0.3f + 1e-4f);
            ASSERT_EQ(sd < 0, off < 0) << "face " << f << " offset " << off;
            good += std::abs(sd - off) < 0.03f;
        }
    }
    EXPECT_GT(good, 0.95 * n);
}

TEST(MeshDistance, OpenMakeHumanHead) {
    if (!std::filesystem::exists(kHeadNeckShoulders))
        GTEST_SKIP() << kHeadNeckShoulders << " not present";
    const Mesh m = read_obj_mesh(kHeadNeckShoulders, 10.f);
    const MeshDistance d(m);
    const Box3 b = m.bounds();
    // The head's centre: between the ears, well above the open cut at the chest.
    const Vec3f centre(0.f, b.hi.y() - 10.f, 0.f);
    float front = -INFINITY;
    for (const Vec3f& p : m.vertices)
        if (std::abs(p.y() - centre.y()) < 0.5f && std::abs(p.x()) < 0.5f)
            front = std::max(front, p.z());
    const Vec3f c(0.f, centre.y(), front - 9.f);
    EXPECT_TRUE(d.inside(c)) << "winding " << d.winding_number(c);
    EXPECT_GT(d.winding_number(c), 0.9f);
    EXPECT_LT(d.signed_distance(c), -5.f);
    const Vec3f out = d.closest_point(c + Vec3f(20, 0, 0));  // side of the head
    const Vec3f p = out + 5.f * (out - c).normalized();
    EXPECT_FALSE(d.inside(p)) << "winding " << d.winding_number(p);
    EXPECT_NEAR(d.signed_distance(p), 5.f, 0.5f);
    EXPECT_FALSE(d.inside(Vec3f(0, b.hi.y() + 5.f, 0)));
}

TEST(MeshDistance, ConcurrentQueriesMatchSerialAndThroughput) {
    const MeshDistance d(head());
    const Box3 b = head().bounds();
    // A grid of ~100k points around the head and shoulders, as the voxelizer will query.
    const int nx = 40, ny = 50, nz = 50;
    const size_t n = static_cast<size_t>(nx) * ny * nz;
    auto point = [&](size_t i) {
        const Vec3f t((i % nx + 0.5f) / nx, ((i / nx) % ny + 0.5f) / ny,
                      (i / (nx * ny) + 0.5f) / nz);
        return Vec3f(b.lo + (t.array() * b.size().array()).matrix() * 1.1f - 0.05f * b.size());
    };
    std::vector<float> serial(n), parallel(n);
    std::vector<char> in_serial(n), in_parallel(n);
    Stopwatch w1;
    for (size_t i = 0; i < n; ++i)
        serial[i] = d.unsigned_distance(point(i));
    const double t_closest = w1.ms();
    Stopwatch w2;
    for (size_t i = 0; i < n; ++i)
        in_serial[i] = d.inside(point(i));
    const double t_inside = w2.ms();
    Stopwatch w3;
    parallel_for(
        n,
        [&](size_t i) {
            parallel[i] = d.unsigned_distance(point(i));
            in_parallel[i] = d.inside(point(i));
        },
        256);
    const double t_parallel = w3.ms();
    EXPECT_TRUE(serial == parallel);
    EXPECT_TRUE(in_serial == in_parallel);
    Stopwatch w6;
    for (size_t i = 0; i < n; ++i)
        ASSERT_EQ(d.unsigned_distance(point(i), 2.f), std::min(serial[i], 2.f));
    const double t_band = w6.ms();
    std::printf(
        "MeshDistance on %zu triangles, grid of %zu points over the bounds: closest point "
        "%.2f us/query, inside %.2f us/query; both, in parallel: %.1f ms\n",
        d.face_count(), n, 1e3 * t_closest / n, 1e3 * t_inside / n, t_parallel);
    // Queries within 1 cm of the surface (collisions, narrow bands).
    Rng rng(4);
    std::vector<Vec3f> near(n);
    for (Vec3f& p : near) {
        const Vec3i& t = head().faces[rng.below(static_cast<uint32_t>(head().faces.size()))];
        p = (head().vertices[t[0]] + head().vertices[t[1]] + head().vertices[t[2]]) / 3.f +
            Vec3f(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    }
    float sink = 0;
    Stopwatch w4;
    for (const Vec3f& p : near)
        sink += d.unsigned_distance(p);
    const double t_near = w4.ms();
    Stopwatch w5;
    for (const Vec3f& p : near)
        sink += d.inside(p);
    const double t_near_inside = w5.ms();
    std::printf("grid, distance capped at 2 cm: %.2f us/query\n", 1e3 * t_band / n);
    std::printf("near the surface: closest point %.2f us/query, inside %.2f us/query (%g)\n",
                1e3 * t_near / n, 1e3 * t_near_inside / n, sink);
}

}  // namespace
}  // namespace wisp
