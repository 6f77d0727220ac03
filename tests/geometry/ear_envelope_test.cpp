#include "geometry/ear_envelope.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "test_meshes.hpp"

namespace wisp {
namespace {

// Each ear lies inside its envelope, which stands only a little off it: the ear's outermost
// point is inside, a point 0.05 head heights further out is outside, and so is the side of
// the head well above the ear (the scalp where hair grows stays free).
void expect_envelopes_hold_the_ears(const Mesh& mesh) {
    const Landmarks l = find_landmarks(mesh);
    const std::vector<EarEnvelope> ears = ear_envelopes(mesh, l);
    ASSERT_EQ(ears.size(), 2u);
    const Vec3f points[2] = {l.ear_left, l.ear_right};
    for (int i = 0; i < 2; ++i) {
        const EarEnvelope& e = ears[i];
        const Vec3f out = (points[i] - l.center).normalized();
        EXPECT_LT(e.distance(points[i]), 0.f) << "ear " << i;
        EXPECT_GT(e.distance(points[i] + 0.05f * l.height * out), 0.f) << "ear " << i;
        EXPECT_GT(e.distance(points[i] + 0.35f * l.height * Vec3f::UnitY()), 0.f) << "ear " << i;
        // The estimate is a distance near the surface: 1 cm outside along `out` reads ~1 cm.
        const Vec3f pole = e.center + e.radii.x() * e.out;
        EXPECT_NEAR(e.distance(pole + e.out), 1.f, 0.05f) << "ear " << i;
        EXPECT_NEAR(e.distance(pole), 0.f, 1e-3f) << "ear " << i;
    }
}

TEST(EarEnvelope, HoldsTheBuiltInEars) {
    expect_envelopes_hold_the_ears(test::builtin_mesh());
}

TEST(EarEnvelope, HoldsTheMakeHumanEars) {
    if (!std::filesystem::exists(test::kHeadNeckShoulders))
        GTEST_SKIP() << "no " << test::kHeadNeckShoulders;
    expect_envelopes_hold_the_ears(read_obj_mesh(test::kHeadNeckShoulders, 10.f));
}

}  // namespace
}  // namespace wisp
