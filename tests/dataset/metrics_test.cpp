// The comparison metrics on hair whose answers are known: the same hair, hair shifted past
// each distance threshold, strands tilted past each angle, hair turned in the picture.
#include "dataset/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"

namespace wisp {
namespace {

// Straight vertical strands on a grid 2 cm apart (x from −10 to 10, z from −4 to 4), each
// 20 cm long in 41 points, transformed by f.
template <class F>
Hair grid(F&& f) {
    Hair h;
    for (int x = -10; x <= 10; x += 2)
        for (int z = -4; z <= 4; z += 2) {
            for (int i = 0; i <= 40; ++i)
                h.points.push_back(f(Vec3f(x, 10.f - 0.5f * i, z), i));
            h.offsets.push_back(static_cast<uint32_t>(h.points.size()));
        }
    h.default_width = 0.05f;
    return h;
}

Hair grid() {
    return grid([](const Vec3f& p, int) { return p; });
}

CompareOptions front_only() {
    CompareOptions o;
    o.views = {"front"};
    o.size = 128;
    return o;
}

TEST(Compare, IdenticalHairScoresPerfectly) {
    const Hair h = grid();
    const CompareResult r = compare_hair(h, h, nullptr, front_only());
    ASSERT_EQ(r.strands.size(), 3u);
    for (const StrandScore& s : r.strands) {
        EXPECT_EQ(s.precision, 1.0);
        EXPECT_EQ(s.recall, 1.0);
        EXPECT_EQ(s.f1, 1.0);
    }
    EXPECT_EQ(r.chamfer_a_to_b, 0.0);
    EXPECT_EQ(r.chamfer_b_to_a, 0.0);
    EXPECT_TRUE(r.corresponding);
    EXPECT_NEAR(r.position_error, 0.0, 1e-6);
    EXPECT_NEAR(r.curvature_error, 0.0, 1e-6);
    EXPECT_EQ(r.orientation_error, 0.0);
    EXPECT_EQ(r.silhouette_iou, 1.0);
    EXPECT_EQ(r.occupancy_iou, 1.0);
}

// Shifted sideways by δ, every point is δ from its own strand's and 2 − δ from the next: F1
// is 1 at the thresholds beyond δ and 0 at those within it.
TEST(Compare, ShiftedHairFallsAsTheShiftPassesEachThreshold) {
    const Hair b = grid();
    struct Case {
        float shift;
        double f1[3];  // at 2, 3, 4 mm
    };
    for (const Case& c : {Case{0.1f, {1, 1, 1}}, Case{0.25f, {0, 1, 1}}, Case{0.35f, {0, 0, 1}},
                          Case{0.5f, {0, 0, 0}}}) {
        const Hair a = grid([&](const Vec3f& p, int) { return Vec3f(p + Vec3f(c.shift, 0, 0)); });
        const CompareResult r = compare_hair(a, b, nullptr, front_only());
        for (int k = 0; k < 3; ++k)
            EXPECT_EQ(r.strands[k].f1, c.f1[k]) << "shift " << c.shift << " threshold " << k;
        EXPECT_NEAR(r.chamfer_a_to_b, c.shift, 1e-4);
        EXPECT_NEAR(r.position_error, c.shift, 1e-4);
        EXPECT_NEAR(r.curvature_error, 0.0, 1e-4);
    }
}

// Strands tilted by 25° about their roots match at 30° and 40°, not at 20°, where their points
// stay within reach: the first few below the root.
TEST(Compare, TiltedStrandsMatchOnlyAtWiderAngles) {
    const Hair b = grid();
    const float t = 25.f * kPi / 180.f;
    const Hair a = grid([&](const Vec3f& p, int i) {
        const float along = 0.5f * i;
        return Vec3f(p.x() + along * std::sin(t), 10.f - along * std::cos(t), p.z());
    });
    const CompareResult r = compare_hair(a, b, nullptr, front_only());
    EXPECT_EQ(r.strands[0].precision, 0.0);  // 20°: the root itself is its only near point
    EXPECT_GT(r.strands[1].precision, 0.0);  // 30°: the points within 3 mm of the strand
    EXPECT_GT(r.strands[2].precision, r.strands[1].precision);
    // The roots' direction is the strand's own, so even the root does not match at 20°.
}

// Hair turned by 10° in the picture's plane: its orientation map differs by 10° wherever the
// masks overlap.
TEST(Compare, OrientationErrorOfAHairTurnedInThePicture) {
    const Hair b = grid();
    const float t = 10.f * kPi / 180.f;
    const Hair a = grid([&](const Vec3f& p, int) {
        return Vec3f(p.x() * std::cos(t) - p.y() * std::sin(t),
                     p.x() * std::sin(t) + p.y() * std::cos(t), p.z());
    });
    const CompareResult r = compare_hair(a, b, nullptr, front_only());
    EXPECT_NEAR(r.orientation_error, 10.0, 1.0);
    EXPECT_GT(r.silhouette_iou, 0.0);
    EXPECT_LT(r.silhouette_iou, 1.0);
}

TEST(Compare, DifferentStrandCountsHaveNoCorrespondence) {
    Hair fewer = grid();
    fewer.points.resize(41 * 10);
    fewer.offsets.resize(11);
    const CompareResult r = compare_hair(fewer, grid(), nullptr, front_only());
    EXPECT_FALSE(r.corresponding);
    EXPECT_EQ(r.strands[2].precision, 1.0);  // every point of the subset is in the whole
    EXPECT_LT(r.strands[2].recall, 0.2);
    EXPECT_FALSE(to_json(r).contains("position_error_cm"));
    EXPECT_EQ(to_json(r)["strands"][2]["recall"], r.strands[2].recall);
}

TEST(Compare, BadInputIsRefused) {
    EXPECT_THROW(compare_hair(grid(), Hair{}, nullptr, front_only()), Error);
    CompareOptions o = front_only();
    o.voxel = 0.f;
    EXPECT_THROW(compare_hair(grid(), grid(), nullptr, o), Error);
    o = front_only();
    o.thresholds = {{0.2f, 95.f}};
    EXPECT_THROW(compare_hair(grid(), grid(), nullptr, o), Error);
    // Hair half a kilometre apart: a millimetre grid over both would be huge; a clear error,
    // not an allocation.
    const Hair far = grid([](const Vec3f& p, int) { return Vec3f(p + Vec3f(5e4f, 0, 0)); });
    o = front_only();
    o.voxel = 0.1f;
    try {
        compare_hair(far, grid(), nullptr, o);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("give a larger voxel"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace wisp
