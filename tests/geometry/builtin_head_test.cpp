#include "geometry/builtin_head.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>

#include "core/timer.hpp"

namespace wisp {
namespace {

const Mesh& head() {
    static const Mesh mesh = builtin_head_mesh();
    return mesh;
}

// The x, y or z extent of the vertices inside a slab lo <= p[axis] <= hi.
float extent_in_slab(const Mesh& m, int axis, float lo, float hi, int measured) {
    float a = INFINITY, b = -INFINITY;
    for (const Vec3f& p : m.vertices)
        if (p[axis] >= lo && p[axis] <= hi) {
            a = std::min(a, p[measured]);
            b = std::max(b, p[measured]);
        }
    return b - a;
}

TEST(BuiltinHead, ClosedOrientedManifoldOfGenusZero) {
    const Mesh& m = head();
    ASSERT_GT(m.faces.size(), 20000u);
    ASSERT_LT(m.faces.size(), 80000u);
    // Every directed edge appears once and its reverse once: closed, manifold, consistently
    // oriented.
    std::map<std::pair<int, int>, int> directed;
    for (const Vec3i& t : m.faces)
        for (int e = 0; e < 3; ++e)
            ++directed[{t[e], t[(e + 1) % 3]}];
    size_t undirected = 0;
    for (const auto& [edge, count] : directed) {
        ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second;
        ASSERT_EQ(directed.count({edge.second, edge.first}), 1u)
            << "boundary edge " << edge.first << "-" << edge.second;
        if (edge.first < edge.second) ++undirected;
    }
    const long euler = static_cast<long>(m.vertices.size()) - static_cast<long>(undirected) +
                       static_cast<long>(m.faces.size());
    EXPECT_EQ(euler, 2);
    for (size_t f = 0; f < m.faces.size(); ++f)
        ASSERT_GT(m.face_area(f), 0.f) << "face " << f;
}

TEST(BuiltinHead, NormalsPointOutward) {
    const Mesh& m = head();
    double volume = 0;  // divergence theorem: positive for outward normals
    for (const Vec3i& t : m.faces)
        volume += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
    EXPECT_GT(volume, 5000.0);
    // The top of the head faces up, the nose faces forward.
    size_t top = 0, front = 0;
    for (size_t v = 0; v < m.vertices.size(); ++v) {
        if (m.vertices[v].y() > m.vertices[top].y()) top = v;
        if (m.vertices[v].z() > m.vertices[front].z()) front = v;
    }
    for (size_t f = 0; f < m.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            if (static_cast<size_t>(m.faces[f][k]) == top) {
                EXPECT_GT(m.face_normal(f).y(), 0.5f);
            }
            if (static_cast<size_t>(m.faces[f][k]) == front) {
                EXPECT_GT(m.face_normal(f).z(), 0.f);
            }
        }
}

TEST(BuiltinHead, HumanProportionsFacingPlusZ) {
    const Mesh& m = head();
    const Box3 b = m.bounds();
    // Crown at about y = 12, chin at about y = -10: 22 cm of head.
    EXPECT_NEAR(b.hi.y(), 12.f, 0.5f);
    float chin = INFINITY;  // lowest point of the face in front of the neck
    for (const Vec3f& p : m.vertices)
        if (p.z() > 6.f && std::abs(p.x()) < 2.f && p.y() > -16.f) chin = std::min(chin, p.y());
    EXPECT_NEAR(b.hi.y() - chin, 22.f, 1.f);
    // Head 15-16 cm wide, 19-20 cm deep (without the nose) above the ears.
    EXPECT_NEAR(extent_in_slab(m, 1, 4.f, 5.f, 0), 15.5f, 0.8f);
    float back = INFINITY, forehead = -INFINITY;
    for (const Vec3f& p : m.vertices)
        if (p.y() > 3.f && p.y() < 6.f) {
            back = std::min(back, p.z());
            forehead = std::max(forehead, p.z());
        }
    EXPECT_NEAR(forehead - back, 19.5f, 1.f);
    // The nose is the frontmost point, on the midline.
    const auto nose =
        *std::max_element(m.vertices.begin(), m.vertices.end(),
                          [](const Vec3f& a, const Vec3f& c) { return a.z() < c.z(); });
    EXPECT_LT(std::abs(nose.x()), 0.5f);
    EXPECT_GT(nose.y(), -5.f);
    EXPECT_LT(nose.y(), 2.f);
    EXPECT_GT(nose.z(), -back);  // nose ahead of the occiput's distance behind
    // Neck about 11-12 cm wide; shoulders about 40 cm.
    EXPECT_NEAR(extent_in_slab(m, 1, -14.5f, -13.5f, 0), 11.5f, 1.f);
    EXPECT_NEAR(b.size().x(), 39.f, 2.f);
    // Symmetric in x.
    EXPECT_NEAR(b.lo.x(), -b.hi.x(), 0.05f);
}

TEST(BuiltinHead, ScalpGroupIsAPlausibleCap) {
    const Mesh& m = head();
    ASSERT_EQ(m.group_names.size(), 2u);
    ASSERT_EQ(m.face_group.size(), m.faces.size());
    const int scalp = m.group_names[0] == "scalp" ? 0 : 1;
    EXPECT_EQ(m.group_names[1 - scalp], "body");
    double area = 0;
    float lowest = INFINITY;
    for (size_t f = 0; f < m.faces.size(); ++f) {
        if (m.face_group[f] != scalp) continue;
        area += m.face_area(f);
        const Vec3i& t = m.faces[f];
        const Vec3f c = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.f;
        lowest = std::min(lowest, c.y());
        // No scalp on the face: nothing in front below the forehead hairline.
        if (c.z() > 6.f) {
            EXPECT_GT(c.y(), 4.f);
        }
    }
    EXPECT_GT(area, 450.0);
    EXPECT_LT(area, 800.0);
    EXPECT_GT(lowest, -6.f);  // the nape
    EXPECT_LT(lowest, 0.f);
}

TEST(BuiltinHead, EveryVertexHasAUv) {
    const Mesh& m = head();
    ASSERT_GE(m.uvs.size(), m.vertices.size());
    ASSERT_EQ(m.face_uvs.size(), m.faces.size());
    for (const Vec2f& uv : m.uvs) {
        ASSERT_TRUE(uv.allFinite());
        ASSERT_LE((uv - Vec2f(0.5f, 0.5f)).norm(), 0.5f + 1e-5f);
    }
}

TEST(BuiltinHead, DeterministicAndFast) {
    Stopwatch watch;
    const Mesh again = builtin_head_mesh();
    const double ms = watch.ms();
    std::printf("built-in head: %zu vertices, %zu triangles in %.1f ms\n", again.vertices.size(),
                again.faces.size(), ms);
    EXPECT_LT(ms, 1000.0);  // loose: shared machines; typically ~50 ms
    ASSERT_EQ(again.vertices.size(), head().vertices.size());
    EXPECT_TRUE(again.vertices == head().vertices);
    EXPECT_TRUE(again.faces == head().faces);
}

}  // namespace
}  // namespace wisp
