#include "groom/style_toml.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
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
    expect_same(parse("[roots]\n[wisp]\n[color]\n"), Style{});
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
    for (const char* required : {"default", "long-straight", "wavy-bob", "curly", "short"})
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
    EXPECT_EQ(bob.prototype.kind, PrototypeSpec::Kind::kWavy);
    EXPECT_EQ(bob.length.procedural, "nape-short");
    EXPECT_GE(bob.length.high, 18.f);
    EXPECT_LE(bob.length.high, 22.f);
    const Style long_ = load_preset("long-straight");
    EXPECT_EQ(long_.prototype.kind, PrototypeSpec::Kind::kStraight);
    EXPECT_GE(long_.length.low, 40.f);
    const Style curly = load_preset("curly");
    EXPECT_EQ(curly.prototype.kind, PrototypeSpec::Kind::kCurly);
    EXPECT_GE(curly.prototype.amplitude, 0.8f);
    EXPECT_LE(curly.prototype.period, 3.f);
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
                        "root_width, tip_width)"),
              std::string::npos)
        << none;
    EXPECT_NE(error_of("[color]\nhue = { distribution = \"normal\", mean = 3, stdev = 1 }")
                  .find("did you mean 'color.hue.stddev'"),
              std::string::npos);
    EXPECT_NE(error_of("[maps]\nlength = { image = \"a.png\", hihg = 3 }")
                  .find("did you mean 'maps.length.high'"),
              std::string::npos);
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

}  // namespace
}  // namespace wisp
