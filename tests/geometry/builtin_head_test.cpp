#include "geometry/builtin_head.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>

namespace wisp {
namespace {

const Mesh& head() {
    static const Mesh mesh = builtin_head_mesh();
    return mesh;
}

Vec3f centroid(const Mesh& m, size_t f) {
    const Vec3i& t = m.faces[f];
    return (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.f;
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

// Where the ray from (x, y, +∞) toward −Z first meets the mesh: the largest z of the surface
// over (x, y), −∞ if none.
float front_z(const Mesh& m, float x, float y) {
    float best = -INFINITY;
    for (const Vec3i& t : m.faces) {
        const Vec3f &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
        const float det = (b.y() - c.y()) * (a.x() - c.x()) + (c.x() - b.x()) * (a.y() - c.y());
        if (std::abs(det) < 1e-12f) continue;
        const float l0 = ((b.y() - c.y()) * (x - c.x()) + (c.x() - b.x()) * (y - c.y())) / det;
        const float l1 = ((c.y() - a.y()) * (x - c.x()) + (a.x() - c.x()) * (y - c.y())) / det;
        const float l2 = 1.f - l0 - l1;
        if (l0 < 0.f || l1 < 0.f || l2 < 0.f) continue;
        best = std::max(best, l0 * a.z() + l1 * b.z() + l2 * c.z());
    }
    return best;
}

// Landmarks measured on the mesh (cm, head space).
struct Landmarks {
    float crown = 0, chin = 0;             // y of the top of the head, of the bottom of the chin
    float breadth = 0;                     // widest x extent of the cranium above the ears
    float glabella_z = 0, glabella_y = 0;  // the brow's most forward point on the midline
    float occiput_z = 0;                   // the back of the head
    Vec3f nose;                            // the frontmost point
    float ear_top = 0, ear_bottom = 0;     // y extent of what stands out of the head at the sides
    float ear_out = 0;                     // |x| of the ear's outermost point
};

Landmarks measure(const Mesh& m) {
    Landmarks l;
    l.crown = m.bounds().hi.y();
    l.chin = INFINITY;  // lowest point of the face in front of the neck
    for (const Vec3f& p : m.vertices)
        if (p.z() > 5.f && std::abs(p.x()) < 2.f && p.y() > -16.f) l.chin = std::min(l.chin, p.y());
    l.breadth = extent_in_slab(m, 1, 4.5f, 9.f, 0);
    l.glabella_z = -INFINITY;
    l.occiput_z = INFINITY;
    for (const Vec3f& p : m.vertices) {
        // Above the root of the nose, below the hairline.
        if (std::abs(p.x()) < 1.f && p.y() > 2.8f && p.y() < 6.f && p.z() > l.glabella_z) {
            l.glabella_z = p.z();
            l.glabella_y = p.y();
        }
        if (p.y() > -2.f && p.y() < 10.f) l.occiput_z = std::min(l.occiput_z, p.z());
    }
    l.nose = *std::max_element(m.vertices.begin(), m.vertices.end(),
                               [](const Vec3f& a, const Vec3f& c) { return a.z() < c.z(); });
    // The ears: whatever lies more than 8 cm out from the midline beside the head.
    l.ear_top = -INFINITY;
    l.ear_bottom = INFINITY;
    for (const Vec3f& p : m.vertices)
        if (std::abs(p.x()) > 8.f && p.y() > -8.f && p.y() < 8.f) {
            l.ear_top = std::max(l.ear_top, p.y());
            l.ear_bottom = std::min(l.ear_bottom, p.y());
            l.ear_out = std::max(l.ear_out, std::abs(p.x()));
        }
    return l;
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
    // Every vertex is used, and no triangle is degenerate.
    std::vector<char> used(m.vertices.size(), 0);
    for (const Vec3i& t : m.faces)
        for (int k = 0; k < 3; ++k)
            used[t[k]] = 1;
    EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
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
    const Landmarks l = measure(m);
    std::printf(
        "crown %.2f, chin %.2f (chin to crown %.2f), breadth %.2f, glabella (y %.2f, z %.2f), "
        "occiput z %.2f (length %.2f), nose tip (%.2f, %.2f, %.2f), ears y %.2f..%.2f out to "
        "|x| %.2f\n",
        l.crown, l.chin, l.crown - l.chin, l.breadth, l.glabella_y, l.glabella_z, l.occiput_z,
        l.glabella_z - l.occiput_z, l.nose.x(), l.nose.y(), l.nose.z(), l.ear_bottom, l.ear_top,
        l.ear_out);
    // Crown at about y = 12.5; 22-23 cm from chin to crown.
    EXPECT_NEAR(l.crown, 12.5f, 0.5f);
    EXPECT_NEAR(l.crown - l.chin, 22.5f, 0.5f);
    // The cranium about 15 cm wide above the ears and 19 cm from the brow to the back of the head.
    EXPECT_NEAR(l.breadth, 15.f, 0.6f);
    EXPECT_NEAR(l.glabella_z - l.occiput_z, 19.f, 0.6f);
    // The origin between the ears at the height of the ear canal: the brow is about as far in
    // front of it as the back of the head is behind it.
    EXPECT_NEAR(l.glabella_z, -l.occiput_z, 2.f);
    // The nose is the frontmost point, on the midline, 2-3 cm ahead of the brow.
    EXPECT_LT(std::abs(l.nose.x()), 0.5f);
    EXPECT_GT(l.nose.y(), -3.f);
    EXPECT_LT(l.nose.y(), 0.f);
    EXPECT_GT(l.nose.z() - l.glabella_z, 1.8f);
    EXPECT_LT(l.nose.z() - l.glabella_z, 3.2f);
    // Neck about 11-12 cm wide under the jaw; shoulders about 41 cm.
    EXPECT_NEAR(extent_in_slab(m, 1, -12.f, -11.f, 0), 11.5f, 1.f);
    EXPECT_NEAR(extent_in_slab(m, 1, -25.f, -23.f, 0), 41.f, 2.f);
    // A bust, not a column: the chest juts in front of the neck, the shoulders spread wide of it.
    EXPECT_GT(extent_in_slab(m, 1, -28.f, -27.f, 2), extent_in_slab(m, 1, -12.f, -11.f, 2) + 6.f);
    EXPECT_GT(extent_in_slab(m, 1, -22.f, -21.f, 0), 2.5f * extent_in_slab(m, 1, -12.f, -11.f, 0));
    // Symmetric in x.
    const Box3 b = m.bounds();
    EXPECT_NEAR(b.lo.x(), -b.hi.x(), 0.05f);
}

// The largest |x| of the vertices in the slab lo <= y <= hi with |x| < x_max (the torso
// without the arms, which hang further out).
float half_width(const Mesh& m, float lo, float hi, float x_max) {
    float w = 0.f;
    for (const Vec3f& p : m.vertices)
        if (p.y() >= lo && p.y() <= hi && std::abs(p.x()) < x_max) w = std::max(w, std::abs(p.x()));
    return w;
}

// An upper body to the waist, as hair of any length needs to rest on: shoulders, chest, back,
// a waist narrower than the chest, and arms hanging free beside it down to the cut through the
// top of the hips, 3 heads below the crown (a figure 8 heads tall).
TEST(BuiltinHead, UpperBodyToTheWaistWithArms) {
    const Mesh& m = head();
    const Box3 b = m.bounds();
    const float head_height = 22.8f;
    EXPECT_NEAR(b.lo.y(), b.hi.y() - 3.3f * head_height, 1.5f);
    // The flat cut at the bottom: a horizontal face there, facing down.
    size_t bottom_faces = 0;
    for (size_t f = 0; f < m.faces.size(); ++f)
        if (centroid(m, f).y() < b.lo.y() + 0.2f && m.face_normal(f).y() < -0.95f) ++bottom_faces;
    EXPECT_GT(bottom_faces, 50u);
    // The waist narrower than the chest and the hips.
    const float chest = half_width(m, -34.f, -32.f, 15.f);
    const float waist = half_width(m, -53.f, -51.f, 14.5f);
    EXPECT_GT(chest, 12.5f);
    EXPECT_LT(waist, chest - 0.8f);
    // A gap between the arm and the waist, seen from the front: nothing at |x| 13.5-14.3 cm
    // around the elbows, but arm beyond it.
    size_t in_gap = 0, arm = 0;
    for (const Vec3f& p : m.vertices) {
        if (p.y() < -52.f || p.y() > -48.f) continue;
        in_gap += std::abs(p.x()) > 13.5f && std::abs(p.x()) < 14.3f;
        arm += std::abs(p.x()) > 18.f;
    }
    EXPECT_EQ(in_gap, 0u);
    EXPECT_GT(arm, 20u);
    // The chest and the back stand in front of and behind the neck, so hair parts over the
    // shoulders into front and back sections.
    EXPECT_GT(extent_in_slab(m, 1, -34.f, -32.f, 2), 19.f);
}

TEST(BuiltinHead, EarsStandOutBetweenTheBrowAndTheNose) {
    const Mesh& m = head();
    const Landmarks l = measure(m);
    // About 6 cm tall, from the line of the brow to the bottom of the nose.
    EXPECT_NEAR(l.ear_top - l.ear_bottom, 6.f, 0.6f);
    EXPECT_NEAR(l.ear_top, l.glabella_y, 1.f);
    EXPECT_GT(l.ear_bottom, l.nose.y() - 2.f);
    EXPECT_LT(l.ear_bottom, l.nose.y());
    // Seen from the front they stand out beyond the side of the head.
    EXPECT_GT(l.ear_out, 0.5f * l.breadth + 1.f);
    // Beside the ear canal, behind it (the origin), on both sides.
    for (float side : {-1.f, 1.f}) {
        float z_lo = INFINITY, z_hi = -INFINITY;
        for (const Vec3f& p : m.vertices)
            if (side * p.x() > 8.f && std::abs(p.y()) < 8.f) {
                z_lo = std::min(z_lo, p.z());
                z_hi = std::max(z_hi, p.z());
            }
        EXPECT_LT(z_hi, 1.f) << "side " << side;
        EXPECT_GT(z_lo, -5.f) << "side " << side;
        EXPECT_GT(z_hi - z_lo, 1.5f) << "side " << side;  // a shell seen from the side
    }
}

TEST(BuiltinHead, EyesSitInTheirSockets) {
    const Mesh& m = head();
    const Landmarks l = measure(m);
    for (float side : {-1.f, 1.f}) {
        const float x = side * 3.15f, y = 1.3f;  // the pupils, 6.3 cm apart
        const float eye = front_z(m, x, y);
        // The eye is behind the brow and the nose, in front of the sides of the face...
        EXPECT_LT(eye, l.glabella_z - 0.8f) << "side " << side;
        EXPECT_GT(eye, 6.5f) << "side " << side;
        // ...under a brow that stands over it (the socket)...
        EXPECT_GT(front_z(m, x, y + 2.f), eye + 0.6f) << "side " << side;
        // ...and it is a ball: between the lids, the surface falls away to either side.
        for (float dx : {-0.7f, 0.7f})
            EXPECT_LT(front_z(m, x + dx, y), eye - 0.1f) << "side " << side << " offset " << dx;
        // The lids lie over the ball above and below the opening: there the surface stands
        // in front of the ball the opening shows (the sphere through `eye`, 1.15 cm across).
        const float centre_z = eye - 1.15f;
        for (float dy : {0.8f, -0.85f}) {
            const float ball = centre_z + std::sqrt(1.15f * 1.15f - dy * dy);
            EXPECT_GT(front_z(m, x, y + dy), ball + 0.15f) << "side " << side << " lid " << dy;
        }
    }
}

// The face is coloured where shape alone cannot make it read: seen from the front, each eye
// shows a dark pupil at its centre, a darker iris round it and white to either side; the lips
// are redder than the skin; the cranium and the body keep the skin's albedo.
TEST(BuiltinHead, EyesAndLipsAreColoured) {
    const Mesh& m = head();
    ASSERT_EQ(m.colors.size(), m.vertices.size());
    // The colour of the vertex nearest p.
    const auto at = [&](const Vec3f& p) {
        size_t best = 0;
        for (size_t v = 1; v < m.vertices.size(); ++v)
            if ((m.vertices[v] - p).squaredNorm() < (m.vertices[best] - p).squaredNorm()) best = v;
        return m.colors[best];
    };
    const auto luminance = [](const Vec3f& c) {
        return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
    };
    const float skin = luminance(kSkinAlbedo);
    for (float side : {-1.f, 1.f}) {
        const float x = side * 3.15f, y = 1.3f;
        const float front = front_z(m, x, y);
        const float pupil = luminance(at({x, y, front}));
        const float iris = luminance(at({x + 0.4f, y, front_z(m, x + 0.4f, y)}));
        EXPECT_LT(pupil, 0.1f * skin) << "side " << side;
        EXPECT_LT(iris, 0.3f * skin) << "side " << side;
        EXPECT_GT(iris, pupil) << "side " << side;
        for (float dx : {-0.85f, 0.85f})
            EXPECT_GT(luminance(at({x + dx, y, front_z(m, x + dx, y)})), 0.85f * skin)
                << "side " << side << " white at " << dx;
    }
    const Vec3f lip = at({0.f, -5.5f, front_z(m, 0.f, -5.5f)});
    EXPECT_GT(lip.x() / lip.y(), 1.2f * kSkinAlbedo.x() / kSkinAlbedo.y());
    for (const Vec3f& p : {Vec3f(0.f, 12.f, 0.f), Vec3f(0.f, -25.f, 8.f), Vec3f(0.f, 0.f, -10.f)})
        EXPECT_EQ(at(p), kSkinAlbedo) << p.transpose();
}

// The eyes and lids are a few millimetres across, finer than the marching grid: the mesh is
// refined there, so that they come out whole instead of as torn slivers.
TEST(BuiltinHead, EyesAreMeshedFinely) {
    const Mesh& m = head();
    float longest = 0.f;
    size_t near = 0;
    for (const Vec3i& t : m.faces)
        for (int k = 0; k < 3; ++k) {
            const Vec3f &a = m.vertices[t[k]], &b = m.vertices[t[(k + 1) % 3]];
            const Vec3f mid = 0.5f * (a + b);
            if ((Vec3f(std::abs(mid.x()), mid.y(), mid.z()) - Vec3f(3.15f, 1.3f, 7.3f)).norm() >
                1.2f)
                continue;
            longest = std::max(longest, (b - a).norm());
            ++near;
        }
    // 2 mm edges, give or take what relaxing the refined patch stretches them by (the marching
    // grid alone leaves edges of 5 mm and more there).
    EXPECT_GT(near, 1500u);
    EXPECT_LT(longest, 0.26f);
}

TEST(BuiltinHead, ScalpGroupIsAPlausibleCap) {
    const Mesh& m = head();
    ASSERT_EQ(m.group_names.size(), 2u);
    ASSERT_EQ(m.face_group.size(), m.faces.size());
    const int scalp = m.group_names[0] == "scalp" ? 0 : 1;
    EXPECT_EQ(m.group_names[1 - scalp], "body");
    const float crown = m.bounds().hi.y();
    double area = 0;
    float lowest = INFINITY, forehead = INFINITY, sideburn = INFINITY;
    for (size_t f = 0; f < m.faces.size(); ++f) {
        const Vec3f c = centroid(m, f);
        // The ears are never scalp, nor anything that stands out beside the head.
        if (std::abs(c.x()) > 8.f && c.y() < 5.f) {
            EXPECT_NE(m.face_group[f], scalp) << "scalp on the ear at " << c.transpose();
        }
        if (m.face_group[f] != scalp) continue;
        area += m.face_area(f);
        lowest = std::min(lowest, c.y());
        // No scalp on the face: nothing in front below the forehead hairline.
        if (c.z() > 6.f) {
            EXPECT_GT(c.y(), 5.f);
        }
        if (std::abs(c.x()) < 1.f && c.z() > 0.f) forehead = std::min(forehead, c.y());
        if (std::abs(c.x()) > 5.f && c.z() > 0.5f) sideburn = std::min(sideburn, c.y());
    }
    EXPECT_GT(area, 450.0);
    EXPECT_LT(area, 800.0);
    // The forehead hairline 6-7 cm below the crown, sideburns in front of the ears down to
    // about the ear canal, the nape hairline 16-19 cm below the crown.
    EXPECT_GT(crown - forehead, 5.8f);
    EXPECT_LT(crown - forehead, 7.f);
    EXPECT_LT(sideburn, 1.5f);
    EXPECT_GT(sideburn, -1.f);
    EXPECT_GT(crown - lowest, 16.f);
    EXPECT_LT(crown - lowest, 19.f);
}

TEST(BuiltinHead, EveryVertexHasAPolarUv) {
    const Mesh& m = head();
    ASSERT_GE(m.uvs.size(), m.vertices.size());
    ASSERT_EQ(m.face_uvs.size(), m.faces.size());
    for (const Vec2f& uv : m.uvs) {
        ASSERT_TRUE(uv.allFinite());
        ASSERT_LE((uv - Vec2f(0.5f, 0.5f)).norm(), 0.5f + 1e-5f);
    }
    // The crown maps near the centre, the front toward v = 1, +X toward u = 1, and the radius
    // grows from the crown down.
    size_t top = 0, front = 0, left = 0;
    for (size_t v = 0; v < m.vertices.size(); ++v) {
        const Vec3f& p = m.vertices[v];
        if (p.y() > m.vertices[top].y()) top = v;
        if (p.y() > 6.f && p.z() > m.vertices[front].z()) front = v;
        if (p.y() > 6.f && p.x() > m.vertices[left].x()) left = v;
    }
    EXPECT_LT((m.uvs[top] - Vec2f(0.5f, 0.5f)).norm(), 0.03f);
    EXPECT_GT(m.uvs[front].y(), 0.6f);
    EXPECT_GT(m.uvs[left].x(), 0.6f);
}

// Its speed is BM_BuiltinHead's (bench/generate_bench.cpp).
TEST(BuiltinHead, Deterministic) {
    const Mesh again = builtin_head_mesh();
    ASSERT_EQ(again.vertices.size(), head().vertices.size());
    EXPECT_TRUE(again.vertices == head().vertices);
    EXPECT_TRUE(again.faces == head().faces);
    EXPECT_TRUE(again.face_group == head().face_group);
}

}  // namespace
}  // namespace wisp
