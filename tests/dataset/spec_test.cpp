// The dataset spec: every mistake is reported with the file, line, field and reason, and
// draws are a pure function of (spec, k) that stay within their distributions.
#include "dataset/spec.hpp"

#include <gtest/gtest.h>

#include <set>

#include <fstream>
#include <map>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "geometry/builtin_head.hpp"

namespace wisp {
namespace {

std::string error_of(const std::string& text) {
    try {
        parse_dataset_spec(text, "spec.toml", ".");
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(DatasetSpec, TheIssuesSmallestSpecParses) {
    const DatasetSpec spec = parse_dataset_spec(R"(samples = 6
seed = 11
[[base]]
preset = "short"
[vary]
"roots.strands" = { choice = [2000, 3000] }
"solve.stiffness" = { uniform = [0.4, 2.0] }
)",
                                                "spec.toml", ".");
    EXPECT_EQ(spec.samples, 6u);
    EXPECT_EQ(spec.seed, 11u);
    ASSERT_EQ(spec.vary.size(), 2u);
    EXPECT_EQ(spec.vary[0].path, "roots.strands");  // the file's order
    EXPECT_EQ(spec.vary[1].kind, VaryRule::Kind::kUniform);
    ASSERT_EQ(spec.cameras.size(), 1u);
    EXPECT_EQ(spec.output.hair, std::vector<std::string>{"hair"});
    // The preset's 3000 wisps come down to a drawn 2000 strands, as `--strands` does.
    for (uint64_t k = 0; k < 6; ++k) {
        const SampleDraw d = draw_sample(spec, k);
        EXPECT_LE(d.style.wisps, d.style.strands);
    }
}

TEST(DatasetSpec, MistakesNameFileLineFieldAndReason) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"seed = 1\n", "spec.toml: field 'samples': required"},
        {"samples = 0\n", "spec.toml:1: field 'samples': expects an integer in [1, "},
        {"samples = 1\nsampels = 3\n", "spec.toml:2: field 'sampels': unknown field"},
        {"samples = 1\n[vary]\n\"solve.stifness\" = { uniform = [0, 1] }\n",
         "spec.toml:3: field 'vary.solve.stifness': is no style field"},
        {"samples = 1\n[vary]\n\"solve.stiffness\" = { uniform = [-1, 2] }\n",
         "spec.toml:3: field 'solve.stiffness': "},
        {"samples = 1\n[vary]\n\"prototype.shape\" = { choice = [\"straight\", \"spiral\"] }\n",
         "spec.toml:3: field 'prototype.shape': "},
        {"samples = 1\n[vary]\n\"prototype.shape\" = { uniform = [0, 1] }\n",
         "spec.toml:3: field 'vary.prototype.shape': is a choice field"},
        {"samples = 1\n[vary]\n\"solve.stiffness\" = { uniform = [2, 1] }\n",
         "spec.toml:3: field 'vary.solve.stiffness.uniform': expects [a, b] with a ≤ b"},
        {"samples = 1\n[vary]\n\"solve.stiffness\" = { log_uniform = [0, 1] }\n",
         "spec.toml:3: field 'vary.solve.stiffness.log_uniform': expects a > 0"},
        {"samples = 1\n[vary]\n\"solve.stiffness\" = { uniform = [1, 2], normal = [1, 1] }\n",
         "spec.toml:3: field 'vary.solve.stiffness': give one of"},
        {"samples = 1\n[vary]\n\"solve.stiffness\" = { uniform = [1, nan] }\n",
         "spec.toml:3: field 'vary.solve.stiffness.uniform': expects a finite number"},
        {"samples = 1\n[vary]\nsolve.stiffness = { uniform = [1, 2] }\n",
         "spec.toml:3: field 'vary.solve': is no style field; quote dotted paths"},
        {"samples = 1\n[[base]]\npreset = \"short\"\nweight = 0\n",
         "spec.toml:4: field 'base[0].weight': expects a weight in (0, 1e12]"},
        {"samples = 1\n[[base]]\npreset = \"nope\"\n", "spec.toml:3: field 'base[0].preset': "},
        {"samples = 1\n[[base]]\nstyle = \"missing.toml\"\n",
         "spec.toml:3: field 'base[0].style': "},
        {"samples = 1\n[[head]]\nscale = -1\n", "spec.toml:3: field 'head.scale': "},
        {"samples = 1\n[output]\nhair = [\"fbx\"]\n",
         "spec.toml:3: field 'output.hair': unknown format 'fbx'"},
        {"samples = 1\n[output]\nsize = [4, 64]\n", "spec.toml:3: field 'output.size': expects"},
        {"samples = 1\n[[camera]]\nview = \"below\"\n",
         "spec.toml:3: field 'camera[0].view': unknown view 'below'"},
        {"samples = 1\n[[camera]]\nazimuth = 400\n", "spec.toml:3: field 'camera[0].azimuth'"},
        {"samples = 1\n[vary\n", "spec.toml:2:"},
    };
    for (const auto& [text, expected] : cases) {
        const std::string message = error_of(text);
        EXPECT_NE(message.find(expected), std::string::npos)
            << "spec:\n"
            << text << "message: " << message << "\nexpected: " << expected;
    }
}

const char* kRules = R"(samples = 50
seed = 3
[[base]]
preset = "short"
[[base]]
preset = "curly"
weight = 3
[vary]
"roots.wisps" = { uniform = [100, 104] }
"solve.stiffness" = { normal = [1.0, 5.0], min = 0.5, max = 1.5 }
"prototype.amplitude" = { log_uniform = [0.1, 10] }
"growth.part" = { choice = ["none", "left"] }
)";

TEST(DatasetSpec, DrawsStayInTheirDistributionsAndReachTheirEnds) {
    const DatasetSpec spec = parse_dataset_spec(kRules, "spec.toml", ".");
    std::map<int, int> wisps;
    std::map<std::string, int> bases, parts;
    double lo = 1e9, hi = -1e9;
    for (uint64_t k = 0; k < 50; ++k) {
        const SampleDraw d = draw_sample(spec, k);
        ++wisps[d.values["roots.wisps"].get<int>()];
        const double s = d.values["solve.stiffness"].get<double>();
        EXPECT_GE(s, 0.5);
        EXPECT_LE(s, 1.5);
        lo = std::min(lo, s);
        hi = std::max(hi, s);
        const double a = d.values["prototype.amplitude"].get<double>();
        EXPECT_GE(a, 0.1 - 1e-6);
        EXPECT_LE(a, 10 + 1e-5);
        ++bases[spec.bases[d.base].name];
        ++parts[d.values["growth.part"].get<std::string>()];
        EXPECT_EQ(d.style.wisps, d.values["roots.wisps"].get<int>());
    }
    EXPECT_EQ(wisps.size(), 5u);  // 100 … 104, both ends included
    EXPECT_EQ(wisps.begin()->first, 100);
    EXPECT_EQ(wisps.rbegin()->first, 104);
    EXPECT_EQ(lo, 0.5);  // a standard deviation of 5 reaches both clamps
    EXPECT_EQ(hi, 1.5);
    EXPECT_GT(bases["preset:curly"], bases["preset:short"]);  // weight 3 against 1
    EXPECT_EQ(parts.size(), 2u);
}

TEST(DatasetSpec, SampleKIsAFunctionOfSpecAndKAlone) {
    const DatasetSpec spec = parse_dataset_spec(kRules, "spec.toml", ".");
    // Another rule: the values the other rules draw do not change.
    const DatasetSpec more = parse_dataset_spec(
        std::string(kRules) + "\"solve.threshold\" = { uniform = [0.1, 0.2] }\n", "spec.toml", ".");
    for (uint64_t k : {0u, 7u, 49u}) {
        const SampleDraw a = draw_sample(spec, k), b = draw_sample(spec, k),
                         c = draw_sample(more, k);
        EXPECT_EQ(a.values, b.values);
        EXPECT_EQ(a.seed, b.seed);
        EXPECT_EQ(a.style.seed, b.style.seed);
        for (const auto& [path, value] : a.values.items())
            EXPECT_EQ(c.values[path], value) << path;
        EXPECT_NE(a.hash, c.hash);
    }
    EXPECT_NE(draw_sample(spec, 1).seed, draw_sample(spec, 2).seed);
}

TEST(DatasetSpec, IndexRangesAndSampleNames) {
    EXPECT_EQ(index_ranges({0, 1, 2, 3, 7, 9, 10}), "0-3,7,9-10");
    EXPECT_EQ(index_ranges({}), "");
    EXPECT_EQ(sample_name(10, 3), "000003");
    EXPECT_EQ(sample_name(20'000'000, 3), "00000003");
}

// Domain randomisation: [render] rules draw the pictures' lights, background and shading per
// sample, in their ranges, recorded with the style's values; mistakes name the rule.
TEST(DatasetSpec, RenderRulesDrawThePicturesLook) {
    const DatasetSpec spec = parse_dataset_spec(R"(samples = 40
[render]
key_azimuth = { uniform = [-60, 60] }
key_temperature = { choice = [2700, 6500] }
rim_intensity = { uniform = [0, 2] }
background_value = { uniform = [0.05, 0.9] }
shading = { choice = ["hair", "fiber"] }
)",
                                                "spec.toml", ".");
    ASSERT_EQ(spec.render.size(), 5u);
    const RenderOptions plain;
    std::set<std::string> shadings;
    for (uint64_t k = 0; k < spec.samples; ++k) {
        const SampleDraw d = draw_sample(spec, k);
        ASSERT_EQ(d.render_values.size(), 5u);
        const double az = d.values.at("render.key_azimuth").get<double>();
        EXPECT_GE(az, -60);
        EXPECT_LE(az, 60);
        const RenderOptions o = sample_render_options(d);
        // Turned about the camera's up axis: the key keeps its height, turns by az.
        EXPECT_NEAR(o.key.direction.y(), plain.key.direction.y(), 1e-5f);
        const Vec3f a = plain.key.direction, b = o.key.direction;
        const float turned =
            std::atan2(a.z() * b.x() - a.x() * b.z(), a.x() * b.x() + a.z() * b.z());
        EXPECT_NEAR(turned * 180 / kPi, az, 1e-3) << k;
        // A warm lamp is redder than daylight, at the key's luminance.
        auto lum = [](const Vec3f& c) {
            return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z();
        };
        EXPECT_NEAR(lum(o.key.color), lum(plain.key.color), 1e-3f);
        const double t = d.values.at("render.key_temperature").get<double>();
        if (t == 2700) {
            EXPECT_GT(o.key.color.x(), o.key.color.y());
            EXPECT_GT(o.key.color.y(), 1.5f * o.key.color.z());
        } else {
            EXPECT_NEAR(o.key.color.x() / o.key.color.z(), 1.0f, 0.1f);  // about white
        }
        const float g = static_cast<float>(d.values.at("render.background_value").get<double>());
        EXPECT_NEAR(o.background.maxCoeff(), g, 1e-5f);
        shadings.insert(d.values.at("render.shading").get<std::string>());
    }
    EXPECT_EQ(shadings.size(), 2u);
    // No [render]: the renderer's own options.
    const DatasetSpec none = parse_dataset_spec("samples = 1\n", "spec.toml", ".");
    const RenderOptions o = sample_render_options(draw_sample(none, 0));
    EXPECT_EQ(o.key.color, RenderOptions{}.key.color);
    EXPECT_EQ(o.background, RenderOptions{}.background);
    for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
             {"[render]\nsun = { uniform = [0, 1] }",
              "field 'render.sun': is no picture parameter (key_azimuth, key_elevation"},
             {"[render]\nkey_intensity = { uniform = [0, 20] }",
              "field 'render.key_intensity': takes numbers in [0, 10], got 20"},
             {"[render]\nshading = { choice = [\"toon\"] }",
              "a choice of \"hair\", \"fiber\", \"kajiya-kay\", got \"toon\""},
             {"[render]\nshading = { uniform = [0, 1] }", "is a choice field"}}) {
        try {
            parse_dataset_spec("samples = 1\n" + text + "\n", "spec.toml", ".");
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("spec.toml:3"), std::string::npos) << e.what();
        }
    }
}

// docs/dataset.md lists every picture parameter and every map the spec takes.
TEST(DatasetSpec, TheDocsListEveryRenderParameterAndMap) {
    std::ifstream in(std::string(WISP_SOURCE_DIR) + "/docs/dataset.md");
    const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(docs.empty());
    for (const RenderField& f : render_field_table())
        EXPECT_NE(docs.find(std::string("`") + f.name + "`"), std::string::npos) << f.name;
    for (const OutputMapInfo& m : output_map_table())
        EXPECT_NE(docs.find(std::string("\"") + m.name + "\""), std::string::npos) << m.name;
}

// Balanced sampling: stratified keeps every base's and head's count within a few samples of
// its weighted share in any first n samples (independent draws stray by about √n); grid
// takes every pair in turn.
TEST(DatasetSpec, StratifiedAndGridSamplingAreBalanced) {
    const std::string bases = R"(
[[base]]
preset = "short"
weight = 3
[[base]]
preset = "curly"
[[base]]
preset = "afro"
[[head]]
builtin = true
[[head]]
builtin = true
weight = 2
)";
    const DatasetSpec stratified =
        parse_dataset_spec("samples = 500\nsampling = \"stratified\"\n" + bases, "s.toml", ".");
    std::vector<int> base_count(3, 0), head_count(2, 0);
    std::map<std::pair<size_t, size_t>, int> pairs;
    double stratified_worst = 0;
    for (uint64_t k = 0; k < stratified.samples; ++k) {
        const SampleDraw d = draw_sample(stratified, k);
        ++base_count[d.base];
        ++head_count[d.head];
        ++pairs[{d.base, d.head}];
        const double n = static_cast<double>(k + 1);
        for (const double off : {base_count[0] - n * 0.6, base_count[1] - n * 0.2,
                                 base_count[2] - n * 0.2, head_count[1] - n * 2 / 3})
            stratified_worst = std::max(stratified_worst, std::abs(off));
    }
    EXPECT_LE(stratified_worst, 6.0);
    EXPECT_EQ(pairs.size(), 6u);  // every pair is drawn
    // Weighted, independent draws stray further from their shares (18 samples here).
    const DatasetSpec weighted = parse_dataset_spec("samples = 500\n" + bases, "s.toml", ".");
    double worst = 0;
    std::vector<int> w(3, 0);
    for (uint64_t k = 0; k < weighted.samples; ++k) {
        ++w[draw_sample(weighted, k).base];
        worst = std::max(worst, std::abs(w[0] - (k + 1) * 0.6));
    }
    EXPECT_GT(worst, 2 * stratified_worst);
    const DatasetSpec grid =
        parse_dataset_spec("samples = 13\nsampling = \"grid\"\n" + bases, "s.toml", ".");
    std::map<std::pair<size_t, size_t>, int> cells;
    for (uint64_t k = 0; k < grid.samples; ++k) {
        const SampleDraw d = draw_sample(grid, k);
        ++cells[{d.base, d.head}];
        EXPECT_EQ(d.base, k % 3);
        EXPECT_EQ(d.head, (k % 6) / 3);
    }
    for (const auto& [cell, n] : cells)
        EXPECT_TRUE(n == 2 || n == 3) << n;
    const std::string bad = error_of("samples = 1\nsampling = \"balanced\"\n");
    EXPECT_NE(bad.find("spec.toml:2: field 'sampling': one of \"weighted\", \"stratified\", "
                       "\"grid\""),
              std::string::npos)
        << bad;
}

// frame = "hair": the view centres on the hair alone and fills the picture with it (a
// hair-centred crop); the default frames the head with it, the hair smaller and off-centre.
TEST(DatasetSpec, HairFramedCamerasCentreAndFillWithTheHair) {
    const DatasetSpec spec = parse_dataset_spec(R"(samples = 1
[output]
size = [128, 128]
[[camera]]
view = "front"
frame = "hair"
[[camera]]
view = "front"
)",
                                                "spec.toml", ".");
    // A tuft on the top of the built-in head.
    Hair hair;
    for (int s = 0; s < 20; ++s) {
        for (int i = 0; i < 8; ++i)
            hair.points.emplace_back(-2.f + 0.2f * s, 12.f + 0.5f * i, 2.f);
        hair.offsets.push_back(static_cast<uint32_t>(hair.points.size()));
    }
    const Mesh& head = builtin_head_mesh();
    const SampleDraw d = draw_sample(spec, 0);
    auto extent = [&](const Camera& cam) {
        Box3 b;
        for (const Vec3f& p : hair.points)
            b.extend(cam.project(p));
        return b;
    };
    const Box3 cropped = extent(sample_camera(spec, d, 0, hair, head));
    const Box3 whole = extent(sample_camera(spec, d, 1, hair, head));
    EXPECT_NEAR(0.5f * (cropped.lo.x() + cropped.hi.x()), 64.f, 2.f);
    EXPECT_NEAR(0.5f * (cropped.lo.y() + cropped.hi.y()), 64.f, 2.f);
    EXPECT_GT(std::max(cropped.size().x() / 128, cropped.size().y() / 128), 0.9f);
    EXPECT_LE(std::max(cropped.size().x(), cropped.size().y()), 128.f);
    EXPECT_GE(std::min(cropped.lo.x(), cropped.lo.y()), 0.f);
    EXPECT_LT(std::max(whole.size().x(), whole.size().y()), 0.5f * 128);
    EXPECT_NE(error_of("samples = 1\n[[camera]]\nframe = \"face\"\n")
                  .find("field 'camera[0].frame': \"head\" (hair and head) or \"hair\""),
              std::string::npos);
}

}  // namespace
}  // namespace wisp
