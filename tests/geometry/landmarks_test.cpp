#include "geometry/landmarks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "geometry/builtin_head.hpp"
#include "test_meshes.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

using test::kBase;
using test::kHeadNeckShoulders;

const Mesh& builtin() {
    return test::builtin_mesh();
}

// A rigid motion about Y with a uniform scale: p → scale · R_y(degrees) p + move.
struct Motion {
    float degrees = 0, scale = 1;
    Vec3f move = Vec3f::Zero();
    Vec3f point(const Vec3f& p) const {
        return scale * (Eigen::AngleAxisf(degrees * kPi / 180.f, Vec3f::UnitY()) * p) + move;
    }
    Vec3f direction(const Vec3f& d) const {
        return Eigen::AngleAxisf(degrees * kPi / 180.f, Vec3f::UnitY()) * d;
    }
};

Mesh moved(const Mesh& mesh, const Motion& motion) {
    Mesh out = mesh;
    for (Vec3f& v : out.vertices)
        v = motion.point(v);
    return out;
}

// `mesh` keeping only the faces whose three corners are at or above y (an open cut).
Mesh cut_below(const Mesh& mesh, float y) {
    Mesh out;
    out.vertices = mesh.vertices;
    for (const Vec3i& t : mesh.faces)
        if (mesh.vertices[t[0]].y() >= y && mesh.vertices[t[1]].y() >= y &&
            mesh.vertices[t[2]].y() >= y)
            out.faces.push_back(t);
    return out;
}

float degrees_between(const Vec3f& a, const Vec3f& b) {
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.f, 1.f)) * 180.f / kPi;
}

#define EXPECT_POINT_NEAR(actual, expected, tolerance)     \
    EXPECT_LE(((actual) - (expected)).norm(), (tolerance)) \
        << #actual << " = " << (actual).transpose() << ", expected " << (expected).transpose()

// Properties of every head's landmarks, whatever its size, place and facing.
void check_consistent(const Landmarks& l) {
    EXPECT_NEAR(l.forward.norm(), 1.f, 1e-4f);
    EXPECT_NEAR(l.forward.y(), 0.f, 1e-5f);
    const Vec3f left = Vec3f::UnitY().cross(l.forward);
    // Midline points lie on the plane through the centre along forward and up.
    for (const Vec3f* p : {&l.crown, &l.brow, &l.nose_tip, &l.chin})
        EXPECT_NEAR(left.dot(*p - l.center), 0.f, 0.02f * l.height) << p->transpose();
    // The order from top to bottom, and from front to back.
    EXPECT_GT(l.crown.y(), l.brow.y());
    EXPECT_GT(l.brow.y(), l.eye_left.y());
    EXPECT_GT(l.eye_left.y(), l.nose_tip.y());
    EXPECT_GT(l.nose_tip.y(), l.chin.y());
    EXPECT_GT(l.chin.y(), l.neck.y());
    EXPECT_GT(l.forward.dot(l.nose_tip - l.brow), 0.f);
    EXPECT_GT(l.forward.dot(l.brow - l.eye_left), 0.f);
    EXPECT_GT(l.forward.dot(l.eye_left - l.center), 0.f);
    // The character's left eye and ear are on its left.
    EXPECT_GT(left.dot(l.eye_left - l.center), 0.f);
    EXPECT_LT(left.dot(l.eye_right - l.center), 0.f);
    EXPECT_GT(left.dot(l.ear_left - l.eye_left), 0.f);
    EXPECT_LT(left.dot(l.ear_right - l.eye_right), 0.f);
    EXPECT_POINT_NEAR(l.center, Vec3f(0.5f * (l.ear_left + l.ear_right)), 1e-4f * l.height);
    EXPECT_NEAR(l.height, l.crown.y() - l.chin.y(), 1e-4f * l.height);
    EXPECT_EQ(std::isnan(l.neck_bottom), !l.head_only);
}

// The built-in head's landmarks, as its header lists them (measured on the mesh).
TEST(Landmarks, BuiltinHeadMatchesItsMeasuredLandmarks) {
    const Landmarks l = find_landmarks(builtin());
    check_consistent(l);
    EXPECT_LT(degrees_between(l.forward, Vec3f::UnitZ()), 1.f);
    // Crown y 12.5 at the top of the head (the top 0.5 cm spans z -3.5 … 2.2).
    EXPECT_NEAR(l.crown.y(), 12.5f, 0.1f);
    EXPECT_NEAR(l.crown.x(), 0.f, 0.1f);
    EXPECT_GT(l.crown.z(), -3.5f);
    EXPECT_LT(l.crown.z(), 2.2f);
    EXPECT_POINT_NEAR(l.brow, Vec3f(0.f, 3.2f, 9.1f), 0.5f);
    EXPECT_POINT_NEAR(l.nose_tip, Vec3f(0.f, -1.45f, 11.45f), 0.3f);
    EXPECT_POINT_NEAR(l.eye_left, Vec3f(3.15f, 1.3f, 6.8f), 0.5f);
    EXPECT_POINT_NEAR(l.eye_right, Vec3f(-3.15f, 1.3f, 6.8f), 0.5f);
    // The header's chin, y -10.3, is the lowest point under the jaw anywhere; on the midline
    // the chin's lowest point is at y -9.91, z 7.3 … 7.7.
    EXPECT_NEAR(l.chin.x(), 0.f, 0.1f);
    EXPECT_GT(l.chin.y(), -10.3f);
    EXPECT_LT(l.chin.y(), -9.7f);
    EXPECT_NEAR(l.chin.z(), 7.5f, 0.5f);
    EXPECT_NEAR(l.height, 12.5f + 9.91f, 0.3f);
    // The ears: out to |x| = 9.0 (its outermost vertex 9.18) at y -2.5 … 3.5, z -3.3 … 0.
    for (const Vec3f& ear :
         {l.ear_left, Vec3f(-l.ear_right.x(), l.ear_right.y(), l.ear_right.z())}) {
        EXPECT_NEAR(ear.x(), 9.f, 0.3f) << ear.transpose();
        EXPECT_GT(ear.y(), -2.5f);
        EXPECT_LT(ear.y(), 3.5f);
        EXPECT_GT(ear.z(), -3.3f);
        EXPECT_LT(ear.z(), 0.f);
    }
    EXPECT_GT(l.ear_left.x(), 0.f);
    // The neck, 11.2 cm wide at y -10 … -17, narrowest just under the jaw.
    EXPECT_NEAR(l.neck.x(), 0.f, 0.1f);
    EXPECT_LT(l.neck.y(), l.chin.y());
    EXPECT_GT(l.neck.y(), -17.f);
    EXPECT_NEAR(l.neck_radius, 5.6f, 0.4f);
    // The bust (and whatever the mesh will carry further down) has shoulders.
    EXPECT_FALSE(l.head_only);
}

// Every landmark moves with the mesh: turned about Y, scaled, moved.
TEST(Landmarks, FollowTheMeshTurnedScaledAndMoved) {
    const Landmarks base = find_landmarks(builtin());
    const Motion motions[] = {{30.f, 1.f, {0.f, 0.f, 0.f}},    {90.f, 1.f, {4.f, -3.f, 2.f}},
                              {180.f, 1.f, {0.f, 0.f, 0.f}},   {-135.f, 1.f, {-20.f, 150.f, 7.f}},
                              {0.f, 0.8f, {0.f, 0.f, 0.f}},    {61.f, 1.3f, {1.f, 2.f, 3.f}},
                              {-17.f, 0.8f, {0.f, -40.f, 0.f}}};
    for (const Motion& m : motions) {
        SCOPED_TRACE(testing::Message() << "turned " << m.degrees << "°, scaled " << m.scale
                                        << ", moved " << m.move.transpose());
        const Landmarks l = find_landmarks(moved(builtin(), m));
        check_consistent(l);
        EXPECT_LT(degrees_between(l.forward, m.direction(base.forward)), 1.f);
        const float tolerance = 0.5f * m.scale;
        EXPECT_POINT_NEAR(l.crown, m.point(base.crown), tolerance);
        EXPECT_POINT_NEAR(l.brow, m.point(base.brow), tolerance);
        EXPECT_POINT_NEAR(l.nose_tip, m.point(base.nose_tip), tolerance);
        EXPECT_POINT_NEAR(l.eye_left, m.point(base.eye_left), tolerance);
        EXPECT_POINT_NEAR(l.eye_right, m.point(base.eye_right), tolerance);
        EXPECT_POINT_NEAR(l.chin, m.point(base.chin), tolerance);
        EXPECT_POINT_NEAR(l.ear_left, m.point(base.ear_left), tolerance);
        EXPECT_POINT_NEAR(l.ear_right, m.point(base.ear_right), tolerance);
        EXPECT_POINT_NEAR(l.center, m.point(base.center), tolerance);
        EXPECT_POINT_NEAR(l.neck, m.point(base.neck), tolerance);
        EXPECT_NEAR(l.height, m.scale * base.height, tolerance);
        EXPECT_NEAR(l.neck_radius, m.scale * base.neck_radius, 0.2f * m.scale);
        EXPECT_EQ(l.head_only, base.head_only);
    }
}

// A head looking up or down (a scan is rarely level): the face's points stay where they were
// on the face, within 1 cm, though "most forward" and "lowest" move a little along it.
TEST(Landmarks, FollowTheHeadTiltedUpOrDown) {
    const Landmarks base = find_landmarks(builtin());
    for (float degrees : {-12.f, -6.f, 6.f, 12.f}) {
        SCOPED_TRACE(testing::Message() << "tilted " << degrees << "° about X");
        const Eigen::AngleAxisf tilt(degrees * kPi / 180.f, Vec3f::UnitX());
        Mesh mesh = builtin();
        for (Vec3f& v : mesh.vertices)
            v = tilt * v;
        const Landmarks l = find_landmarks(mesh);
        check_consistent(l);
        EXPECT_LT(degrees_between(l.forward, Vec3f::UnitZ()), 1.f);
        EXPECT_POINT_NEAR(l.nose_tip, Vec3f(tilt * base.nose_tip), 1.f);
        EXPECT_POINT_NEAR(l.chin, Vec3f(tilt * base.chin), 1.f);
        EXPECT_POINT_NEAR(l.eye_left, Vec3f(tilt * base.eye_left), 1.f);
        EXPECT_POINT_NEAR(l.eye_right, Vec3f(tilt * base.eye_right), 1.f);
        EXPECT_POINT_NEAR(l.ear_left, Vec3f(tilt * base.ear_left), 1.f);
        EXPECT_POINT_NEAR(l.ear_right, Vec3f(tilt * base.ear_right), 1.f);
    }
}

TEST(Landmarks, AreDeterministic) {
    const Landmarks a = find_landmarks(builtin()), b = find_landmarks(builtin());
    for (auto field :
         {&Landmarks::forward, &Landmarks::crown, &Landmarks::brow, &Landmarks::nose_tip,
          &Landmarks::eye_left, &Landmarks::eye_right, &Landmarks::chin, &Landmarks::ear_left,
          &Landmarks::ear_right, &Landmarks::center, &Landmarks::neck})
        EXPECT_EQ(a.*field, b.*field);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.neck_radius, b.neck_radius);
}

// The MakeHuman head's landmarks, measured on its vertices (cm, read in decimetres × 10): the
// eye centres are the base mesh's eye joints; the other points are vertices on its midline
// x = 0 or its outermost ones.
void check_makehuman(const Landmarks& l) {
    check_consistent(l);
    EXPECT_LT(degrees_between(l.forward, Vec3f::UnitZ()), 5.f);
    // The top of the head is flat: its vertices within 0.5 cm of the top (y 84.91) span z
    // 3.16 … 6.96 on the midline.
    EXPECT_NEAR(l.crown.y(), 84.91f, 0.1f);
    EXPECT_NEAR(l.crown.x(), 0.f, 0.1f);
    EXPECT_GT(l.crown.z(), 3.16f);
    EXPECT_LT(l.crown.z(), 6.96f);
    // The midline's most forward point between the root of the nose and the forehead.
    EXPECT_POINT_NEAR(l.brow, Vec3f(0.f, 75.60f, 15.34f), 1.f);
    EXPECT_POINT_NEAR(l.nose_tip, Vec3f(0.f, 69.09f, 16.81f), 1.f);
    EXPECT_POINT_NEAR(l.eye_left, Vec3f(3.08f, 72.84f, 12.45f), 1.f);
    EXPECT_POINT_NEAR(l.eye_right, Vec3f(-3.08f, 72.84f, 12.45f), 1.f);
    // The underside of the chin is flat: the midline's lowest vertex is (0, 61.555, 12.31) and
    // the vertices to z 13.46 are within 0.06 cm of it.
    EXPECT_NEAR(l.chin.x(), 0.f, 0.1f);
    EXPECT_NEAR(l.chin.y(), 61.55f, 0.3f);
    EXPECT_GT(l.chin.z(), 12.3f);
    EXPECT_LT(l.chin.z(), 13.8f);
    EXPECT_NEAR(l.height, 84.91f - 61.55f, 0.4f);
    EXPECT_POINT_NEAR(l.ear_left, Vec3f(8.79f, 72.41f, 3.75f), 1.f);
    EXPECT_POINT_NEAR(l.ear_right, Vec3f(-8.79f, 72.41f, 3.75f), 1.f);
    // The neck is short: its narrowest section (radius 4.82) is at y ≈ 61.05, half a
    // centimetre under the chin; by y = 57 the trapezius spreads to 30 cm wide.
    EXPECT_NEAR(l.neck.y(), 61.05f, 0.5f);
    EXPECT_NEAR(l.neck.x(), 0.f, 0.1f);
    EXPECT_NEAR(l.neck_radius, 4.82f, 0.2f);
    EXPECT_FALSE(l.head_only);
}

TEST(Landmarks, MakeHumanHeadNeckAndShoulders) {
    if (!fs::exists(kHeadNeckShoulders)) GTEST_SKIP() << kHeadNeckShoulders << " not present";
    check_makehuman(find_landmarks(read_obj_mesh(kHeadNeckShoulders, 10.f)));
}

// The full body carries eyes, teeth, eyelashes and helper shells (hair, tights, skirt) beside
// the body: the largest piece is the body.
TEST(Landmarks, MakeHumanFullBody) {
    if (!fs::exists(kBase)) GTEST_SKIP() << kBase << " not present";
    const Mesh mesh = read_obj_mesh(kBase, 10.f);
    const Landmarks l = find_landmarks(mesh);
    check_makehuman(l);
    // Turned to face -X, in metres and moved: the same landmarks, moved likewise.
    const Motion m{-90.f, 0.01f, {1.f, -0.8f, 2.f}};
    const Landmarks t = find_landmarks(moved(mesh, m));
    EXPECT_LT(degrees_between(t.forward, m.direction(l.forward)), 1.f);
    for (auto field : {&Landmarks::crown, &Landmarks::brow, &Landmarks::nose_tip,
                       &Landmarks::eye_left, &Landmarks::eye_right, &Landmarks::chin,
                       &Landmarks::ear_left, &Landmarks::ear_right, &Landmarks::neck})
        EXPECT_POINT_NEAR(t.*field, m.point(l.*field), 0.5f * m.scale);
}

// A scan that ends at the neck: no shoulders, and the mesh's end is reported.
TEST(Landmarks, HeadOnlyMeshEndsBelowTheNeck) {
    {
        SCOPED_TRACE("built-in head cut at y = -14");
        const Landmarks full = find_landmarks(builtin());
        const Landmarks l = find_landmarks(cut_below(builtin(), -14.f));
        check_consistent(l);
        EXPECT_TRUE(l.head_only);
        EXPECT_GE(l.neck_bottom, -14.f);
        EXPECT_LT(l.neck_bottom, -13.5f);
        EXPECT_POINT_NEAR(l.nose_tip, full.nose_tip, 0.3f);
        EXPECT_POINT_NEAR(l.chin, full.chin, 0.3f);
        EXPECT_POINT_NEAR(l.neck, full.neck, 0.5f);
    }
    if (!fs::exists(kBase)) GTEST_SKIP() << kBase << " not present";
    const Mesh body = read_obj_mesh(kBase, 10.f);
    for (float y : {60.f, 58.5f, 57.5f}) {
        SCOPED_TRACE(testing::Message() << "MakeHuman body cut at y = " << y);
        const Landmarks l = find_landmarks(cut_below(body, y));
        check_consistent(l);
        EXPECT_TRUE(l.head_only);
        EXPECT_GE(l.neck_bottom, y);
        EXPECT_LT(l.neck_bottom, y + 0.5f);
        EXPECT_POINT_NEAR(l.nose_tip, Vec3f(0.f, 69.09f, 16.81f), 1.f);
        EXPECT_NEAR(l.chin.y(), 61.55f, 0.3f);
        EXPECT_LT(l.neck.y(), l.chin.y());
        EXPECT_GT(l.neck.y(), y);
    }
}

std::string error_of(const Mesh& mesh) {
    try {
        find_landmarks(mesh);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

Mesh box(const Vec3f& half) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.emplace_back(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(),
                                i & 4 ? half.z() : -half.z());
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.faces.emplace_back(q[0], q[1], q[2]);
        m.faces.emplace_back(q[0], q[2], q[3]);
    }
    return m;
}

// A UV sphere of the given radii (an ellipsoid), `rings` × `segments`.
Mesh ellipsoid(const Vec3f& radii, int rings, int segments) {
    Mesh m;
    m.vertices.emplace_back(0.f, radii.y(), 0.f);
    for (int j = 1; j < rings; ++j)
        for (int i = 0; i < segments; ++i) {
            const float theta = kPi * j / rings, phi = 2.f * kPi * i / segments;
            m.vertices.emplace_back(radii.x() * std::sin(theta) * std::cos(phi),
                                    radii.y() * std::cos(theta),
                                    radii.z() * std::sin(theta) * std::sin(phi));
        }
    m.vertices.emplace_back(0.f, -radii.y(), 0.f);
    const int last = static_cast<int>(m.vertices.size()) - 1;
    auto at = [&](int j, int i) { return 1 + (j - 1) * segments + i % segments; };
    for (int i = 0; i < segments; ++i) {
        m.faces.emplace_back(0, at(1, i + 1), at(1, i));
        m.faces.emplace_back(last, at(rings - 1, i), at(rings - 1, i + 1));
    }
    for (int j = 1; j < rings - 1; ++j)
        for (int i = 0; i < segments; ++i) {
            m.faces.emplace_back(at(j, i), at(j, i + 1), at(j + 1, i + 1));
            m.faces.emplace_back(at(j, i), at(j + 1, i + 1), at(j + 1, i));
        }
    return m;
}

// Decided: a mesh with no head is an error that says what is missing, not landmarks made up.
TEST(Landmarks, NoHeadIsAnError) {
    EXPECT_NE(error_of(Mesh{}).find("no faces"), std::string::npos);
    // A box, a cylinder's kin: no section narrows below a wider one.
    EXPECT_NE(error_of(box({5.f, 10.f, 5.f})).find("no head"), std::string::npos);
    // A sphere and an egg narrow below their middle, but have no face: no nose on either side.
    EXPECT_NE(error_of(ellipsoid({10.f, 10.f, 10.f}, 24, 48)).find("no face"), std::string::npos);
    EXPECT_NE(error_of(ellipsoid({7.5f, 12.f, 10.f}, 40, 64)).find("no face"), std::string::npos);
}

}  // namespace
}  // namespace wisp
