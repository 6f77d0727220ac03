#include "groom/growth.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.hpp"
#include "core/image.hpp"
#include "core/rng.hpp"
#include "geometry/scalp.hpp"
#include "groom/head.hpp"
#include "groom/style_toml.hpp"

namespace wisp {
namespace {

Vec3f dir(float x, float y, float z) {
    return Vec3f(x, y, z).normalized();
}

TEST(Growth, UnitAndTangentEverywhere) {
    Rng rng(3, Stream::kRoll, 0);
    for (GrowthSpec::Part part :
         {GrowthSpec::Part::kNone, GrowthSpec::Part::kCentre, GrowthSpec::Part::kSide})
        for (GrowthSpec::Front front :
             {GrowthSpec::Front::kSides, GrowthSpec::Front::kBack, GrowthSpec::Front::kFringe}) {
            GrowthSpec spec;
            spec.part = part;
            spec.front = front;
            for (int i = 0; i < 2000; ++i) {
                const Vec3f r = dir(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
                const Vec3f g = growth_direction(spec, r);
                ASSERT_TRUE(g.allFinite());
                EXPECT_NEAR(g.norm(), 1.f, 1e-4f);
                EXPECT_NEAR(g.dot(r), 0.f, 1e-4f);
            }
        }
}

TEST(Growth, APartSplitsTheTopToEitherSide) {
    GrowthSpec spec;  // centre part
    EXPECT_GT(growth_direction(spec, dir(0.2f, 0.9f, 0.3f)).x(), 0.5f);
    EXPECT_LT(growth_direction(spec, dir(-0.2f, 0.9f, 0.3f)).x(), -0.5f);
    spec.part = GrowthSpec::Part::kSide;
    spec.part_offset = 0.35f;  // on the left: hair between it and the midline goes right
    EXPECT_LT(growth_direction(spec, dir(0.2f, 0.9f, 0.3f)).x(), -0.5f);
    EXPECT_GT(growth_direction(spec, dir(0.5f, 0.8f, 0.3f)).x(), 0.3f);
    EXPECT_TRUE(on_part(spec, dir(0.35f, 0.85f, 0.4f), 0.05f));
    EXPECT_FALSE(on_part(spec, dir(0.f, 0.85f, 0.4f), 0.05f));
    spec.part = GrowthSpec::Part::kNone;
    EXPECT_FALSE(on_part(spec, dir(0.f, 0.85f, 0.4f), 0.05f));
}

TEST(Growth, PartNearnessFollowsThePartAndFadesBesideIt) {
    // The part maps' lift: full on the part line over the top, none a hand's width beside it
    // or behind where the part ends, none at all without a part; a side part moves it.
    GrowthSpec centre;
    EXPECT_NEAR(part_nearness(centre, dir(0.f, 0.9f, 0.4f), 0.14f), 1.f, 1e-4f);
    EXPECT_GT(part_nearness(centre, dir(0.05f, 0.9f, 0.4f), 0.14f), 0.5f);
    EXPECT_EQ(part_nearness(centre, dir(0.3f, 0.9f, 0.4f), 0.14f), 0.f);
    EXPECT_EQ(part_nearness(centre, dir(0.f, -0.3f, -0.95f), 0.14f), 0.f) << "the nape";
    GrowthSpec none;
    none.part = GrowthSpec::Part::kNone;
    EXPECT_EQ(part_nearness(none, dir(0.f, 0.9f, 0.4f), 0.14f), 0.f);
    GrowthSpec side;
    side.part = GrowthSpec::Part::kSide;
    EXPECT_EQ(part_nearness(side, dir(0.f, 0.9f, 0.4f), 0.14f), 0.f);
    EXPECT_GT(part_nearness(side, Vec3f(side.part_offset, 0.9f, 0.3f).normalized(), 0.14f), 0.7f);
}

TEST(Growth, FrontHairlineHairGoesToTheSidesBackOrForward) {
    const Vec3f forehead_left = dir(0.15f, 0.45f, 0.88f);
    GrowthSpec spec;
    const Vec3f sides = growth_direction(spec, forehead_left);
    EXPECT_GT(sides.x(), 0.5f);  // to the left temple
    EXPECT_LT(sides.z(), 0.f);   // and back, never over the face
    spec.front = GrowthSpec::Front::kBack;
    EXPECT_LT(growth_direction(spec, dir(0.f, 0.45f, 0.88f)).z(), -0.1f);
    spec.front = GrowthSpec::Front::kFringe;
    spec.part = GrowthSpec::Part::kNone;
    const Vec3f fringe = growth_direction(spec, dir(0.f, 0.45f, 0.88f));
    EXPECT_LT(fringe.y(), -0.5f);  // down over the forehead
}

// Combed back, all of the top ahead of the whorl runs back, and neighbours either side of the
// midline run nearly alike: hair that grew forward from the whorl to meet hair combed back
// from the hairline would part along the seam.
TEST(Growth, CombedBackTheTopRunsBackWithoutASeam) {
    GrowthSpec spec;
    spec.part = GrowthSpec::Part::kNone;
    spec.front = GrowthSpec::Front::kBack;
    const Vec3f whorl = spec.whorl.normalized();
    for (float z = 0.f; z <= 0.9f; z += 0.05f) {
        const float y = std::sqrt(1.f - z * z);
        const Vec3f mid = dir(0.f, y, z);
        if (std::acos(mid.dot(whorl)) < 0.45f) continue;  // the whorl itself turns
        const Vec3f left = growth_direction(spec, dir(0.04f, y, z));
        const Vec3f right = growth_direction(spec, dir(-0.04f, y, z));
        EXPECT_LT(left.z(), -0.5f) << "z " << z;
        EXPECT_LT(right.z(), -0.5f) << "z " << z;
        EXPECT_GT(left.dot(right), 0.95f) << "z " << z;
    }
}

TEST(Growth, HairTurnsAboutTheWhorlInItsSense) {
    GrowthSpec spec;
    spec.part = GrowthSpec::Part::kNone;
    spec.whorl = Vec3f::UnitY();
    // Just behind the whorl, seen from above: clockwise turns from -Z toward +X... measured
    // as the sign of the turn about +Y, (r × g)·Y < 0 for clockwise.
    const Vec3f r = dir(0.f, 0.95f, -0.3f);
    spec.whorl_turn = 1.f;
    const float cw = r.cross(growth_direction(spec, r)).y();
    spec.whorl_turn = -1.f;
    const float ccw = r.cross(growth_direction(spec, r)).y();
    EXPECT_LT(cw, 0.f);
    EXPECT_GT(ccw, 0.f);
    // Far from the whorl, no turn: the nape grows down.
    EXPECT_LT(growth_direction(spec, dir(0.f, -0.3f, -0.95f)).y(), -0.8f);
}

TEST(Growth, ReadFromTheStyle) {
    const Style s = parse_style(R"(
[growth]
part = "right"
part_offset = 0.4
part_length = 0.7
front = "fringe"
whorl = [0.1, 1.0, -0.3]
whorl_turn = "counter-clockwise"
whorl_swirl = 1.2
map = "flow.png"
map_strength = 0.5
)",
                                "growth.toml");
    EXPECT_EQ(s.growth.part, GrowthSpec::Part::kSide);
    EXPECT_FLOAT_EQ(s.growth.part_offset, -0.4f);
    EXPECT_FLOAT_EQ(s.growth.part_length, 0.7f);
    EXPECT_EQ(s.growth.front, GrowthSpec::Front::kFringe);
    EXPECT_FLOAT_EQ(s.growth.whorl.x(), 0.1f);
    EXPECT_FLOAT_EQ(s.growth.whorl_turn, -1.f);
    EXPECT_FLOAT_EQ(s.growth.whorl_swirl, 1.2f);
    EXPECT_EQ(s.growth.map.filename(), "flow.png");
    EXPECT_FLOAT_EQ(s.growth.map_strength, 0.5f);
    // The default field now includes the growth term.
    const Style empty = parse_style("", "empty.toml");
    ASSERT_EQ(empty.solve.field.size(), 2u);
    EXPECT_EQ(empty.solve.field[1].kind, FieldTerm::Kind::kGrowth);
    EXPECT_THROW(parse_style("[growth]\npart = \"middle\"\n", "bad.toml"), Error);
    EXPECT_THROW(parse_style("[growth]\nwhorl = [0, 0, 0]\n", "bad.toml"), Error);
    EXPECT_THROW(parse_style("[growth]\npart_offset = 2\n", "bad.toml"), Error);
}

// A growth map in the top view that points every root toward the image's right (the subject's
// right, −X) on the left half of the image and leaves the right half neutral grey.
TEST(Growth, MapTakesOverWhereItIsStrong) {
    namespace fs = std::filesystem;
    const fs::path file = fs::temp_directory_path() / "wisp_growth_map_test.png";
    RgbImage img;
    img.width = img.height = 64;
    img.rgb.resize(64 * 64 * 3);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            uint8_t* px = &img.rgb[(static_cast<size_t>(j) * 64 + i) * 3];
            px[0] = i < 32 ? 255 : 128;  // right on the image's left half (the subject's left)
            px[1] = 128;
            px[2] = 128;
        }
    write_png(file, img);
    const Head head = load_head(HeadSpec{});
    GrowthSpec spec;
    spec.map = file;
    const GrowthField with_map(spec, *head.scalp);
    const GrowthField without(GrowthSpec{}, *head.scalp);
    // On the top of the subject's left (+X, image left), hair now grows toward −X over the
    // crown; on the right, the map is neutral and the procedural directions stay.
    const Vec3f left = dir(0.5f, 0.8f, 0.1f), right = dir(-0.5f, 0.8f, 0.1f);
    EXPECT_LT(with_map(left).x(), -0.5f);
    EXPECT_GT(without(left).x(), 0.3f);
    EXPECT_TRUE(with_map(right).isApprox(without(right), 1e-5f));
    EXPECT_NEAR(with_map(left).dot(left), 0.f, 1e-4f);
    spec.map_strength = 0.f;
    EXPECT_TRUE(GrowthField(spec, *head.scalp)(left).isApprox(without(left), 1e-5f));
    // A map that cannot be read names itself.
    spec.map = file.string() + ".missing";
    try {
        GrowthField bad(spec, *head.scalp);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(".missing"), std::string::npos) << e.what();
    }
    fs::remove(file);
}

}  // namespace
}  // namespace wisp
