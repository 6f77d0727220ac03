#include "groom/style_toml.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "groom/hairdressing.hpp"
#include "groom/maps.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

void expect_same(const Distribution& a, const Distribution& b, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.min, b.min);
    EXPECT_EQ(a.max, b.max);
    EXPECT_EQ(a.mean, b.mean);
    EXPECT_EQ(a.stddev, b.stddev);
    EXPECT_EQ(a.table, b.table);
}

void expect_same(const ScalarMap& a, const ScalarMap& b, const std::string& what) {
    SCOPED_TRACE(what);
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.image, b.image);
    EXPECT_EQ(a.procedural, b.procedural);
    EXPECT_EQ(a.low, b.low);
    EXPECT_EQ(a.high, b.high);
}

// Field-by-field equality of two styles (Style has no operator==).
void expect_same(const Style& a, const Style& b) {
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.seed, b.seed);
    EXPECT_EQ(a.head.obj, b.head.obj);
    EXPECT_EQ(a.head.scale, b.head.scale);
    EXPECT_EQ(a.head.scalp.kind, b.head.scalp.kind);
    EXPECT_EQ(a.head.scalp.group, b.head.scalp.group);
    EXPECT_EQ(a.head.scalp.mask, b.head.scalp.mask);
    EXPECT_EQ(a.head.scalp.hairline_front, b.head.scalp.hairline_front);
    EXPECT_EQ(a.head.scalp.hairline_side, b.head.scalp.hairline_side);
    EXPECT_EQ(a.head.scalp.hairline_back, b.head.scalp.hairline_back);
    EXPECT_EQ(a.wisps, b.wisps);
    EXPECT_EQ(a.strands, b.strands);
    EXPECT_EQ(a.points_per_strand, b.points_per_strand);
    expect_same(a.density, b.density, "density");
    expect_same(a.length, b.length, "length");
    expect_same(a.protrusion, b.protrusion, "protrusion");
    EXPECT_EQ(a.root_width, b.root_width);
    EXPECT_EQ(a.tip_width, b.tip_width);
    EXPECT_EQ(a.prototype.kind, b.prototype.kind);
    EXPECT_EQ(a.prototype.amplitude, b.prototype.amplitude);
    EXPECT_EQ(a.prototype.period, b.prototype.period);
    EXPECT_EQ(a.prototype.length, b.prototype.length);
    EXPECT_EQ(a.prototype.polyline.size(), b.prototype.polyline.size());
    EXPECT_EQ(a.prototype.window, b.prototype.window);
    EXPECT_EQ(a.prototype.temperature, b.prototype.temperature);
    EXPECT_EQ(a.prototype.roll, b.prototype.roll);
    expect_same(a.wisp.length, b.wisp.length, "wisp.length");
    EXPECT_EQ(a.wisp.deviation_radius, b.wisp.deviation_radius);
    EXPECT_EQ(a.wisp.fuzziness, b.wisp.fuzziness);
    expect_same(a.color.hue, b.color.hue, "hue");
    expect_same(a.color.saturation, b.color.saturation, "saturation");
    expect_same(a.color.value, b.color.value, "value");
    EXPECT_EQ(a.color.wisp_hue, b.color.wisp_hue);
    EXPECT_EQ(a.color.wisp_saturation, b.color.wisp_saturation);
    EXPECT_EQ(a.color.wisp_value, b.color.wisp_value);
    EXPECT_EQ(a.solve.enabled, b.solve.enabled);
    EXPECT_EQ(a.solve.stiffness, b.solve.stiffness);
    EXPECT_EQ(a.solve.threshold, b.solve.threshold);
    EXPECT_EQ(a.solve.cell, b.solve.cell);
    EXPECT_EQ(a.solve.full_density, b.solve.full_density);
    EXPECT_EQ(a.solve.bend_step, b.solve.bend_step);
    EXPECT_EQ(a.solve.max_tries, b.solve.max_tries);
    EXPECT_EQ(a.solve.depth_first, b.solve.depth_first);
    EXPECT_EQ(a.solve.head_margin, b.solve.head_margin);
    ASSERT_EQ(a.solve.field.size(), b.solve.field.size());
    for (size_t i = 0; i < a.solve.field.size(); ++i) {
        EXPECT_EQ(a.solve.field[i].kind, b.solve.field[i].kind);
        EXPECT_EQ(a.solve.field[i].weight, b.solve.field[i].weight);
    }
    EXPECT_EQ(a.cut.enabled, b.cut.enabled);
    EXPECT_EQ(a.cut.normal, b.cut.normal);
    EXPECT_EQ(a.cut.offset, b.cut.offset);
    EXPECT_EQ(a.cut.head_relative, b.cut.head_relative);
    EXPECT_EQ(a.groups.size(), b.groups.size());
}

Style parse(const std::string& text) {
    return parse_style(text, "test.toml", "/styles");
}

// The message of the wisp::Error that parsing `text` throws ("" if it does not throw).
std::string error_of(const std::string& text) {
    try {
        parse(text);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(StyleToml, EmptyTextGivesTheDefaults) {
    expect_same(parse(""), Style{});
    expect_same(parse("# only a comment\n\n"), Style{});
    expect_same(parse("[roots]\n[wisp]\n[color]\n[solve]\n"), Style{});
}

TEST(StyleToml, ReadsEveryField) {
    const Style s = parse(R"(
name = "test style"
seed = 42
[head]
obj = "heads/me.obj"
scale = 2.5
[head.scalp]
method = "hairline"
front = 5
side = 9.5
back = 13
[roots]
wisps = 500
strands = 20000
points_per_strand = 48
[maps]
density = "side-part"
length = { image = "len.png", low = 5, high = 30 }
protrusion = { procedural = "crown", low = 0.1, high = 0.6 }
[strand]
root_width = 0.01
tip_width = 0.001
[prototype]
shape = "curly"
amplitude = 1.1
period = 2.4
length = 35
window = 6
temperature = 0.07
roll = 1.0
[wisp]
length = { distribution = "table", values = [0, 1, 3], min = 0.5, max = 1 }
deviation_radius = [1, 2, 3, 4]
fuzziness = 0.9
[color]
hue = { distribution = "uniform", min = 20, max = 40 }
saturation = 0.5
value = { distribution = "normal", mean = 0.4, stddev = 0.05 }
wisp_hue = 3
wisp_saturation = 0.05
wisp_value = 0.02
)");
    EXPECT_EQ(s.name, "test style");
    EXPECT_EQ(s.seed, 42u);
    EXPECT_EQ(s.head.obj, fs::path("/styles/heads/me.obj"));
    EXPECT_FLOAT_EQ(s.head.scale, 2.5f);
    EXPECT_EQ(s.head.scalp.kind, ScalpSpec::Kind::kHairline);
    EXPECT_FLOAT_EQ(s.head.scalp.hairline_front, 5.f);
    EXPECT_FLOAT_EQ(s.head.scalp.hairline_side, 9.5f);
    EXPECT_FLOAT_EQ(s.head.scalp.hairline_back, 13.f);
    EXPECT_EQ(s.wisps, 500);
    EXPECT_EQ(s.strands, 20000);
    EXPECT_EQ(s.points_per_strand, 48);
    EXPECT_EQ(s.density.kind, ScalarMap::Kind::kProcedural);
    EXPECT_EQ(s.density.procedural, "side-part");
    EXPECT_FLOAT_EQ(s.density.low, 0.f);
    EXPECT_FLOAT_EQ(s.density.high, 1.f);
    EXPECT_EQ(s.length.kind, ScalarMap::Kind::kImage);
    EXPECT_EQ(s.length.image, fs::path("/styles/len.png"));
    EXPECT_FLOAT_EQ(s.length.low, 5.f);
    EXPECT_FLOAT_EQ(s.length.high, 30.f);
    EXPECT_EQ(s.protrusion.kind, ScalarMap::Kind::kProcedural);
    EXPECT_EQ(s.protrusion.procedural, "crown");
    EXPECT_FLOAT_EQ(s.protrusion.low, 0.1f);
    EXPECT_FLOAT_EQ(s.protrusion.high, 0.6f);
    EXPECT_FLOAT_EQ(s.root_width, 0.01f);
    EXPECT_FLOAT_EQ(s.tip_width, 0.001f);
    EXPECT_EQ(s.prototype.kind, PrototypeSpec::Kind::kCurly);
    EXPECT_FLOAT_EQ(s.prototype.amplitude, 1.1f);
    EXPECT_FLOAT_EQ(s.prototype.period, 2.4f);
    EXPECT_FLOAT_EQ(s.prototype.length, 35.f);
    EXPECT_EQ(s.prototype.window, 6);
    EXPECT_FLOAT_EQ(s.prototype.temperature, 0.07f);
    EXPECT_FLOAT_EQ(s.prototype.roll, 1.f);
    EXPECT_EQ(s.wisp.length.kind, Distribution::Kind::kTable);
    EXPECT_EQ(s.wisp.length.table, (std::vector<float>{0, 1, 3}));
    EXPECT_FLOAT_EQ(s.wisp.length.min, 0.5f);
    EXPECT_FLOAT_EQ(s.wisp.length.max, 1.f);
    EXPECT_EQ(s.wisp.deviation_radius, (std::vector<float>{1, 2, 3, 4}));
    EXPECT_FLOAT_EQ(s.wisp.fuzziness, 0.9f);
    EXPECT_EQ(s.color.hue.kind, Distribution::Kind::kUniform);
    EXPECT_FLOAT_EQ(s.color.hue.min, 20.f);
    EXPECT_FLOAT_EQ(s.color.hue.max, 40.f);
    EXPECT_EQ(s.color.saturation.kind, Distribution::Kind::kConstant);
    EXPECT_FLOAT_EQ(s.color.saturation.value, 0.5f);
    EXPECT_EQ(s.color.value.kind, Distribution::Kind::kNormal);
    EXPECT_FLOAT_EQ(s.color.value.mean, 0.4f);
    EXPECT_FLOAT_EQ(s.color.value.stddev, 0.05f);
    EXPECT_FLOAT_EQ(s.color.value.min, 0.f);  // truncation range defaults to the domain
    EXPECT_FLOAT_EQ(s.color.value.max, 1.f);
    EXPECT_FLOAT_EQ(s.color.wisp_hue, 3.f);
    EXPECT_FLOAT_EQ(s.color.wisp_saturation, 0.05f);
    EXPECT_FLOAT_EQ(s.color.wisp_value, 0.02f);
}

TEST(StyleToml, MapForms) {
    const Style s = parse(R"(
[maps]
density = 2
length = "bangs"
protrusion = { value = 0.7 }
)");
    EXPECT_EQ(s.density.kind, ScalarMap::Kind::kConstant);
    EXPECT_FLOAT_EQ(s.density.value, 2.f);
    EXPECT_EQ(s.length.kind, ScalarMap::Kind::kProcedural);
    EXPECT_EQ(s.length.procedural, "bangs");
    EXPECT_FLOAT_EQ(s.length.low, 1.f);  // documented defaults for length maps
    EXPECT_FLOAT_EQ(s.length.high, 25.f);
    EXPECT_EQ(s.protrusion.kind, ScalarMap::Kind::kConstant);
    EXPECT_FLOAT_EQ(s.protrusion.value, 0.7f);
    for (const auto& name : procedural_map_names())
        EXPECT_EQ(parse("maps.density = \"" + name + "\"").density.procedural, name);
}

TEST(StyleToml, ScalpMethodIsInferredFromItsKeys) {
    EXPECT_EQ(parse("[head.scalp]\nmask = \"m.png\"").head.scalp.kind, ScalpSpec::Kind::kMask);
    EXPECT_EQ(parse("[head.scalp]\nmask = \"m.png\"").head.scalp.mask, fs::path("/styles/m.png"));
    EXPECT_EQ(parse("[head.scalp]\nfront = 7").head.scalp.kind, ScalpSpec::Kind::kHairline);
    const Style g = parse("[head.scalp]\ngroup = \"hair\"");
    EXPECT_EQ(g.head.scalp.kind, ScalpSpec::Kind::kGroup);
    EXPECT_EQ(g.head.scalp.group, "hair");
}

TEST(StyleToml, PolylinePrototype) {
    const Style s = parse(R"(
[prototype]
points = [[0, 0, 0], [0, -1, 0.2], [0, -2, 0], [0, -3, -0.2], [0, -4, 0]]
window = 2
)");
    EXPECT_EQ(s.prototype.kind, PrototypeSpec::Kind::kPolyline);
    ASSERT_EQ(s.prototype.polyline.size(), 5u);
    EXPECT_FLOAT_EQ(s.prototype.polyline[3].z(), -0.2f);
    EXPECT_FLOAT_EQ(s.prototype.polyline[4].y(), -4.f);
}

TEST(StyleToml, DistributionWithoutKindAdjustsTheCurrentOne) {
    // The default hue is normal(30, 2) over [0, 360]: only the mean changes.
    const Style s = parse("[color]\nhue = { mean = 20 }\n[wisp]\nlength = { min = 0.5 }");
    EXPECT_EQ(s.color.hue.kind, Distribution::Kind::kNormal);
    EXPECT_FLOAT_EQ(s.color.hue.mean, 20.f);
    EXPECT_FLOAT_EQ(s.color.hue.stddev, Style{}.color.hue.stddev);
    EXPECT_EQ(s.wisp.length.kind, Distribution::Kind::kUniform);
    EXPECT_FLOAT_EQ(s.wisp.length.min, 0.5f);
    EXPECT_FLOAT_EQ(s.wisp.length.max, Style{}.wisp.length.max);
}

TEST(StyleToml, ColorPresetThenExplicitFields) {
    const Style blonde = parse("[color]\npreset = \"blonde\"");
    EXPECT_EQ(blonde.color.value.kind, Distribution::Kind::kNormal);
    EXPECT_GT(blonde.color.value.mean, 0.6f);
    EXPECT_GT(blonde.color.wisp_value, 0.f);
    const Style black = parse("[color]\npreset = \"black\"");
    EXPECT_LT(black.color.value.mean, 0.15f);

    const Style mixed = parse("[color]\npreset = \"blonde\"\nvalue = { mean = 0.5 }\nwisp_hue = 0");
    EXPECT_FLOAT_EQ(mixed.color.value.mean, 0.5f);
    EXPECT_FLOAT_EQ(mixed.color.value.stddev, blonde.color.value.stddev);
    EXPECT_FLOAT_EQ(mixed.color.hue.mean, blonde.color.hue.mean);
    EXPECT_FLOAT_EQ(mixed.color.wisp_hue, 0.f);

    for (const char* name :
         {"black", "dark-brown", "brown", "auburn", "blonde", "platinum", "red", "gray"}) {
        const Style s = parse(std::string("color.preset = \"") + name + "\"");
        EXPECT_EQ(s.color.hue.kind, Distribution::Kind::kNormal) << name;
    }
}

TEST(StyleToml, ReadsSolveAndCut) {
    const Style s = parse(R"(
[solve]
enabled = false
stiffness = 2.5
threshold = 0.1
cell = 0.5
full_density = 150
bend_step = 6
max_tries = 40
order = "depth-first"
head_margin = 0.5
[[solve.field]]
kind = "gravity"
weight = 0.5
[[solve.field]]
kind = "wind"
weight = 0.3
direction = [1, 0, 0]
[[solve.field]]
kind = "side-part"
side = "right"
[[solve.field]]
kind = "pulled-back"
weight = -0.2
[[solve.field]]
kind = "file"
file = "fields/swirl.field"
[cut]
normal = [0, -1, 0.2]
offset = 1.4
head_relative = false
)");
    EXPECT_FALSE(s.solve.enabled);
    EXPECT_FLOAT_EQ(s.solve.stiffness, 2.5f);
    EXPECT_FLOAT_EQ(s.solve.threshold, 0.1f);
    EXPECT_FLOAT_EQ(s.solve.cell, 0.5f);
    EXPECT_FLOAT_EQ(s.solve.full_density, 150.f);
    EXPECT_FLOAT_EQ(s.solve.bend_step, 6.f);
    EXPECT_EQ(s.solve.max_tries, 40);
    EXPECT_TRUE(s.solve.depth_first);
    EXPECT_FLOAT_EQ(s.solve.head_margin, 0.5f);
    ASSERT_EQ(s.solve.field.size(), 5u);
    EXPECT_EQ(s.solve.field[0].kind, FieldTerm::Kind::kGravity);
    EXPECT_FLOAT_EQ(s.solve.field[0].weight, 0.5f);
    EXPECT_EQ(s.solve.field[1].kind, FieldTerm::Kind::kWind);
    EXPECT_TRUE(s.solve.field[1].direction.isApprox(Vec3f(1, 0, 0)));
    EXPECT_EQ(s.solve.field[2].kind, FieldTerm::Kind::kSidePart);
    EXPECT_FLOAT_EQ(s.solve.field[2].side, -1.f);
    EXPECT_FLOAT_EQ(s.solve.field[2].weight, 1.f);
    EXPECT_EQ(s.solve.field[3].kind, FieldTerm::Kind::kPulledBack);
    EXPECT_FLOAT_EQ(s.solve.field[3].weight, -0.2f);
    EXPECT_EQ(s.solve.field[4].kind, FieldTerm::Kind::kFile);
    EXPECT_EQ(s.solve.field[4].file, fs::path("/styles/fields/swirl.field"));
    EXPECT_TRUE(s.cut.enabled);
    EXPECT_TRUE(s.cut.normal.isApprox(Vec3f(0, -1, 0.2f)));
    EXPECT_FLOAT_EQ(s.cut.offset, 1.4f);
    EXPECT_FALSE(s.cut.head_relative);
    EXPECT_EQ(parse("[solve]\norder = \"breadth-first\"").solve.depth_first, false);
    EXPECT_FLOAT_EQ(parse("[[solve.field]]\nkind = \"side-part\"").solve.field[0].side, 1.f);
}

TEST(StyleToml, FieldTermsReplaceTheDefaultGravity) {
    const Style none = parse("[solve]\nstiffness = 1");
    ASSERT_EQ(none.solve.field.size(), 2u);  // gravity and the growth term
    EXPECT_EQ(none.solve.field[0].kind, FieldTerm::Kind::kGravity);
    EXPECT_FLOAT_EQ(none.solve.field[0].weight, 1.f);
    EXPECT_EQ(none.solve.field[1].kind, FieldTerm::Kind::kGrowth);
    EXPECT_FLOAT_EQ(none.solve.field[1].weight, 1.5f);
    const Style wind = parse("[[solve.field]]\nkind = \"wind\"");
    ASSERT_EQ(wind.solve.field.size(), 1u);
    EXPECT_EQ(wind.solve.field[0].kind, FieldTerm::Kind::kWind);
    EXPECT_TRUE(wind.solve.field[0].direction.isApprox(FieldTerm{}.direction));
    EXPECT_TRUE(parse("solve.field = []").solve.field.empty());  // no force at all
}

TEST(StyleToml, CutIsEnabledByItsSection) {
    EXPECT_FALSE(parse("").cut.enabled);
    const Style cut = parse("[cut]\noffset = 1.5");
    EXPECT_TRUE(cut.cut.enabled);
    EXPECT_TRUE(cut.cut.head_relative);
    EXPECT_TRUE(cut.cut.normal.isApprox(CutSpec{}.normal));
    EXPECT_FALSE(parse("[cut]\nenabled = false").cut.enabled);
}

TEST(StyleToml, GroupsSelectEveryWayAndQueueTheirConstraints) {
    const Style s = parse(R"(
[roots]
wisps = 100
strands = 1000
[[group]]
name = "fringe"
region = "bangs"
[[group.constraint]]
kind = "point"
point = [0, 0.5, 1.2]
radius = 0.2
weight = 0.7
[[group.constraint]]
kind = "trajectory"
trajectory = [[0, 0.5, 1.2], [0.5, 0, 1.1], [0.9, -0.5, 0.6]]
smooth = true
hold = true
[[group]]
mask = "left.png"
part = 1
parts = 2
head_relative = false
[[group.constraint]]
kind = "direction"
trajectory = [[5, 10, 0], [10, 0, -5]]
[[group.constraint]]
kind = "point"
point = [0, 0, -14]
head_relative = true
hold = false
[[group]]
box = { min = [-1, 0, -2], max = [1, 2, 0] }
[[group.constraint]]
kind = "point"
point = [0, 0, -1.2]
[[group]]
half_space = { normal = [0, 0, -1], offset = 0.2 }
[[group.constraint]]
kind = "point"
point = [0, 0, -1.2]
[[group]]
wisps = [0, 5, 99]
[[group.constraint]]
kind = "point"
point = [0, 0, -1.2]
[[group]]
select = "all"
[[group.constraint]]
kind = "point"
point = [0, 0, -1.2]
)");
    ASSERT_EQ(s.groups.size(), 6u);
    const GroupSpec& fringe = s.groups[0];
    EXPECT_EQ(fringe.name, "fringe");
    EXPECT_EQ(fringe.selection.kind, Selection::Kind::kRegion);
    EXPECT_EQ(fringe.selection.region, "bangs");
    EXPECT_EQ(fringe.selection.part, 0);
    EXPECT_EQ(fringe.selection.parts, 1);
    EXPECT_TRUE(fringe.selection.head_relative);
    ASSERT_EQ(fringe.queue.size(), 2u);
    EXPECT_EQ(fringe.queue[0].kind, ConstraintSpec::Kind::kPoint);
    EXPECT_TRUE(fringe.queue[0].point.isApprox(Vec3f(0, 0.5f, 1.2f)));
    EXPECT_FLOAT_EQ(fringe.queue[0].radius, 0.2f);
    EXPECT_FLOAT_EQ(fringe.queue[0].weight, 0.7f);
    EXPECT_TRUE(fringe.queue[0].head_relative);
    EXPECT_EQ(fringe.queue[1].kind, ConstraintSpec::Kind::kTrajectory);
    ASSERT_EQ(fringe.queue[1].trajectory.size(), 3u);
    EXPECT_TRUE(fringe.queue[1].trajectory[2].isApprox(Vec3f(0.9f, -0.5f, 0.6f)));
    EXPECT_TRUE(fringe.queue[1].smooth);
    EXPECT_FLOAT_EQ(fringe.queue[1].radius, 0.1f);  // documented default, head units
    EXPECT_FLOAT_EQ(fringe.queue[1].weight, 1.f);
    EXPECT_TRUE(fringe.queue[0].hold);  // a point constraint holds by default (a tie)
    EXPECT_TRUE(fringe.queue[1].hold);  // a trajectory when asked (hairpins)

    const GroupSpec& masked = s.groups[1];
    EXPECT_EQ(masked.name, "group[1]");
    EXPECT_EQ(masked.selection.kind, Selection::Kind::kMask);
    EXPECT_EQ(masked.selection.mask, fs::path("/styles/left.png"));
    EXPECT_EQ(masked.selection.part, 1);
    EXPECT_EQ(masked.selection.parts, 2);
    EXPECT_FALSE(masked.selection.head_relative);
    ASSERT_EQ(masked.queue.size(), 2u);
    EXPECT_EQ(masked.queue[0].kind, ConstraintSpec::Kind::kDirection);
    EXPECT_FALSE(masked.queue[0].head_relative);  // inherited from the group
    EXPECT_FALSE(masked.queue[0].smooth);
    EXPECT_FLOAT_EQ(masked.queue[0].radius, 4.f);   // a direction's default influence, in cm
    EXPECT_TRUE(masked.queue[1].head_relative);     // its own setting wins
    EXPECT_FLOAT_EQ(masked.queue[1].radius, 0.1f);  // … and its default radius follows it
    EXPECT_FALSE(masked.queue[0].hold);             // a direction does not hold by default
    EXPECT_FALSE(masked.queue[1].hold);             // a point asked not to

    EXPECT_EQ(s.groups[2].selection.kind, Selection::Kind::kBox);
    EXPECT_TRUE(s.groups[2].selection.lo.isApprox(Vec3f(-1, 0, -2)));
    EXPECT_TRUE(s.groups[2].selection.hi.isApprox(Vec3f(1, 2, 0)));
    EXPECT_EQ(s.groups[3].selection.kind, Selection::Kind::kHalfSpace);
    EXPECT_TRUE(s.groups[3].selection.normal.isApprox(Vec3f(0, 0, -1)));
    EXPECT_FLOAT_EQ(s.groups[3].selection.offset, 0.2f);
    EXPECT_EQ(s.groups[4].selection.kind, Selection::Kind::kWisps);
    EXPECT_EQ(s.groups[4].selection.wisps, (std::vector<int>{0, 5, 99}));
    EXPECT_EQ(s.groups[5].selection.kind, Selection::Kind::kAll);
}

TEST(StyleToml, HairdressingSectionsExpandInFileOrder) {
    const Style s = parse(R"(
[[comb]]
name = "sweep"
region = "front"
trajectory = [[0, 1, 1], [0, 1.2, 0], [0, 0.6, -1.2]]
radius = 0.5
weight = 0.4
smooth = false

[[braid]]
region = "back"
strands = 4
start = [0, -0.3, -1.1]
axis = [0, -1, -0.1]
side = [1, 0, 0]
length = 2
width = 0.3
period = 0.4
radius = 0.05
weight = 0.9

[[tie]]
name = "ponytail"
point = [0, 0.4, -1.1]
radius = 0.15

[[group]]
name = "late"
[[group.constraint]]
kind = "point"
point = [0, 0, -1.2]

[[updo]]
point = [0, 0.5, -1]
facing = [0, 0.2, -1]
radius = 0.1
bun_radius = 0.25
turns = 3
weight = 0.8
head_relative = false
)");
    // comb, 4 braid strands, tie, group, updo: the order they are written in.
    ASSERT_EQ(s.groups.size(), 8u);
    EXPECT_EQ(s.groups[0].name, "sweep");
    ASSERT_EQ(s.groups[0].queue.size(), 1u);
    EXPECT_EQ(s.groups[0].queue[0].kind, ConstraintSpec::Kind::kDirection);
    EXPECT_FALSE(s.groups[0].queue[0].smooth);
    EXPECT_FLOAT_EQ(s.groups[0].queue[0].radius, 0.5f);
    EXPECT_FLOAT_EQ(s.groups[0].queue[0].weight, 0.4f);
    EXPECT_EQ(s.groups[0].selection.region, "front");

    BraidSpec braid;
    braid.strands = 4;
    braid.start = Vec3f(0, -0.3f, -1.1f);
    braid.axis = Vec3f(0, -1, -0.1f);
    braid.side = Vec3f(1, 0, 0);
    braid.length = 2;
    braid.width = 0.3f;
    braid.period = 0.4f;
    for (int i = 0; i < 4; ++i) {
        SCOPED_TRACE(i);
        const GroupSpec& g = s.groups[1 + i];
        EXPECT_EQ(g.name, "braid[0] strand " + std::to_string(i));
        EXPECT_EQ(g.selection.kind, Selection::Kind::kRegion);
        EXPECT_EQ(g.selection.region, "back");
        EXPECT_EQ(g.selection.part, i);
        EXPECT_EQ(g.selection.parts, 4);
        ASSERT_EQ(g.queue.size(), 2u);
        EXPECT_EQ(g.queue[0].kind, ConstraintSpec::Kind::kPoint);
        EXPECT_TRUE(g.queue[0].point.isApprox(braid.start));
        EXPECT_FLOAT_EQ(g.queue[0].radius, 0.05f);
        EXPECT_FLOAT_EQ(g.queue[0].weight, 0.9f);
        EXPECT_EQ(g.queue[1].kind, ConstraintSpec::Kind::kTrajectory);
        const auto& traj = g.queue[1].trajectory;
        const auto expected = braid_trajectory(braid, i, int(traj.size()));
        ASSERT_EQ(traj.size(), expected.size());
        for (size_t k = 0; k < traj.size(); ++k)
            EXPECT_LT((traj[k] - expected[k]).norm(), 1e-5f);
    }
    EXPECT_EQ(s.groups[5].name, "ponytail");
    EXPECT_EQ(s.groups[5].selection.kind, Selection::Kind::kAll);
    ASSERT_EQ(s.groups[5].queue.size(), 1u);
    EXPECT_TRUE(s.groups[5].queue[0].point.isApprox(Vec3f(0, 0.4f, -1.1f)));
    EXPECT_FLOAT_EQ(s.groups[5].queue[0].radius, 0.15f);
    EXPECT_FLOAT_EQ(s.groups[5].queue[0].weight, 1.f);
    EXPECT_EQ(s.groups[6].name, "late");
    EXPECT_EQ(s.groups[7].name, "updo[0]");
    ASSERT_EQ(s.groups[7].queue.size(), 2u);
    EXPECT_FLOAT_EQ(s.groups[7].queue[0].weight, 0.8f);
    for (const ConstraintSpec& c : s.groups[7].queue)
        EXPECT_FALSE(c.head_relative);  // the whole section is in cm
    EXPECT_FALSE(s.groups[7].selection.head_relative);
    const auto& spiral = s.groups[7].queue[1].trajectory;
    float r = 0.f;
    for (const Vec3f& p : spiral)
        r = std::max(r, (p - Vec3f(0, 0.5f, -1)).norm());
    EXPECT_NEAR(r, 0.25f, 1e-4f);
}

TEST(StyleToml, HairdressingDefaultsComeFromTheSpecs) {
    const Style s = parse("[[tie]]\n[[braid]]\n[[updo]]\n");
    ASSERT_EQ(s.groups.size(), 5u);  // tie, 3 braid strands, updo
    EXPECT_TRUE(s.groups[0].queue[0].point.isApprox(TieSpec{}.point));
    EXPECT_FLOAT_EQ(s.groups[0].queue[0].weight, 1.f);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(s.groups[1 + i].selection.parts, 3);
        EXPECT_EQ(s.groups[1 + i].selection.part, i);
        EXPECT_TRUE(s.groups[1 + i].queue[0].point.isApprox(BraidSpec{}.start));
    }
    EXPECT_TRUE(s.groups[4].queue[0].point.isApprox(UpdoSpec{}.point));
    for (const GroupSpec& g : s.groups)
        for (const ConstraintSpec& c : g.queue)
            EXPECT_TRUE(c.head_relative);
    // For the animation, ties and the bun hold; a braid holds at its start only.
    EXPECT_TRUE(s.groups[0].queue[0].hold);
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(s.groups[1 + i].queue[0].hold);
        EXPECT_FALSE(s.groups[1 + i].queue[1].hold);
    }
    EXPECT_TRUE(s.groups[4].queue[0].hold);
    EXPECT_TRUE(s.groups[4].queue[1].hold);
    // An inline array of tables reads like [[…]] sections.
    EXPECT_EQ(parse("tie = [{ point = [0, 0.3, -1.1] }, { region = \"left\" }]").groups.size(), 2u);
}

TEST(StyleToml, RelativePathsResolveAgainstBaseDir) {
    const std::string text = "[head]\nobj = \"h.obj\"\n[maps]\ndensity = { image = \"d.png\" }";
    const Style rel = parse_style(text, "s.toml", "/a/b");
    EXPECT_EQ(rel.head.obj, fs::path("/a/b/h.obj"));
    EXPECT_EQ(rel.density.image, fs::path("/a/b/d.png"));
    const Style none = parse_style(text, "s.toml");
    EXPECT_EQ(none.head.obj, fs::path("h.obj"));
    const Style abs = parse_style("[head]\nobj = \"/x/h.obj\"", "s.toml", "/a/b");
    EXPECT_EQ(abs.head.obj, fs::path("/x/h.obj"));
}

TEST(StyleToml, LoadStyleReadsFileAndNamesItFromTheStem) {
    const fs::path dir = fs::temp_directory_path() / "wisp_style_toml_test";
    fs::create_directories(dir);
    const fs::path file = dir / "my-style.toml";
    {
        std::ofstream out(file);
        out << "[maps]\ndensity = { image = \"d.png\" }\n[wisp]\nfuzziness = 0.5\n";
    }
    const Style s = load_style(file);
    EXPECT_EQ(s.name, "my-style");
    EXPECT_FLOAT_EQ(s.wisp.fuzziness, 0.5f);
    EXPECT_EQ(s.density.image, dir / "d.png");
    {
        std::ofstream out(file);
        out << "\n[wisp]\nfuzziness = -1\n";
    }
    try {
        load_style(file);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  file.string() + ":3: field 'wisp.fuzziness': must be ≥ 0, got -1");
    }
    EXPECT_THROW(load_style(dir / "missing.toml"), Error);
    EXPECT_THROW(load_style(dir), Error);
    fs::remove_all(dir);
}

TEST(StyleToml, EveryPresetParses) {
    const auto names = preset_names();
    EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
    for (const char* required : {"default", "long-straight", "wavy-bob", "curly", "afro", "short",
                                 "bangs", "ponytail", "braid", "updo", "combed-back", "side-swept"})
        EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
    for (const auto& name : names) {
        SCOPED_TRACE(name);
        EXPECT_FALSE(preset_text(name).empty());
        Style s;
        ASSERT_NO_THROW(s = load_preset(name));
        EXPECT_FALSE(s.name.empty());
        EXPECT_EQ(s.strands, 100000);
        EXPECT_GE(s.wisps, 1500);
        EXPECT_LE(s.wisps, 3000);
    }
}

TEST(StyleToml, PresetsLookLikeTheirNames) {
    // Lengths are the map's [low, high] in cm.
    const Style short_ = load_preset("short");
    EXPECT_LE(short_.length.high, 7.5f);
    const Style bob = load_preset("wavy-bob");
    // A bob is a cut: at the jaw (about 1.1 head units below the skull's centre), on a line
    // that falls toward the face, the back shortest.
    EXPECT_EQ(bob.prototype.kind, PrototypeSpec::Kind::kWavy);
    EXPECT_TRUE(bob.cut.enabled);
    EXPECT_GE(bob.cut.offset, 0.9f);
    EXPECT_LE(bob.cut.offset, 1.3f);
    EXPECT_LT(bob.cut.normal.y(), 0.f);
    EXPECT_LT(bob.cut.normal.z(), 0.f);
    const Style long_ = load_preset("long-straight");
    EXPECT_EQ(long_.prototype.kind, PrototypeSpec::Kind::kStraight);
    EXPECT_GE(long_.length.low, 40.f);
    const Style curly = load_preset("curly");
    EXPECT_EQ(curly.prototype.kind, PrototypeSpec::Kind::kCurly);
    EXPECT_GE(curly.prototype.amplitude, 0.8f);
    EXPECT_LE(curly.prototype.period, 3.f);
    // Afro-textured: tight coils standing off the scalp, held up rather than falling.
    const Style afro = load_preset("afro");
    EXPECT_EQ(afro.prototype.kind, PrototypeSpec::Kind::kKinky);
    EXPECT_LE(afro.prototype.amplitude, 0.5f);
    EXPECT_GE(afro.protrusion.kind == ScalarMap::Kind::kConstant ? afro.protrusion.value
                                                                 : afro.protrusion.high,
              0.7f);
    EXPECT_GT(afro.solve.stiffness, 1.f);
}

TEST(StyleToml, HairdressingPresetsShowTheirOperation) {
    using CK = ConstraintSpec::Kind;
    const auto only_kinds = [](const Style& s) {
        std::vector<std::vector<CK>> kinds;
        for (const GroupSpec& g : s.groups) {
            kinds.emplace_back();
            for (const ConstraintSpec& c : g.queue)
                kinds.back().push_back(c.kind);
        }
        return kinds;
    };
    // The tying presets comb their front half back over the head first (a group of its own),
    // then apply the operation, which is the last section.
    const Style ponytail = load_preset("ponytail");
    ASSERT_FALSE(ponytail.groups.empty());
    EXPECT_EQ(only_kinds(ponytail).back(), (std::vector<CK>{CK::kPoint}));
    EXPECT_FLOAT_EQ(ponytail.groups.back().queue[0].weight, 1.f);  // §6.2: tying uses w = 1
    EXPECT_LT(ponytail.groups.back().queue[0].point.z(), -1.f);    // behind the head

    const Style braid = load_preset("braid");
    std::vector<const GroupSpec*> strands;
    for (const GroupSpec& g : braid.groups)
        if (g.selection.parts == 3) strands.push_back(&g);
    ASSERT_EQ(strands.size(), 3u);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(strands[i]->selection.part, i);
        ASSERT_EQ(strands[i]->queue.size(), 2u);
        EXPECT_EQ(strands[i]->queue[0].kind, CK::kPoint);
        EXPECT_EQ(strands[i]->queue[1].kind, CK::kTrajectory);
    }
    EXPECT_GE(braid.points_per_strand, 48);

    const Style updo = load_preset("updo");
    ASSERT_FALSE(updo.groups.empty());
    EXPECT_EQ(only_kinds(updo).back(), (std::vector<CK>{CK::kPoint, CK::kTrajectory}));

    const Style combed = load_preset("combed-back");
    EXPECT_EQ(only_kinds(combed), (std::vector<std::vector<CK>>{{CK::kDirection}}));
    ASSERT_FALSE(combed.solve.field.empty());
    EXPECT_EQ(combed.solve.field[0].kind, FieldTerm::Kind::kGrowth);
    EXPECT_EQ(combed.growth.front, GrowthSpec::Front::kBack);

    const Style swept = load_preset("side-swept");
    ASSERT_FALSE(swept.solve.field.empty());
    EXPECT_EQ(swept.solve.field[0].kind, FieldTerm::Kind::kGrowth);
    EXPECT_EQ(swept.growth.part, GrowthSpec::Part::kSide);

    // Every preset places its constraints near the head, in head units.
    for (const auto& name : preset_names()) {
        const Style s = load_preset(name);
        for (const GroupSpec& g : s.groups) {
            for (const ConstraintSpec& c : g.queue) {
                EXPECT_TRUE(c.head_relative) << name;
                EXPECT_LT(c.point.norm(), 4.f) << name;
                for (const Vec3f& p : c.trajectory)
                    EXPECT_LT(p.norm(), 4.f) << name;
            }
        }
    }
}

TEST(StyleToml, UnknownPresetListsTheNames) {
    try {
        preset_text("curlly");
        FAIL() << "no error";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("'curlly'"), std::string::npos) << message;
        EXPECT_NE(message.find("did you mean 'curly'"), std::string::npos) << message;
        for (const auto& name : preset_names())
            EXPECT_NE(message.find(name), std::string::npos) << message;
    }
    EXPECT_THROW(load_preset("nope"), Error);
}

TEST(StyleToml, UnknownKeysSuggestTheField) {
    EXPECT_EQ(error_of("[wisp]\nfuzzyness = 0.2"),
              "test.toml:2: unknown field 'wisp.fuzzyness' (did you mean 'wisp.fuzziness'?)");
    EXPECT_EQ(error_of("\n\nwisps = 10"),
              "test.toml:3: unknown field 'wisps' (did you mean 'roots.wisps'?)");
    EXPECT_EQ(error_of("[rots]\nwisps = 10"),
              "test.toml:1: unknown field 'rots' (did you mean 'roots'?)");
    const std::string none = error_of("[strand]\ncolour = 1");
    EXPECT_NE(none.find("test.toml:2: unknown field 'strand.colour' (expected one of: "
                        "root_width, tip_width, taper)"),
              std::string::npos)
        << none;
    EXPECT_NE(error_of("[color]\nhue = { distribution = \"normal\", mean = 3, stdev = 1 }")
                  .find("did you mean 'color.hue.stddev'"),
              std::string::npos);
    EXPECT_NE(error_of("[maps]\nlength = { image = \"a.png\", hihg = 3 }")
                  .find("did you mean 'maps.length.high'"),
              std::string::npos);
}

TEST(StyleToml, UnknownKeysInTheNewSectionsSuggestTheField) {
    EXPECT_EQ(error_of("[[tie]]\npiont = [0, 0.1, -1]"),
              "test.toml:2: unknown field 'tie[0].piont' (did you mean 'tie[0].point'?)");
    EXPECT_EQ(error_of("[[tie]]\nbox = { min = [0, 0, 0], max = [1, 1, 1], mid = 2 }"),
              "test.toml:2: unknown field 'tie[0].box.mid' (did you mean 'tie[0].box.min'?)");
    EXPECT_EQ(error_of("[[group]]\n[[group.constraint]]\nkind = \"point\"\nweigth = 1"),
              "test.toml:4: unknown field 'group[0].constraint[0].weigth' (did you mean "
              "'group[0].constraint[0].weight'?)");
    EXPECT_EQ(error_of("[solve]\nstifness = 2"),
              "test.toml:2: unknown field 'solve.stifness' (did you mean 'solve.stiffness'?)");
    EXPECT_EQ(error_of("\nstiffness = 2"),
              "test.toml:2: unknown field 'stiffness' (did you mean 'solve.stiffness' or "
              "'dynamics.stiffness'?)");
    EXPECT_EQ(error_of("[[braids]]"),
              "test.toml:1: unknown field 'braids' (did you mean 'braid'?)");
    EXPECT_EQ(error_of("[[solve.field]]\nkind = \"wind\"\ndirecton = [1, 0, 0]"),
              "test.toml:3: unknown field 'solve.field[0].directon' (did you mean "
              "'solve.field[0].direction'?)");
    EXPECT_EQ(error_of("[cut]\nnromal = [0, -1, 0]"),
              "test.toml:2: unknown field 'cut.nromal' (did you mean 'cut.normal'?)");
}

// Keys and values quoted in messages are escaped and cut short, and a huge unknown key is
// reported without a "did you mean" search: that edit distance is quadratic in the key's
// length, so on this key it would run for hours and the test's timeout would fail it. (No
// wall-clock bound here: timings belong to benchmarks, and one fails under load.)
TEST(StyleToml, MessagesQuoteKeysAndValuesOnOneShortLine) {
    EXPECT_EQ(error_of("[roots]\n\"a\\nb\\u001b[2J\" = 1"),
              "test.toml:2: unknown field 'roots.a\\nb\\x1b[2J' (expected one of: wisps, "
              "strands, points_per_strand)");
    const std::string value = error_of("[growth]\npart = \"" + std::string(5'000'000, 'q') + "\"");
    EXPECT_LT(value.size(), 300u) << value.substr(0, 400);
    EXPECT_NE(value.find("\"qqqq"), std::string::npos) << value;
    EXPECT_NE(value.find("... (5000000 bytes)"), std::string::npos) << value;
    EXPECT_NE(error_of("[growth]\npart = \"x\\u001b]0;t\\u0007\"").find("got \"x\\x1b]0;t\\x07\""),
              std::string::npos);

    const std::string key = error_of(std::string(15'000'000, 'k') + " = 1");
    EXPECT_LT(key.size(), 600u);
    EXPECT_EQ(key.rfind("test.toml:1: unknown field 'kkkk", 0), 0u) << key.substr(0, 100);
    EXPECT_NE(key.find("... (15000000 bytes)'"), std::string::npos);
    EXPECT_EQ(key.find('\n'), std::string::npos);
}

TEST(StyleToml, SyntaxErrorsGiveLineAndColumn) {
    const std::string message = error_of("seed = 1\n[wisp\n");
    EXPECT_EQ(message.rfind("test.toml:2:", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(error_of("seed = 1\nseed = 2").rfind("test.toml:2:", 0), 0u);
}

struct BadInput {
    const char* text;
    int line;
    const char* field;  // the field named in the message
    const char* says;   // a part of the reason
};

TEST(StyleToml, InvalidInputsNameFileLineAndField) {
    const BadInput cases[] = {
        // types
        {"name = 3", 1, "name", "must be a string, got 3"},
        {"seed = 1.5", 1, "seed", "must be an integer, got 1.5"},
        {"seed = -1", 1, "seed", "must be ≥ 0"},
        {"roots = 3", 1, "roots", "must be a table"},
        {"[roots]\nwisps = \"many\"", 2, "roots.wisps", "must be an integer, got \"many\""},
        {"[wisp]\nfuzziness = \"a lot\"", 2, "wisp.fuzziness", "must be a number"},
        {"[wisp]\nfuzziness = true", 2, "wisp.fuzziness", "got true"},
        // counts
        {"[roots]\nwisps = -5", 2, "roots.wisps", "must be ≥ 1, got -5"},
        {"[roots]\nwisps = 0", 2, "roots.wisps", "must be ≥ 1"},
        {"[roots]\nstrands = 100\nwisps = 200", 3, "roots.wisps", "must be ≤ roots.strands"},
        {"[roots]\nstrands = 1000", 2, "roots.strands", "must be ≥ roots.wisps (2000)"},
        {"[roots]\nstrands = 20000000", 2, "roots.strands", "must be ≤ 10000000"},
        {"[roots]\npoints_per_strand = 3", 2, "roots.points_per_strand", "must be ≥ 4"},
        {"[roots]\npoints_per_strand = 5000", 2, "roots.points_per_strand", "must be ≤ 1024"},
        {"[roots]\nstrands = 10000000\npoints_per_strand = 1000", 3, "roots.points_per_strand",
         "strands × points_per_strand must be ≤"},
        // numbers
        {"[wisp]\nfuzziness = -1", 2, "wisp.fuzziness", "must be ≥ 0, got -1"},
        {"[wisp]\nfuzziness = nan", 2, "wisp.fuzziness", "must be a finite number, got nan"},
        {"[wisp]\nfuzziness = inf", 2, "wisp.fuzziness", "must be a finite number, got inf"},
        {"[wisp]\ndeviation_radius = [1, 0, 2]", 2, "wisp.deviation_radius[1]", "must be > 0"},
        {"[wisp]\ndeviation_radius = []", 2, "wisp.deviation_radius", "must hold 1 to"},
        {"[wisp]\ndeviation_radius = -1", 2, "wisp.deviation_radius", "must be > 0"},
        {"[wisp]\ndeviation_radius = \"wide\"", 2, "wisp.deviation_radius", "must be a number"},
        {"[strand]\nroot_width = 0", 2, "strand.root_width", "must be > 0, got 0"},
        {"[strand]\ntip_width = -0.1", 2, "strand.tip_width", "must be > 0"},
        {"[head]\nscale = 0", 2, "head.scale", "must be > 0"},
        {"[head]\nobj = \"\"", 2, "head.obj", "must not be empty"},
        {"[prototype]\ntemperature = -0.5", 2, "prototype.temperature", "must be ≥ 0"},
        {"[prototype]\nperiod = 0", 2, "prototype.period", "must be > 0"},
        {"[prototype]\namplitude = -1", 2, "prototype.amplitude", "must be ≥ 0"},
        {"[prototype]\nwindow = 0", 2, "prototype.window", "must be ≥ 1"},
        {"[prototype]\nroll = -1", 2, "prototype.roll", "must be ≥ 0"},
        // enums
        {"[prototype]\nshape = \"curley\"", 2, "prototype.shape", "(did you mean \"curly\"?)"},
        {"[prototype]\nshape = 2", 2, "prototype.shape", "must be one of \"straight\""},
        {"[head.scalp]\nmethod = \"paint\"", 2, "head.scalp.method", "must be one of"},
        {"[color]\npreset = \"green\"", 2, "color.preset", "must be one of \"black\""},
        // polyline prototypes
        {"[prototype]\nshape = \"polyline\"", 1, "prototype.points", "required"},
        {"[prototype]\npoints = [[0,0,0],[0,1,0]]", 2, "prototype.points", "4 to"},
        {"[prototype]\npoints = [[0,0,0],[0,1,0],[0,2],[0,3,0]]", 2, "prototype.points[2]",
         "must be a point [x, y, z]"},
        {"[prototype]\nshape = \"wavy\"\npoints = [[0,0,0],[0,1,0],[0,2,0],[0,3,0]]", 3,
         "prototype.points", "only used with shape = \"polyline\""},
        {"[prototype]\nwindow = 4\npoints = [[0,0,0],[0,1,0],[0,2,0],[0,3,0]]", 2,
         "prototype.window", "must be < the number of prototype points"},
        // scalp methods
        {"[head.scalp]\nmethod = \"group\"\nmask = \"m.png\"", 3, "head.scalp.mask",
         "belongs to method = \"mask\""},
        {"[head.scalp]\nmask = \"m.png\"\nfront = 4", 3, "head.scalp.front",
         "belongs to method = \"hairline\""},
        {"[head.scalp]\nmethod = \"mask\"", 1, "head.scalp.mask", "required"},
        {"[head.scalp]\nback = 0", 2, "head.scalp.back", "must be > 0"},
        // maps
        {"[maps]\ndensity = \"bangz\"", 2, "maps.density", "unknown procedural map \"bangz\""},
        {"[maps]\nlength = { procedural = \"crwn\" }", 2, "maps.length.procedural",
         "did you mean \"crown\""},
        {"[maps]\ndensity = -1", 2, "maps.density", "must be > 0"},
        {"[maps]\ndensity = 0", 2, "maps.density", "must be > 0"},
        {"[maps]\ndensity = { image = \"d.png\", low = 0, high = 0 }", 2, "maps.density",
         "must not both be 0"},
        {"[maps]\nlength = 0", 2, "maps.length", "must be > 0"},
        {"[maps]\nlength = { procedural = \"bangs\", low = 0 }", 2, "maps.length.low",
         "must be > 0"},
        {"[maps]\nlength = 800", 2, "maps.length", "must be ≤ 500"},
        {"[maps]\nprotrusion = 1.5", 2, "maps.protrusion", "must be ≤ 1"},
        {"[maps]\nprotrusion = { low = 0 }", 2, "maps.protrusion", "needs one of"},
        {"[maps]\nprotrusion = { value = 0.5, image = \"p.png\" }", 2, "maps.protrusion.image",
         "cannot be combined with 'value'"},
        {"[maps]\nprotrusion = { value = 0.5, low = 0 }", 2, "maps.protrusion.low",
         "only applies to image and procedural maps"},
        {"[maps]\nlength = [1, 2]", 2, "maps.length", "must be a number, a procedural map"},
        // distributions
        {"[wisp]\nlength = { distribution = \"uniform\", min = 0.9, max = 0.8 }", 2,
         "wisp.length.max", "min must be ≤ max"},
        {"[wisp]\nlength = { distribution = \"uniform\", min = 0, max = 0 }", 2, "wisp.length.max",
         "must be > 0"},
        {"[wisp]\nlength = 0", 2, "wisp.length", "must be > 0"},
        {"[wisp]\nlength = 1.5", 2, "wisp.length", "must be ≤ 1"},
        {"[wisp]\nlength = { distribution = \"gaussian\" }", 2, "wisp.length.distribution",
         "must be one of"},
        {"[wisp]\nlength = { distribution = \"normal\", mean = 0.9 }", 2, "wisp.length.stddev",
         "required by a normal distribution"},
        {"[wisp]\nlength = { distribution = \"uniform\", mean = 0.9 }", 2, "wisp.length.mean",
         "not used by a uniform distribution"},
        {"[wisp]\nlength = { distribution = \"table\", values = [1] }", 2, "wisp.length.values",
         "must hold 2 to"},
        {"[wisp]\nlength = { distribution = \"table\", values = [0, 0, 0] }", 2,
         "wisp.length.values", "must not be all zero"},
        {"[wisp]\nlength = { distribution = \"table\", values = [1, -1] }", 2,
         "wisp.length.values[1]", "must be ≥ 0"},
        {"[wisp]\nlength = \"long\"", 2, "wisp.length", "must be a number or a table"},
        {"[color]\nhue = 400", 2, "color.hue", "must be ≤ 360, got 400"},
        {"[color]\nhue = -10", 2, "color.hue", "must be ≥ 0"},
        {"[color]\nsaturation = 1.2", 2, "color.saturation", "must be ≤ 1"},
        {"[color]\nvalue = { distribution = \"normal\", mean = 0.5, stddev = -0.1 }", 2,
         "color.value.stddev", "must be ≥ 0"},
        {"[color]\nvalue = { distribution = \"normal\", mean = 0.5, stddev = 0.1, max = 0.4 }", 2,
         "color.value.mean", "must lie within [min, max]"},
        {"[color]\nvalue = { distribution = \"uniform\", min = -0.5 }", 2, "color.value.min",
         "must be ≥ 0"},
        {"[color]\nvalue = { value = 0.5 }", 2, "color.value.value",
         "not used by a normal distribution"},
        {"[color]\nwisp_hue = -1", 2, "color.wisp_hue", "must be ≥ 0"},
        {"[color]\nwisp_value = 2", 2, "color.wisp_value", "must be ≤ 1"},
        // [solve]
        {"[solve]\nenabled = 1", 2, "solve.enabled", "must be true or false, got 1"},
        {"[solve]\nstiffness = -1", 2, "solve.stiffness", "must be ≥ 0"},
        {"[solve]\nstiffness = 2000", 2, "solve.stiffness", "must be ≤ 1000"},
        {"[solve]\nthreshold = 0", 2, "solve.threshold", "must be > 0"},
        {"[solve]\nthreshold = 1.5", 2, "solve.threshold", "must be ≤ 1"},
        {"[solve]\nthreshold = nan", 2, "solve.threshold", "must be a finite number"},
        {"[solve]\ncell = 0.1", 2, "solve.cell", "must be ≥ 0.2"},
        {"[solve]\ncell = 11", 2, "solve.cell", "must be ≤ 10"},
        {"[solve]\nfull_density = 0", 2, "solve.full_density", "must be > 0"},
        {"[solve]\nbend_step = 0", 2, "solve.bend_step", "must be > 0"},
        {"[solve]\nbend_step = 50", 2, "solve.bend_step", "must be ≤ 45"},
        {"[solve]\nmax_tries = -1", 2, "solve.max_tries", "must be ≥ 0"},
        {"[solve]\nmax_tries = 1001", 2, "solve.max_tries", "must be ≤ 1000"},
        {"[solve]\nmax_tries = 2.5", 2, "solve.max_tries", "must be an integer"},
        {"[solve]\norder = \"depth-frist\"", 2, "solve.order", "(did you mean \"depth-first\"?)"},
        {"[solve]\nhead_margin = -0.1", 2, "solve.head_margin", "must be ≥ 0"},
        {"[solve]\nfield = \"gravity\"", 2, "solve.field", "must be an array of tables"},
        {"[solve.field]\nkind = \"gravity\"", 1, "solve.field", "write [[solve.field]]"},
        {"[[solve.field]]\nweight = 1", 1, "solve.field[0].kind", "required"},
        {"[[solve.field]]\nkind = \"gravty\"", 2, "solve.field[0].kind",
         "(did you mean \"gravity\"?)"},
        {"[[solve.field]]\nkind = \"gravity\"\nweight = inf", 3, "solve.field[0].weight",
         "must be a finite number"},
        {"[[solve.field]]\nkind = \"wind\"\ndirection = [0, 0, 0]", 3, "solve.field[0].direction",
         "must be a non-zero direction"},
        {"[[solve.field]]\nkind = \"wind\"\ndirection = [1, 0]", 3, "solve.field[0].direction",
         "must be a direction [x, y, z]"},
        {"[[solve.field]]\nkind = \"wind\"\ndirection = [1, nan, 0]", 3,
         "solve.field[0].direction[1]", "must be a finite number"},
        {"[[solve.field]]\nkind = \"gravity\"\ndirection = [1, 0, 0]", 3,
         "solve.field[0].direction", "only used with kind = \"wind\""},
        {"[[solve.field]]\nkind = \"wind\"\nside = \"left\"", 3, "solve.field[0].side",
         "only used with kind = \"side-part\""},
        {"[[solve.field]]\nkind = \"side-part\"\nside = \"middle\"", 3, "solve.field[0].side",
         "must be one of \"left\", \"right\""},
        {"[[solve.field]]\nkind = \"file\"", 1, "solve.field[0].file", "required by kind"},
        {"[[solve.field]]\nkind = \"file\"\nfile = \"\"", 3, "solve.field[0].file",
         "must not be empty"},
        {"[[solve.field]]\nkind = \"gravity\"\n[[solve.field]]\nkind = \"wind\"\nfile = \"f\"", 5,
         "solve.field[1].file", "only used with kind = \"file\""},
        // [cut]
        {"[cut]\nnormal = [0, 0, 0]", 2, "cut.normal", "must be a non-zero direction"},
        {"[cut]\noffset = \"low\"", 2, "cut.offset", "must be a number"},
        {"[cut]\noffset = nan", 2, "cut.offset", "must be a finite number"},
        {"[cut]\nhead_relative = \"yes\"", 2, "cut.head_relative", "must be true or false"},
        // selections
        {"[[group]]\nregion = \"bangz\"\n[[group.constraint]]\nkind = \"point\"\npoint = [0,0,0]",
         2, "group[0].region", "did you mean \"bangs\""},
        {"[[tie]]\nregion = \"back\"\nmask = \"m.png\"", 3, "tie[0].mask",
         "cannot be combined with 'region'"},
        {"[[tie]]\nselect = \"some\"", 2, "tie[0].select", "must be one of \"all\""},
        {"[[tie]]\nmask = \"\"", 2, "tie[0].mask", "must not be empty"},
        {"[[tie]]\nbox = [0, 1]", 2, "tie[0].box", "must be a table { min"},
        {"[[tie]]\nbox = { min = [0, 0, 0] }", 2, "tie[0].box.max", "required"},
        {"[[tie]]\nbox = { min = [0, 0, 0], max = [1, -1, 1] }", 2, "tie[0].box.max",
         "must be ≥ min in every coordinate, got max[1] = -1"},
        {"[[tie]]\nhalf_space = { offset = 1 }", 2, "tie[0].half_space.normal", "required"},
        {"[[tie]]\nhalf_space = { normal = [0, 0, 0] }", 2, "tie[0].half_space.normal",
         "must be a non-zero direction"},
        {"[[tie]]\nwisps = []", 2, "tie[0].wisps", "must hold 1 to roots.wisps (2000) ids"},
        {"[[tie]]\nwisps = 3", 2, "tie[0].wisps", "must be an array of wisp ids"},
        {"[[tie]]\nwisps = [1, -2]", 2, "tie[0].wisps[1]", "must be ≥ 0"},
        {"[[tie]]\nwisps = [1, 2.5]", 2, "tie[0].wisps[1]", "must be an integer"},
        {"[[tie]]\nwisps = [3, 3]", 2, "tie[0].wisps[1]", "lists wisp 3 twice"},
        {"[[tie]]\nwisps = [0, 2000]", 2, "tie[0].wisps[1]",
         "must be < roots.wisps (2000), got 2000"},
        {"[[tie]]\nwisps = [0, 150]\n[roots]\nwisps = 100\nstrands = 1000", 2, "tie[0].wisps[1]",
         "must be < roots.wisps (100)"},
        {"[[tie]]\nparts = 0\npart = 0", 2, "tie[0].parts", "must be ≥ 1"},
        {"[[tie]]\nparts = 3\npart = 3", 3, "tie[0].part", "must be < parts (3), got 3"},
        {"[[tie]]\npart = -1", 2, "tie[0].part", "must be ≥ 0"},
        {"[[tie]]\npart = 1", 2, "tie[0].part", "must be < parts (1)"},
        {"[[tie]]\nparts = 2", 2, "tie[0].part", "required with 'parts'"},
        {"[[tie]]\nhead_relative = 1", 2, "tie[0].head_relative", "must be true or false"},
        // [[group]] and its constraints
        {"group = 3", 1, "group", "must be an array of tables ([[group]])"},
        {"[group]\nname = \"a\"", 1, "group", "write [[group]] for each"},
        {"[[group]]\nname = \"a\"", 1, "group[0].constraint", "at least one [[group.constraint]]"},
        {"[[group]]\nname = \"\"", 2, "group[0].name", "must not be empty"},
        {"[[group]]\n[[group.constraint]]\npoint = [0, 0, 0]", 2, "group[0].constraint[0].kind",
         "required"},
        {"[[group]]\n[[group.constraint]]\nkind = \"pull\"", 3, "group[0].constraint[0].kind",
         "must be one of \"point\", \"trajectory\", \"direction\""},
        {"[[group]]\n[[group.constraint]]\nkind = \"point\"", 2, "group[0].constraint[0].point",
         "required by kind = \"point\""},
        {"[[group]]\n[[group.constraint]]\nkind = \"point\"\npoint = [0, 1]", 4,
         "group[0].constraint[0].point", "must be a point [x, y, z]"},
        {"[[group]]\n[[group.constraint]]\nkind = \"point\"\npoint = [0, 0, inf]", 4,
         "group[0].constraint[0].point[2]", "must be a finite number"},
        {"[[group]]\n[[group.constraint]]\nkind = \"point\"\npoint = [0, 0, 0]\nradius = 0", 5,
         "group[0].constraint[0].radius", "must be > 0"},
        {"[[group]]\n[[group.constraint]]\nkind = \"point\"\npoint = [0, 0, 0]\nweight = 1.5", 5,
         "group[0].constraint[0].weight", "must be ≤ 1"},
        {"[[group]]\n[[group.constraint]]\nkind = \"point\"\npoint = [0, 0, 0]\nweight = -0.5", 5,
         "group[0].constraint[0].weight", "must be ≥ 0"},
        {"[[group]]\n[[group.constraint]]\nkind = \"point\"\npoint = [0, 0, 0]\nsmooth = true", 5,
         "group[0].constraint[0].smooth", "only used with kind = \"trajectory\""},
        {"[[group]]\n[[group.constraint]]\nkind = \"trajectory\"", 2,
         "group[0].constraint[0].trajectory", "required by kind = \"trajectory\""},
        {"[[group]]\n[[group.constraint]]\nkind = \"direction\"\ntrajectory = [[0, 0, 0]]", 4,
         "group[0].constraint[0].trajectory", "must hold 2 to"},
        {"[[group]]\n[[group.constraint]]\nkind = \"trajectory\"\ntrajectory = [[0, 0, 0], [0, "
         "0, 0]]",
         4, "group[0].constraint[0].trajectory[1]", "repeats the previous point"},
        {"[[group]]\n[[group.constraint]]\nkind = \"trajectory\"\ntrajectory = [0, 1, 2]", 4,
         "group[0].constraint[0].trajectory[0]", "must be a point [x, y, z]"},
        {"[[group]]\n[[group.constraint]]\nkind = \"trajectory\"\ntrajectory = [[0, 0, 0], [0, "
         "1, 0]]\npoint = [0, 0, 0]",
         5, "group[0].constraint[0].point", "only used with kind = \"point\""},
        // [[tie]], [[braid]], [[updo]], [[comb]]
        {"[[tie]]\nradius = 0", 2, "tie[0].radius", "must be > 0"},
        {"[[tie]]\nweight = 2", 2, "tie[0].weight", "must be ≤ 1"},
        {"[[tie]]\npoint = [0, 0.1]", 2, "tie[0].point", "must be a point [x, y, z]"},
        {"[[braid]]\nstrands = 2", 2, "braid[0].strands", "must be ≥ 3, got 2"},
        {"[[braid]]\nstrands = 17", 2, "braid[0].strands", "must be ≤ 16"},
        {"[[braid]]\npart = 0", 2, "braid[0].part", "is set by the braid"},
        {"[[braid]]\nparts = 3", 2, "braid[0].parts", "is set by the braid"},
        {"[[braid]]\naxis = [0, 0, 0]", 2, "braid[0].axis", "must be a non-zero direction"},
        {"[[braid]]\nside = [0, 0, 0]", 2, "braid[0].side", "must be a non-zero direction"},
        {"[[braid]]\naxis = [0, -1, 0]\nside = [0, 2, 0]", 3, "braid[0].side", "(nearly) parallel"},
        {"[[braid]]\nlength = 0", 2, "braid[0].length", "must be > 0"},
        {"[[braid]]\nwidth = -1", 2, "braid[0].width", "must be > 0"},
        {"[[braid]]\nperiod = 0", 2, "braid[0].period", "must be > 0"},
        {"[[braid]]\nperiod = 0.0001", 2, "braid[0].period", "length / period must be ≤ 1000"},
        {"[[braid]]\nradius = nan", 2, "braid[0].radius", "must be a finite number"},
        {"[[braid]]\nweight = -1", 2, "braid[0].weight", "must be ≥ 0"},
        {"[[updo]]\nfacing = [0, 0, 0]", 2, "updo[0].facing", "must be a non-zero direction"},
        {"[[updo]]\nbun_radius = 0", 2, "updo[0].bun_radius", "must be > 0"},
        {"[[updo]]\nturns = 0", 2, "updo[0].turns", "must be > 0"},
        {"[[updo]]\nturns = 100", 2, "updo[0].turns", "must be ≤ 50"},
        {"[[comb]]\nregion = \"front\"", 1, "comb[0].trajectory", "required"},
        {"[[comb]]\ntrajectory = [[0, 1, 1]]", 2, "comb[0].trajectory", "must hold 2 to"},
        {"[[comb]]\ntrajectory = [[0, 1, 1], [0, 1, 0]]\nsmooth = \"yes\"", 3, "comb[0].smooth",
         "must be true or false"},
        {"[[comb]]\ntrajectory = [[0, 1, 1], [0, 1, 0]]\nweight = 1.1", 3, "comb[0].weight",
         "must be ≤ 1"},
        {"[[comb]]\ntrajectory = [[0, 1, 1], [0, 1, 0]]\nname = 5", 3, "comb[0].name",
         "must be a string"},
        {"tie = [{ point = [0, 0, -1] }, 3]", 1, "tie[1]", "must be a table, got 3"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.text);
        const std::string message = error_of(c.text);
        ASSERT_FALSE(message.empty()) << "no error";
        const std::string prefix =
            "test.toml:" + std::to_string(c.line) + ": field '" + c.field + "': ";
        EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
        EXPECT_NE(message.find(c.says), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST(StyleToml, DynamicsSection) {
    const Style s = parse(
        "[dynamics]\nlevels = 2\nsub_wisps = 4\nsections = 12\nlinks = \"soft\"\n"
        "split_threshold = 0.4\ndt = 0.005\nhair_collisions = false\n");
    EXPECT_EQ(s.dynamics.levels, 2);
    EXPECT_EQ(s.dynamics.sub_wisps, 4);
    EXPECT_EQ(s.dynamics.sections, 12);
    EXPECT_EQ(s.dynamics.links, DynamicsSpec::Links::kSoft);
    EXPECT_FLOAT_EQ(s.dynamics.split_threshold, 0.4f);
    EXPECT_FLOAT_EQ(s.dynamics.dt, 0.005f);
    EXPECT_FALSE(s.dynamics.hair_collisions);
    EXPECT_NE(error_of("[dynamics]\nlevels = 5").find("dynamics.levels"), std::string::npos);
    EXPECT_NE(error_of("[dynamics]\nlinks = \"wobbly\"").find("dynamics.links"), std::string::npos);
    EXPECT_NE(error_of("[dynamics]\nfriction = 200").find("friction · dt must be under 1"),
              std::string::npos);
    EXPECT_NE(error_of("[dynamics]\ndt = 0").find("dynamics.dt"), std::string::npos);
}

}  // namespace
// The files a style reads, each once, resolved against its folder: the head mesh, map and
// mask images, field files; a path its method does not read (a scalp mask beside the
// hairline scalp) is not one.
TEST(StyleToml, StyleFilesAreTheFilesItReads) {
    const Style s = parse_style(R"(
[head]
obj = "heads/a.obj"
scalp = { method = "hairline" }
[maps]
density = { image = "maps/d.png" }
length = { image = "maps/d.png", low = 10, high = 30 }
[[solve.field]]
kind = "file"
file = "../fields/f.txt"
[[group]]
mask = "masks/tie.png"
[[group.constraint]]
kind = "point"
point = [0, 0, 0]
)",
                                "s.toml", "/styles");
    const std::vector<std::filesystem::path> files = style_files(s);
    const std::vector<std::filesystem::path> expected = {
        "/styles/heads/a.obj", "/styles/maps/d.png", "/styles/../fields/f.txt",
        "/styles/masks/tie.png"};
    EXPECT_EQ(files, expected);
    EXPECT_TRUE(style_files(Style{}).empty());
}

}  // namespace wisp
