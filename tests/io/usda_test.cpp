#include "io/usda.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>

#include "core/parallel.hpp"
#include "io/hair_io.hpp"
#include "io_test_util.hpp"

namespace wisp {
namespace {

using test::expect_error;

const std::string kUsdDir = WISP_SHARED_DIR "/data/usd/";

const UsdCurves& prim(const std::vector<UsdCurves>& curves, const std::string& path) {
    for (const UsdCurves& c : curves)
        if (c.path == path) return c;
    throw std::runtime_error("no prim " + path);
}

Hair read_usda_from_text(const std::string& text) {
    return hair_from_usda(parse_usda(text, "mem.usda"), "mem.usda");
}

std::vector<size_t> segments_of(const UsdCurves& c) {
    std::vector<size_t> s;
    for (size_t i = 0; i < c.counts.size(); ++i)
        s.push_back(usd_segment_count(c, i));
    return s;
}

TEST(Usda, RoundTripIsBitExact) {
    const Hair h = test::random_hair(3, 500);
    test::TempPath p(".usda");
    write_usda(p, h);
    const Hair r = read_usda(p);
    test::expect_same_geometry(h, r);
    ASSERT_EQ(r.widths.size(), h.widths.size());
    EXPECT_TRUE(test::same_bits(h.widths.data(), r.widths.data(), 4 * h.widths.size()));
    ASSERT_EQ(r.colors.size(), h.colors.size());
    test::expect_same_colors(h, r);
    EXPECT_EQ(r.wisp, h.wisp);
}

// Strands are formatted in blocks on the worker threads: the bytes, streamed to a file or
// built in memory, must not depend on the thread count. Enough strands for many blocks, and
// widths that repeat along strands (the writer copies a repeated width's text).
TEST(Usda, BytesIdenticalAtAnyThreadCount) {
    Hair h = test::random_hair(11, 5000);
    for (size_t i = 0; i < h.widths.size(); ++i)
        if (i % 3) h.widths[i] = h.widths[i - 1];
    h.widths[7] = -0.f;  // same value as 0 but not the same text
    h.widths[8] = 0.f;
    std::string one;
    {
        const ThreadLimit limit(1);
        one = encode_usda(h);
    }
    for (int threads : {2, 3, 8}) {
        const ThreadLimit limit(threads);
        EXPECT_EQ(encode_usda(h), one) << threads << " threads";
        test::TempPath p(".usda");
        write_usda(p, h);
        EXPECT_EQ(test::read_file_text(p), one) << threads << " threads, file";
    }
    EXPECT_NE(one.find(", -0, 0, "), std::string::npos);
    // The reader keeps widths exact (it turns -0 into 0, which == compares equal).
    EXPECT_EQ(read_usda_from_text(one).widths, h.widths);
}

TEST(Usda, RoundTripWithDefaults) {
    Hair h = test::random_hair(4, 50, 6, false, false, false);
    h.default_width = 0.0123f;
    h.default_color = Vec3f(0.1f, 0.2f, 0.7f);
    const Hair r = hair_from_usda(parse_usda(encode_usda(h), "mem.usda"), "mem.usda");
    test::expect_same_geometry(h, r);
    test::expect_same_widths(h, r);  // per-vertex widths filled with the default
    EXPECT_TRUE(r.colors.empty());   // one constant color becomes the default color
    EXPECT_EQ(r.default_color, h.default_color);
    EXPECT_TRUE(r.wisp.empty());
}

TEST(Usda, WriterLayout) {
    Hair h;
    h.add_strand(std::vector<Vec3f>{{0, 0, 0}, {0, 1, 0}, {0, 2, 0.5f}});
    const std::string text = encode_usda(h);
    for (const char* line :
         {"#usda 1.0", "metersPerUnit = 0.01", "upAxis = \"Y\"", "def Xform \"hair\"",
          "def BasisCurves \"strands\"", "uniform token type = \"cubic\"",
          "uniform token basis = \"catmullRom\"", "uniform token wrap = \"pinned\"",
          "int[] curveVertexCounts = [3]", "point3f[] points", "float[] widths",
          "interpolation = \"vertex\"", "color3f[] primvars:displayColor", "float3[] extent"})
        EXPECT_NE(text.find(line), std::string::npos) << line;
    const UsdaLayer layer = parse_usda(text, "layout.usda");
    ASSERT_EQ(layer.curves.size(), 1u);
    EXPECT_EQ(layer.curves[0].path, "/hair/strands");
    EXPECT_EQ(usd_curves_problem(layer.curves[0]), "");
    Hair one;
    one.add_strand(std::vector<Vec3f>{{0, 0, 0}});
    expect_error([&] { encode_usda(one, "one.usda"); }, "one.usda: strand 0 has 1 points");
}

// The declarations of the BasisCurves prim's attributes as written: name -> type.
std::map<std::string, std::string> declared_types(const std::string& text) {
    static const std::regex decl(R"(\n\s*(?:uniform\s+)?([A-Za-z0-9]+(?:\[\])?)\s+([\w:]+)\s*=)");
    std::map<std::string, std::string> types;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), decl);
         it != std::sregex_iterator(); ++it)
        types[(*it)[2]] = (*it)[1];
    return types;
}

// The values of a one-line-per-value array attribute `name = [ ... ]`, as text.
size_t array_values(const std::string& text, const std::string& name) {
    size_t at = text.find(name + " = [");
    if (at == std::string::npos) return 0;
    at += name.size() + 4;
    const size_t end = text.find(']', at);
    return static_cast<size_t>(std::count(text.begin() + at, text.begin() + end, '('));
}

// Unreal's USD importer (UsdGroomConversion.cpp) reads a BasisCurves prim with the GroomAPI
// schema as a groom, and every primvar named groom_* of type int[], float[], float3[] or
// float2[] (not color3f[]) as a strand (uniform, constant) or vertex attribute.
TEST(Usda, UnrealGroomDeclarations) {
    const Hair h = test::random_hair(5, 300);
    const std::string text = encode_usda(h, "groom.usda");
    EXPECT_NE(text.find("def BasisCurves \"strands\" (\n        prepend apiSchemas = "
                        "[\"GroomAPI\"]\n    )\n    {"),
              std::string::npos);
    const auto types = declared_types(text);
    EXPECT_EQ(types.at("primvars:groom_group_id"), "int[]");
    EXPECT_EQ(types.at("primvars:groom_color"), "float3[]");
    EXPECT_EQ(types.at("widths"), "float[]");
    EXPECT_EQ(types.at("points"), "point3f[]");
    EXPECT_NE(text.find("int[] primvars:groom_group_id = [0] (\n            interpolation = "
                        "\"constant\""),
              std::string::npos);
    EXPECT_EQ(array_values(text, "float3[] primvars:groom_color"), h.strand_count());
    EXPECT_EQ(array_values(text, "color3f[] primvars:displayColor"), h.strand_count());
    // wisp's reader reads past the new metadata and primvars: the same hair comes back.
    const UsdaLayer layer = parse_usda(text, "groom.usda");
    ASSERT_EQ(layer.curves.size(), 1u);
    EXPECT_EQ(usd_curves_problem(layer.curves[0]), "");
    const Hair r = hair_from_usda(layer, "groom.usda");
    test::expect_same_geometry(h, r);
    test::expect_same_widths(h, r);
    test::expect_same_colors(h, r);
    EXPECT_EQ(r.wisp, h.wisp);
    // Without colors, one constant groom color (the default color).
    Hair plain = test::random_hair(6, 20, 6, false, false, false);
    const std::string plain_text = encode_usda(plain);
    EXPECT_NE(plain_text.find("float3[] primvars:groom_color = [(0.3, 0.2, 0.12)] (\n"
                              "            interpolation = \"constant\""),
              std::string::npos);
}

TEST(Usda, ZUpTurnsYIntoZAndReadsBack) {
    const Hair h = test::random_hair(7, 200);
    const std::string text = encode_usda(h, "z.usda", UsdaWriteOptions{.z_up = true});
    EXPECT_NE(text.find("upAxis = \"Z\""), std::string::npos);
    EXPECT_EQ(text.find("upAxis = \"Y\""), std::string::npos);
    const UsdaLayer layer = parse_usda(text, "z.usda");
    EXPECT_EQ(layer.up_axis, "Z");
    ASSERT_EQ(layer.curves.size(), 1u);
    const std::vector<Vec3f>& pts = layer.curves[0].points;
    ASSERT_EQ(pts.size(), h.point_count());
    for (size_t i = 0; i < pts.size(); ++i) {
        const Vec3f& p = h.points[i];
        ASSERT_EQ(pts[i], Vec3f(p.x(), -p.z(), p.y())) << "point " << i;
    }
    // The extent bounds the turned points.
    const std::string extent = text.substr(text.find("float3[] extent = "), 200);
    float lo[3], hi[3];
    ASSERT_EQ(std::sscanf(extent.c_str(), "float3[] extent = [(%f, %f, %f), (%f, %f, %f)]", &lo[0],
                          &lo[1], &lo[2], &hi[0], &hi[1], &hi[2]),
              6);
    for (const Vec3f& p : pts)
        for (int k = 0; k < 3; ++k) {
            EXPECT_LE(lo[k], p[k]);
            EXPECT_GE(hi[k], p[k]);
        }
    // read_usda turns a Z-up layer back to head space: bit-exact (only signs and order move).
    const Hair r = hair_from_usda(layer, "z.usda");
    test::expect_same_geometry(h, r);
    test::expect_same_widths(h, r);
    test::expect_same_colors(h, r);
    // The default stays Y up, as before.
    EXPECT_NE(encode_usda(h).find("upAxis = \"Y\""), std::string::npos);
}

TEST(Usda, AnimationTimeSamples) {
    std::vector<Hair> frames;
    for (int f = 0; f < 3; ++f) {
        Hair h = test::random_hair(9, 20, 5);
        for (Vec3f& p : h.points)
            p.y() += float(f);
        frames.push_back(h);
    }
    test::TempPath p(".usda");
    write_usda_animation(p, frames, 24.0);
    const UsdaLayer layer = read_usda_layer(p);
    EXPECT_EQ(layer.time_codes_per_second, 24.0);
    const Hair r = hair_from_usda(layer, "anim");
    test::expect_same_geometry(frames[0], r);  // the earliest sample
    const std::string text = test::read_file_text(p);
    EXPECT_NE(text.find("points.timeSamples"), std::string::npos);
    EXPECT_NE(text.find("endTimeCode = 2"), std::string::npos);
    frames[1] = test::random_hair(9, 20, 6);
    expect_error([&] { encode_usda_animation(frames, 24.0, "a.usda"); },
                 "frame 1 has a different topology");
}

TEST(Usda, StreamedAnimationMatchesTheWholeOne) {
    std::vector<Hair> frames;
    for (int f = 0; f < 3; ++f) {
        Hair h = test::random_hair(7, 12, 3);
        for (Vec3f& p : h.points)
            p.x() -= float(f);
        frames.push_back(h);
    }
    test::TempPath p(".usda");
    {
        UsdaAnimationWriter writer(p, frames[0], 30.0, frames.size());
        for (const Hair& f : frames)
            writer.add(f);
        writer.finish();
    }
    EXPECT_EQ(test::read_file_text(p), encode_usda_animation(frames, 30.0));
    test::TempPath q(".usda");
    {
        UsdaAnimationWriter writer(q, frames[0], 30.0, 5);
        writer.add(frames[0]);
        expect_error([&] { writer.finish(); }, "1 frames written of 5 announced");
        expect_error([&] { writer.add(test::random_hair(7, 12, 4)); },
                     "frame 1 has a different topology");
    }
    EXPECT_FALSE(std::filesystem::exists(q.path()));  // never committed: nothing left behind
}

// Value clips: a layer per frame, a manifest and a top-level layer whose clips metadata
// names them; wisp reads the top-level layer as frame 0.
TEST(Usda, ValueClipsWriteAFilePerFrame) {
    std::vector<Hair> frames;
    for (int f = 0; f < 3; ++f) {
        Hair h = test::random_hair(5, 30, 4);
        for (Vec3f& p : h.points)
            p.x() += 2.f * float(f);
        frames.push_back(h);
    }
    const auto dir =
        std::filesystem::temp_directory_path() / ("wisp_clips_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto top = dir / "anim.usda";
    {
        UsdaClipWriter writer(top, frames[0], 24.0, frames.size());
        for (const Hair& f : frames)
            writer.add(f);
        writer.finish();
    }
    EXPECT_EQ(UsdaClipWriter::frame_path(top, 2, 3), dir / "anim.0002.usda");
    EXPECT_EQ(UsdaClipWriter::frame_path(top, 2, 12345), dir / "anim.00002.usda");
    const std::string text = test::read_file_text(top);
    for (const char* line :
         {"def Xform \"hair\" (\n    clips = {\n        dictionary default = {\n",
          "            double2[] active = [(0, 0), (1, 1), (2, 2)]\n",
          "            asset[] assetPaths = [@./anim.0000.usda@, @./anim.0001.usda@, "
          "@./anim.0002.usda@]\n",
          "            asset manifestAssetPath = @./anim.manifest.usda@\n",
          "            string primPath = \"/hair\"\n",
          "            double2[] times = [(0, 0), (1, 1), (2, 2)]\n", "        point3f[] points\n",
          "    endTimeCode = 2\n"})
        EXPECT_NE(text.find(line), std::string::npos) << line;
    EXPECT_EQ(text.find("points = "), std::string::npos);  // a local value would hide the clips
    const UsdaLayer layer = read_usda_layer(top);
    ASSERT_EQ(layer.clip_sets.size(), 1u);
    EXPECT_EQ(layer.clip_sets[0].prim, "/hair");
    EXPECT_EQ(layer.clip_sets[0].asset_paths.size(), 3u);
    const Hair first = read_usda(top);
    test::expect_same_geometry(frames[0], first);
    EXPECT_EQ(first.colors.size(), frames[0].colors.size());
    // Each clip holds its frame's points at its time code.
    const UsdaLayer clip = read_usda_layer(dir / "anim.0002.usda");
    ASSERT_EQ(clip.curves.size(), 1u);
    EXPECT_EQ(clip.curves[0].path, "/hair/strands");
    EXPECT_EQ(clip.curves[0].points, frames[2].points);
    EXPECT_NE(test::read_file_text(dir / "anim.0002.usda")
                  .find("        point3f[] points.timeSamples = {\n            2: ["),
              std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(dir / "anim.manifest.usda"));

    // A missing clip is named.
    std::filesystem::remove(dir / "anim.0000.usda");
    expect_error([&] { read_usda(top); }, "value clip @./anim.0000.usda@");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    {
        UsdaClipWriter writer(top, frames[0], 24.0, 3);
        writer.add(frames[0]);
        writer.add(frames[1]);
        EXPECT_TRUE(std::filesystem::exists(dir / "anim.0001.usda"));
    }  // unfinished: nothing left behind
    EXPECT_TRUE(std::filesystem::is_empty(dir));
    std::filesystem::remove_all(dir);
}

TEST(Usda, ClipMetadataErrors) {
    const std::string head =
        "#usda 1.0\ndef Xform \"hair\" (\n clips = {\n dictionary default = {\n";
    const std::string tail =
        "}\n}\n)\n{\n def BasisCurves \"c\" {\n int[] curveVertexCounts = [2]\n point3f[] points\n"
        "}\n}\n";
    test::TempPath p(".usda");
    test::write_bytes(p, head + "string templateAssetPath = \"a.#.usd\"\n" + tail);
    expect_error([&] { read_usda(p); }, "template clips (templateAssetPath) are not read");
    test::write_bytes(
        p, head + "asset[] assetPaths = [@x.usda@]\ndouble2[] active = [(0, 3)]\n" + tail);
    expect_error([&] { read_usda(p); }, "active clip 3 is not an index into the 1 assetPaths");
    expect_error([&] { parse_usda(head + "asset[] assetPaths = [\"x\"]\n" + tail, "m.usda"); },
                 "m.usda:5:23: expected an asset path @...@ in clip assetPaths");
    expect_error([&] { parse_usda(head + "double2[] active = [(0 1)]\n" + tail, "m.usda"); },
                 "in a pair of clip active");
}

TEST(Usda, OpenUsdFilesLoad) {
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(kUsdDir)) {
        if (e.path().extension() != ".usda") continue;
        ++files;
        SCOPED_TRACE(e.path().string());
        const std::vector<UsdCurves> curves = read_usda_curves(e.path());
        EXPECT_FALSE(curves.empty());
        EXPECT_NO_THROW(hair_file_info(e.path()));
    }
    EXPECT_GE(files, 3u);
    const Hair examples = read_hair(kUsdDir + "openusd_examples_basisCurves.usda");
    EXPECT_EQ(examples.strand_count(), 10u);
    EXPECT_EQ(examples.widths.size(), examples.point_count());
    // Bezier "BezierClosedBad" (periodic, 4 vertices) is invalid: read_hair names it.
    expect_error([&] { read_hair(kUsdDir + "openusd_basicCurves.usda"); },
                 "prim /World/BezierClosedBad: curve 0 has 4 vertices, but a periodic bezier "
                 "curve needs a multiple of 3");
}

TEST(Usda, SegmentCountsMatchOpenUsdTests) {
    std::ifstream in(WISP_SHARED_DIR "/data/reference_numbers.json");
    ASSERT_TRUE(in);
    const nlohmann::json ref = nlohmann::json::parse(in)["usd_basiscurves_expected"];
    const std::vector<UsdCurves> curves =
        read_usda_curves(kUsdDir + "openusd_testUsdGeomBasisCurves_basisCurves.usda");
    size_t checked = 0;
    for (const auto& [path, expected] : ref["segment_counts"].items()) {
        SCOPED_TRACE(path);
        const UsdCurves& c = prim(curves, path);
        EXPECT_EQ(c.counts, expected["counts"].get<std::vector<int>>());
        EXPECT_EQ(segments_of(c), expected["segments"].get<std::vector<size_t>>());
        ++checked;
    }
    EXPECT_EQ(checked, 8u);
    // Counts: the default when authored, else the earliest time sample.
    for (const auto& [path, earliest] : ref["curve_counts_earliest_time"].items()) {
        SCOPED_TRACE(path);
        const size_t expected = path == "/TimeSampledAndDefaultVertexCounts"
                                    ? ref["curve_counts_default_time"][path].get<size_t>()
                                    : earliest.get<size_t>();
        EXPECT_EQ(prim(curves, path).counts.size(), expected);
    }
    const UsdCurves& bc = prim(curves, "/BezierCubic");
    const auto& sizes = ref["/BezierCubic_data_sizes"];
    EXPECT_EQ(usd_interpolation_size(bc, "uniform"), sizes["uniform"].get<size_t>());
    EXPECT_EQ(usd_interpolation_size(bc, "varying"), sizes["varying"].get<size_t>());
    EXPECT_EQ(usd_interpolation_size(bc, "vertex"), sizes["vertex"].get<size_t>());
    for (const auto& [n, interp] : sizes["interpolation_for_size"].items())
        EXPECT_EQ(usd_interpolation_for_size(bc, std::stoul(n)),
                  interp.is_null() ? "" : interp.get<std::string>())
            << n;
    EXPECT_EQ(bc.widths_interpolation, "constant");
    EXPECT_EQ(bc.points.size(), 10u);
}

// Written for these tests after OpenUSD's pinnedCurves.usda: comments inside arrays and a
// deliberately invalid 1-vertex pinned curve.
const char* kPinned = R"(#usda 1.0
(
    upAxis = "Y"
)

def Xform "World"
{
    def BasisCurves "curve"
    {
        uniform token basis = "bspline"
        uniform token type = "cubic"
        uniform token wrap = "pinned"
        # uniform token wrap = "nonperiodic"
        int[] curveVertexCounts = [5, 3, 2, 1]
        point3f[] points =[
            # curve 0
            (1, 0, 0), (0.7, 0.7, 0), (-4.371139e-8, 1, 0), (-0.7, 0.7, 0), (-1, -8.742278e-8, 0),
            # curve 1
            (1, -3, 0), (2, -2, 0), (3, -3, 0),
            # curve 2
            (1, -6, 0), (2, -6, 0),
            # curve 3: a single vertex
            (1, -9, 0)] (
            interpolation = "vertex"
        )
        float[] widths = [
            0.05, 0.05, 0.05, 0.05, 0.05, # curve 0
            0.05, 0.07, 0.05,
            0.05, 0.07,
            0.09] (
            interpolation = "vertex"
        )
        color3f[] primvars:displayColor = [
            (0.7, 0, 0), // curve 0
            (0.7, 0.7, 0), /* curve 1 */
            (0.7, 0, 0.7),
            (0, 0.7, 0.7)](
            interpolation = "uniform"
        )
    }
}
)";

TEST(Usda, CommentsInsideArraysAndInvalidPinnedCurve) {
    const UsdaLayer layer = parse_usda(kPinned, "pinned.usda");
    ASSERT_EQ(layer.curves.size(), 1u);
    const UsdCurves& c = layer.curves[0];
    EXPECT_EQ(c.path, "/World/curve");
    EXPECT_EQ(c.counts, (std::vector<int>{5, 3, 2, 1}));
    EXPECT_EQ(c.points.size(), 11u);
    EXPECT_EQ(c.widths.size(), 11u);
    EXPECT_EQ(c.display_color.size(), 4u);
    EXPECT_EQ(c.points[2].x(), -4.371139e-8f);
    EXPECT_EQ(segments_of(c), (std::vector<size_t>{4, 2, 1, 0}));
    EXPECT_EQ(usd_curves_problem(c),
              "curve 3 has 1 vertex, but a pinned bspline curve needs at least 2");
    expect_error([&] { hair_from_usda(layer, "pinned.usda"); },
                 "pinned.usda:8: prim /World/curve: curve 3 has 1 vertex");
}

TEST(Usda, TimeSamplesBlockedValuesAndMetadata) {
    const char* text = R"(#usda 1.0
(
    doc = """A "layer" with
    several lines"""
    metersPerUnit = 1
    upAxis = "Z"
    subLayers = [@./other.usda@ (offset = 1)]
)
over "Ignored" { def Mesh "m" { point3f[] points = [(1, 2, 3)] } }
class BasisCurves "NotAPrim" { int[] curveVertexCounts = [2] }
def BasisCurves "Anim" (
    active = true
    prepend apiSchemas = ["SomeAPI"]
    customData = { string note = "x" }
)
{
    int[] curveVertexCounts.timeSamples = {
        2: [3],
        1: [2],
    }
    point3f[] points = None
    point3f[] points.timeSamples = {
        1: [(1, 2, 3), (4, 5, 6)],
        2: [(0, 0, 0), (0, 0, 1), (0, 0, 2)],
    }
    uniform token type = "linear"
    token wrap = 'nonperiodic'
    float[] widths = [0.5]
    custom rel material:binding = </Looks/Hair>
    float3 xformOp:translate.connect = </Other.attr>
    normal3f[] normals = [(0, 0, 1), (0, 0, 1)] (interpolation = "vertex")
    color3f[] primvars:displayColor (interpolation = "constant")
    color3f[] primvars:displayColor.timeSamples = { 0: [(0.5, 0.25, 1)] }
    double3 xformOp:rotateXYZ = (0, -inf, nan)
    variantSet "look" = { "a" { float x = 1 } "b" (doc = "b") { } }
    reorder properties = ["points"]
}
)";
    const UsdaLayer layer = parse_usda(text, "ts.usda");
    EXPECT_EQ(layer.up_axis, "Z");
    EXPECT_EQ(layer.meters_per_unit, 1.0);
    ASSERT_EQ(layer.curves.size(), 1u);
    const UsdCurves& c = layer.curves[0];
    EXPECT_EQ(c.path, "/Anim");
    EXPECT_EQ(c.counts, std::vector<int>{2});  // earliest sample: time 1
    ASSERT_EQ(c.points.size(), 2u);            // blocked default, earliest sample
    EXPECT_EQ(c.type, "linear");
    EXPECT_EQ(c.wrap, "nonperiodic");
    EXPECT_EQ(c.basis, "bezier");  // schema fallback
    EXPECT_TRUE(c.has_normals);
    EXPECT_EQ(c.display_color_interpolation, "constant");
    const Hair h = hair_from_usda(layer, "ts.usda");
    // metres and Z up to centimetres and Y up: (x, y, z) -> 100 (x, z, -y)
    EXPECT_EQ(h.points[0], Vec3f(100, 300, -200));
    EXPECT_EQ(h.widths, (std::vector<float>{50.f, 50.f}));  // constant width, scaled
    EXPECT_EQ(h.default_color, Vec3f(0.5f, 0.25f, 1.f));
}

TEST(Usda, CurveConversion) {
    const char* text = R"(#usda 1.0
def BasisCurves "Bez" {
    int[] curveVertexCounts = [7]
    point3f[] points = [(0,0,0), (1,1,0), (2,1,0), (3,0,0), (4,-1,0), (5,-1,0), (6,0,0)]
    float[] widths = [1, 2, 3] (interpolation = "varying")
}
def BasisCurves "Loop" {
    uniform token type = "linear"
    uniform token wrap = "periodic"
    int[] curveVertexCounts = [3]
    point3f[] points = [(0,0,0), (1,0,0), (0,1,0)]
    color3f[] primvars:displayColor = [(1, 0, 0)]
    int[] primvars:wisp_id = [7] (interpolation = "uniform")
}
def BasisCurves "Pinned" {
    uniform token basis = "bspline"
    uniform token wrap = "pinned"
    int[] curveVertexCounts = [4]
    point3f[] points = [(0,0,0), (1,2,0), (2,-1,0), (3,0,5)]
}
def BasisCurves "CR" {
    uniform token basis = "catmullRom"
    uniform token wrap = "pinned"
    int[] curveVertexCounts = [2, 3]
    point3f[] points = [(0,0,0), (0,1,0), (1,0,0), (1,1,0), (1,2,1)]
    float[] widths = [0.25, 0.5] (interpolation = "uniform")
}
)";
    const UsdaLayer layer = parse_usda(text, "conv.usda");
    const Hair h = hair_from_usda(layer, "conv.usda", 8);
    ASSERT_EQ(h.strand_count(), 5u);
    // Bezier: 2 segments × 8 samples + the end point; passes through p0, p3, p6.
    ASSERT_EQ(h.strand_size(0), 17u);
    EXPECT_TRUE(h.strand(0)[0].isApprox(Vec3f(0, 0, 0)));
    EXPECT_TRUE(h.strand(0)[8].isApprox(Vec3f(3, 0, 0)));
    EXPECT_TRUE(h.strand(0)[16].isApprox(Vec3f(6, 0, 0)));
    EXPECT_FLOAT_EQ(h.widths[4], 1.5f);  // varying: linear within the first segment
    EXPECT_FLOAT_EQ(h.widths[16], 3.f);
    // Periodic linear: closed.
    ASSERT_EQ(h.strand_size(1), 4u);
    EXPECT_EQ(h.strand(1)[3], h.strand(1)[0]);
    // Pinned bspline passes through its end points.
    const auto pin = h.strand(2);
    ASSERT_EQ(pin.size(), 3u * 8u + 1u);
    EXPECT_TRUE(pin.front().isApprox(Vec3f(0, 0, 0)));
    EXPECT_TRUE(pin.back().isApprox(Vec3f(3, 0, 5)));
    // Pinned catmullRom: control points as they are, uniform widths per point.
    ASSERT_EQ(h.strand_size(3), 2u);
    ASSERT_EQ(h.strand_size(4), 3u);
    EXPECT_EQ(h.strand(4)[2], Vec3f(1, 2, 1));
    EXPECT_EQ(h.widths[h.offsets[4]], 0.5f);
    // Colors and wisp ids of the one prim that has them; defaults elsewhere.
    ASSERT_EQ(h.colors.size(), 5u);
    EXPECT_EQ(h.colors[1], Vec3f(1, 0, 0));
    EXPECT_EQ(h.colors[0], Hair().default_color);
    ASSERT_EQ(h.wisp.size(), 5u);
    EXPECT_EQ(h.wisp[1], 7);
    EXPECT_EQ(h.wisp[0], -1);
}

TEST(Usda, MalformedInputNamesTheLocation) {
    const std::string head = "#usda 1.0\ndef BasisCurves \"C\" {\n";
    expect_error(
        [&] { parse_usda(head + "    point3f[] points = [(1, 2), (1, 2, 3)]\n}\n", "m.usda"); },
        "m.usda:3:33: array element has 3 components, the first had 2");
    expect_error([&] { parse_usda(head + "    token type = \"cubic\n}\n", "s.usda"); },
                 "s.usda:3:18: string runs past the end of its line");
    expect_error([&] { parse_usda(head + "    int[] curveVertexCounts = [2, x]\n}\n", "i.usda"); },
                 "i.usda:3:35: expected a number");
    expect_error([&] { parse_usda(head + "    float[] widths = [1 2]\n}\n", "c.usda"); },
                 "c.usda:3:25: expected `,` or `]`");
    expect_error([&] { parse_usda(head, "open.usda"); }, "open.usda:2:1: prim /C is never closed");
    expect_error([&] { parse_usda("#sdf 1.0\n", "h.usda"); }, "h.usda:1:1: not a usda text layer");
    expect_error([&] { parse_usda("PXR-USDC....", "b.usda"); }, "binary usdc");
    expect_error([&] { parse_usda(head + "    int[] curveVertexCounts = [2] $\n}\n", "d.usda"); },
                 "d.usda:3:35: unexpected character `$`");
    expect_error(
        [&] {
            parse_usda(head + "    point3f[] points = [" + std::string(500, '(') + "\n}\n",
                       "deep.usda");
        },
        "nested too deeply");
    // Counts that do not match the points: read_usda_curves keeps it, conversion rejects it.
    const UsdaLayer l = parse_usda(
        head + "    int[] curveVertexCounts = [3]\n    point3f[] points = [(0,0,0)]\n}\n",
        "n.usda");
    expect_error(
        [&] { hair_from_usda(l, "n.usda"); },
        "prim /C: curve 0 has 3 vertices, but a nonperiodic bezier curve needs at least 4");
}

// Tuples must hold exactly their declared numbers: empty, short and nested tuples once read
// past the values array.
TEST(Usda, TuplesMustHoldNumbers) {
    const std::string head = "#usda 1.0\ndef BasisCurves \"C\" {\n";
    const std::string counts = "    int[] curveVertexCounts = [4]\n";
    expect_error(
        [&] {
            parse_usda(head + counts + "    point3f[] points = [((),(),()), ((),(),())]\n}\n",
                       "e.usda");
        },
        "e.usda:4:26: values nested too deeply");
    expect_error([&] { parse_usda(head + "    point3f[] points = [(), ()]\n}\n", "p.usda"); },
                 "p.usda:3:25: empty tuple");
    expect_error(
        [&] { parse_usda(head + "    point3f[] points = [(1,2,()), (3,4,())]\n}\n", "s.usda"); },
        "s.usda:3:30: values nested too deeply");
    expect_error(
        [&] {
            parse_usda(head + "    color3f[] primvars:displayColor = [((),(),())]\n}\n", "c.usda");
        },
        "c.usda:3:41: values nested too deeply");
    expect_error([&] { parse_usda(head + "    float[] widths = [()]\n}\n", "w.usda"); },
                 "w.usda:3:23: empty tuple");
}

// Prim names reach messages, `info` and JSON: control characters and bytes that are not UTF-8
// are rejected, quoted escaped; other input quoted in messages is escaped and cut short.
TEST(Usda, MessagesNeverCarryRawControlCharacters) {
    expect_error([] { parse_usda("#usda 1.0\ndef BasisCurves \"a\xff\xfe\" {\n}\n", "u.usda"); },
                 "u.usda:2:17: prim name \"a\\xff\\xfe\" holds control characters or bytes that "
                 "are not UTF-8");
    expect_error([] { parse_usda("#usda 1.0\ndef Xform \"\x1b[2J\" {\n}\n", "e.usda"); },
                 "prim name \"\\x1b[2J\"");
    const UsdaLayer ok = parse_usda("#usda 1.0\ndef Xform \"caf\xc3\xa9\" {\n}\n", "ok.usda");
    const std::string big(1 << 20, 'x');
    try {
        parse_usda("#usda 1.0\n(\n    upAxis = \"" + big + "\"\n)\n", "big.usda");
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_LT(m.size(), 200u) << m.substr(0, 300);
        EXPECT_NE(m.find("big.usda: upAxis \"xxx"), std::string::npos) << m;
    }
    expect_error([] { parse_usda("#usda 1.0\ndef Xform \"a\" {\n    \x01\n}\n", "c.usda"); },
                 "c.usda:3:5: unexpected character `\\x01`");
}

// Big plain arrays are parsed in parallel blocks; errors inside them and after them must
// still name the right line.
TEST(Usda, BigArraysKeepLineNumbers) {
    std::string text = "#usda 1.0\ndef BasisCurves \"C\" {\n    point3f[] points = [\n";
    for (int i = 0; i < 200000; ++i)
        text += "        (1.5, -2, 3e-3),\n";  // lines 4..200003
    std::string good = text + "    ]\n    int[] curveVertexCounts = [200000] $\n}\n";
    expect_error([&] { parse_usda(good, "big.usda"); }, "big.usda:200005:");
    std::string bad = text;
    bad.replace(bad.find("(1.5", bad.size() / 2), 4, "(1.5.");
    const size_t line = 4 + 100000;
    try {
        parse_usda(bad + "    ]\n}\n", "bad.usda");
        ADD_FAILURE() << "expected an error";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.rfind("bad.usda:", 0), 0u) << m;
        const size_t l = std::stoul(m.substr(9));
        EXPECT_NEAR(double(l), double(line), 1.0) << m;
    }
    const UsdaLayer ok = parse_usda(text + "    ]\n}\n", "ok.usda");
    ASSERT_EQ(ok.curves[0].points.size(), 200000u);
    EXPECT_EQ(ok.curves[0].points[123456], Vec3f(1.5f, -2.f, 3e-3f));
}

// The reader parses the decimals writers give without from_chars (a shortcut through
// double); every float it reads must be the one from_chars reads from the same text. Random
// bit patterns over the magnitudes of hair (1e-7 to 1e7), written shortest and at every
// precision 1..9, as tuples (points) and as scalars (widths).
TEST(Usda, FastNumberParsingMatchesFromChars) {
    std::mt19937 rng(15);
    std::vector<std::string> texts;
    while (texts.size() < 300000) {
        const float v = std::bit_cast<float>(static_cast<uint32_t>(rng()));
        if (!std::isfinite(v) || std::abs(v) > 1e7f || (v != 0 && std::abs(v) < 1e-7f)) continue;
        char buf[64];
        const int precision = static_cast<int>(texts.size() % 10);  // 0: shortest
        const auto r = precision == 0 ? std::to_chars(buf, buf + sizeof buf, v)
                                      : std::to_chars(buf, buf + sizeof buf, v,
                                                      std::chars_format::general, precision);
        texts.emplace_back(buf, r.ptr);
    }
    texts.insert(texts.end(), {"0", "-0", "0.5", "-.5", "1.", "123456789012345", "0.1e1", "1.5E-3",
                               "999999999999999e-12", "16777217", "0.000000000001"});
    while (texts.size() % 3)
        texts.emplace_back("1");
    std::string points, widths;
    for (size_t i = 0; i < texts.size(); i += 3)
        points += "(" + texts[i] + ", " + texts[i + 1] + ", " + texts[i + 2] + "),\n";
    for (const std::string& t : texts)
        widths += t + ", ";
    const UsdaLayer layer = parse_usda("#usda 1.0\ndef BasisCurves \"C\" {\n point3f[] points = [" +
                                           points + "]\n float[] widths = [" + widths + "]\n}\n",
                                       "fast.usda");
    const UsdCurves& c = layer.curves.at(0);
    ASSERT_EQ(c.points.size() * 3, texts.size());
    ASSERT_EQ(c.widths.size(), texts.size());
    size_t wrong = 0;
    for (size_t i = 0; i < texts.size(); ++i) {
        float expected;
        std::from_chars(texts[i].data(), texts[i].data() + texts[i].size(), expected);
        const float got = c.points[i / 3][static_cast<int>(i % 3)];
        if (std::bit_cast<uint32_t>(got) != std::bit_cast<uint32_t>(expected) ||
            std::bit_cast<uint32_t>(c.widths[i]) != std::bit_cast<uint32_t>(expected)) {
            if (++wrong < 10)
                ADD_FAILURE() << texts[i] << " read as " << got << " / " << c.widths[i];
        }
    }
    EXPECT_EQ(wrong, 0u);
}

// Int arrays take the parallel fast path too, and arrays wisp does not read (the groom_*
// primvars) are skipped without tokens; a malformed one still fails at its place.
TEST(Usda, FastIntArraysAndSkippedArrays) {
    std::string counts, ids;
    for (int i = 0; i < 100000; ++i) {
        counts += "2, ";
        ids += std::to_string(i % 977) + ", ";
    }
    std::string pts;
    for (int i = 0; i < 200000; ++i)
        pts += "(0, " + std::to_string(i) + ", 0), ";
    std::string skipped;
    for (int i = 0; i < 100000; ++i)
        skipped += "(0.25, 0.75),\n";
    const std::string head = "#usda 1.0\ndef BasisCurves \"C\" {\n int[] curveVertexCounts = [" +
                             counts + "]\n point3f[] points = [" + pts +
                             "]\n int[] primvars:wisp_id = [" + ids +
                             "]\n float2[] primvars:groom_root_uv = [" + skipped + "]\n";
    const UsdaLayer layer = parse_usda(head + " float extra = 1\n}\n", "ints.usda");
    const UsdCurves& c = layer.curves.at(0);
    ASSERT_EQ(c.counts.size(), 100000u);
    EXPECT_TRUE(std::all_of(c.counts.begin(), c.counts.end(), [](int n) { return n == 2; }));
    ASSERT_EQ(c.wisp_id.size(), 100000u);
    EXPECT_EQ(c.wisp_id[99999], 99999 % 977);
    EXPECT_EQ(c.points[123457], Vec3f(0, 123457, 0));
    // After the skipped array (lines 6 .. 100006), line numbers are still right.
    expect_error([&] { parse_usda(head + " $\n}\n", "ints.usda"); }, "ints.usda:100007:2:");
    // A bad int inside a big int array is reported by the token path at its place.
    std::string bad = head;
    bad.replace(bad.find("2, 2, ") + 3, 1, "2.5");
    expect_error([&] { parse_usda(bad + "}\n", "bad.usda"); }, "bad.usda:3:");
    // An unbalanced tuple inside a skipped array is not skipped by the shortcut.
    std::string unbalanced = head;
    unbalanced.replace(unbalanced.find("(0.25, 0.75),\n(0.25"), 1, "");
    EXPECT_THROW(parse_usda(unbalanced + "}\n", "unbalanced.usda"), Error);
}

// --precision N: every number within half a unit of its N-th significant digit (rounded
// to float), the file smaller the fewer the digits, the extent still holding every point,
// 0 the exact default and anything outside 0..9 refused.
TEST(Usda, PrecisionBoundsTheErrorAndShrinksTheFile) {
    Hair h = test::random_hair(8, 2000, 12);
    for (size_t s = 0; s < h.strand_count(); ++s)
        h.root_uv.emplace_back(float(s) / 2000.f + 1e-4f, 0.333333f);
    const std::string exact = encode_usda(h);
    EXPECT_EQ(encode_usda(h, "hair", {.precision = 0}), exact);
    size_t previous = exact.size();
    for (int digits : {9, 6, 4, 3}) {
        const std::string text = encode_usda(h, "hair", {.precision = digits});
        if (digits < 9) {  // 9 digits are more than the shortest exact form needs
            EXPECT_LT(text.size(), previous) << digits;
            previous = text.size();
        }
        const UsdaLayer layer = parse_usda(text, "p.usda");
        const Hair back = hair_from_usda(layer, "p.usda");
        ASSERT_EQ(back.points.size(), h.points.size());
        const double rel = 0.5 * std::pow(10.0, 1 - digits);
        auto close = [&](float got, float want) {
            return std::abs(double(got) - double(want)) <=
                   rel * std::abs(double(want)) +
                       2 * std::numeric_limits<float>::epsilon() * std::abs(double(want));
        };
        size_t bad = 0, changed = 0;
        for (size_t i = 0; i < h.points.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                bad += !close(back.points[i][k], h.points[i][k]);
                changed += back.points[i][k] != h.points[i][k];
            }
        for (size_t i = 0; i < h.widths.size(); ++i)
            bad += !close(back.widths[i], h.widths[i]);
        EXPECT_EQ(bad, 0u) << digits << " digits";
        if (digits < 9) {
            EXPECT_GT(changed, 0u) << digits;  // the rounding happened
        } else {
            EXPECT_EQ(changed, 0u);  // 9 digits always read back exact
        }
        // The extent (exact) holds every point as read back.
        const std::smatch m = [&] {
            std::smatch r;
            static const std::regex re(
                R"(float3\[\] extent = \[\(([^,]+), ([^,]+), ([^)]+)\), \(([^,]+), ([^,]+), ([^)]+)\)\])");
            std::regex_search(text, r, re);
            return r;
        }();
        ASSERT_EQ(m.size(), 7u);
        for (const Vec3f& p : back.points)
            for (int k = 0; k < 3; ++k) {
                EXPECT_LE(std::stof(m[1 + k]), p[k]);
                EXPECT_GE(std::stof(m[4 + k]), p[k]);
            }
    }
    for (int wrong : {-1, 10})
        test::expect_error([&] { encode_usda(h, "w.usda", {.precision = wrong}); },
                           "w.usda: precision " + std::to_string(wrong));
}

// Both animation writers take the precision: each frame's points are rounded as a single
// layer's are (the same text as encode_usda's points at that precision), its extent holds
// them, and the files shrink; a precision outside 0-9 is refused naming the file.
TEST(Usda, AnimationWritersTakeThePrecision) {
    std::vector<Hair> frames;
    for (int f = 0; f < 2; ++f) {
        Hair h = test::random_hair(9, 200, 8);
        for (Vec3f& p : h.points)
            p.x() += 1.5f * float(f);
        frames.push_back(h);
    }
    const auto dir =
        std::filesystem::temp_directory_path() / ("wisp_prec_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    // The numbers of the array that starts at `from`, without spaces and line breaks (the
    // layers indent them differently).
    const auto points_text = [](const std::string& text, const std::string& from) {
        const size_t a = text.find(from);
        if (a == std::string::npos) return std::string();
        std::string out;
        for (size_t i = a + from.size(); i < text.size() && text[i] != ']'; ++i)
            if (text[i] != ' ' && text[i] != '\n') out += text[i];
        return out;
    };
    for (int digits : {0, 4}) {
        const auto single = dir / ("single" + std::to_string(digits) + ".usda");
        const auto top = dir / ("clips" + std::to_string(digits) + ".usda");
        {
            UsdaAnimationWriter a(single, frames[0], 24.0, 2, nullptr, digits);
            UsdaClipWriter c(top, frames[0], 24.0, 2, nullptr, digits);
            for (const Hair& f : frames) {
                a.add(f);
                c.add(f);
            }
            a.finish();
            c.finish();
        }
        for (int f = 0; f < 2; ++f) {
            // The frame's points as encode_usda writes them at that precision.
            const std::string want = points_text(
                encode_usda(frames[f], "hair", {.precision = digits}), "point3f[] points = [\n");
            const std::string clip = test::read_file_text(UsdaClipWriter::frame_path(top, f, 2));
            const std::string got = points_text(clip, cat(f, ": [\n"));
            ASSERT_FALSE(want.empty());
            EXPECT_EQ(got, want) << digits << " digits, frame " << f;
            // A clip holds points only (the topology is the top layer's).
            const UsdaLayer layer = parse_usda(clip, "clip.usda");
            ASSERT_EQ(layer.curves.size(), 1u);
            const std::vector<Vec3f>& back = layer.curves[0].points;
            ASSERT_EQ(back.size(), frames[f].points.size());
            if (digits == 0) {
                EXPECT_EQ(back, frames[f].points);
            }
            // The frame's extent holds its points as read back.
            std::smatch m;
            static const std::regex re(
                R"(extent.timeSamples = \{\s*\d+: \[\(([^,]+), ([^,]+), ([^)]+)\), \(([^,]+), ([^,]+), ([^)]+)\)\])");
            ASSERT_TRUE(std::regex_search(clip, m, re));
            for (const Vec3f& p : back)
                for (int k = 0; k < 3; ++k) {
                    EXPECT_LE(std::stof(m[1 + k]), p[k]);
                    EXPECT_GE(std::stof(m[4 + k]), p[k]);
                }
        }
        if (digits == 4) {
            EXPECT_LT(std::filesystem::file_size(single),
                      std::filesystem::file_size(dir / "single0.usda"));
            EXPECT_LT(
                std::filesystem::file_size(UsdaClipWriter::frame_path(top, 1, 2)),
                std::filesystem::file_size(UsdaClipWriter::frame_path(dir / "clips0.usda", 1, 2)));
        }
    }
    test::expect_error([&] { UsdaClipWriter(dir / "bad.usda", frames[0], 24.0, 2, nullptr, 10); },
                       "bad.usda: precision 10");
    test::expect_error(
        [&] { UsdaAnimationWriter(dir / "bad.usda", frames[0], 24.0, 2, nullptr, -1); },
        "bad.usda: precision -1");
    std::filesystem::remove_all(dir);
}

TEST(Usda, TruncatedFilesFail) {
    Hair h = test::random_hair(21, 6, 4);
    const std::string text = encode_usda(h);
    // A cut before the first prim can leave a valid empty layer; any cut inside the prims
    // leaves a prim unclosed.
    const size_t first_prim = text.find("def Xform");
    for (size_t cut = 0; cut + 1 < text.size(); cut += cut <= first_prim ? 1 : 3) {
        if (cut <= first_prim) {
            try {
                EXPECT_TRUE(
                    parse_usda(std::string_view(text).substr(0, cut), "cut.usda").curves.empty());
            } catch (const Error&) {
            }
            continue;
        }
        EXPECT_THROW(parse_usda(std::string_view(text).substr(0, cut), "cut.usda"), Error)
            << "cut at " << cut;
    }
}

// Prints wall-clock times; the bounds only catch pathological slowness, because the test
// machines are shared (the timings that matter are in docs/formats.md).
TEST(Usda, RoundTrips100kStrandsOf32Points) {
    // Speed is measured by bench/io_bench; this checks the format holds a groom of a
    // realistic size exactly.
    const Hair h = test::random_hair(42, 100000, 32);
    test::TempPath p(".usda");
    write_usda(p, h);
    test::expect_same_geometry(h, read_usda(p));
}

}  // namespace
}  // namespace wisp
