#include "render/render.hpp"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "geometry/body_proxy.hpp"
#include "geometry/builtin_head.hpp"
#include "synthetic_hair.hpp"

namespace wisp {
namespace {

// A small scene: a few thousand thick strands on a sphere standing in for the head.
struct Scene {
    Hair hair;
    Mesh head;
};

const Scene& small_scene() {
    static const Scene scene = [] {
        Scene s;
        test::SyntheticHairSpec spec;
        spec.strands = 3000;
        spec.points = 16;
        spec.width = 0.08f;  // ten times real hair, so that 3000 strands read at 96 px
        s.hair = test::synthetic_hair(spec);
        s.head = test::sphere_mesh(spec.center, spec.radius - 0.1f, 32);
        return s;
    }();
    return scene;
}

RenderOptions small_options(const std::string& view = "three-quarter") {
    RenderOptions o;
    o.width = o.height = 96;
    o.view = view;
    return o;
}

float luminance(const uint8_t* p) {
    return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
}

TEST(Render, ShadowsDarkenTheHair) {
    const Scene& s = small_scene();
    RenderOptions o = small_options();
    o.width = o.height = 128;
    const RgbImage lit_background = render(Hair{}, nullptr, o);
    o.shadows = true;
    const RgbImage with = render(s.hair, &s.head, o);
    o.shadows = false;
    const RgbImage without = render(s.hair, &s.head, o);
    // Hair pixels: where a render of the hair alone differs from the empty background.
    o.shadows = false;
    const RgbImage hair_only = render(s.hair, nullptr, o);
    double sum_with = 0, sum_without = 0;
    size_t n = 0;
    for (size_t i = 0; i < hair_only.rgb.size(); i += 3)
        if (hair_only.rgb[i] != lit_background.rgb[i] ||
            hair_only.rgb[i + 1] != lit_background.rgb[i + 1]) {
            sum_with += luminance(&with.rgb[i]);
            sum_without += luminance(&without.rgb[i]);
            ++n;
        }
    ASSERT_GT(n, 1000u);
    EXPECT_LT(sum_with / n, 0.97 * sum_without / n);
}

TEST(Render, StrandVariationShowsSingleHairsAndKeepsTheMeanBrightness) {
    // Per-strand brightness and width (RenderOptions::strand_brightness, strand_width) are
    // uniform about 1: the hair's mean luminance stays, while neighbouring pixels differ more
    // where strands lie side by side (a sparse layer: in a dense one they average out).
    test::SyntheticHairSpec spec;
    spec.strands = 500;
    spec.points = 16;
    spec.width = 0.05f;
    const Hair hair = test::synthetic_hair(spec);
    RenderOptions o = small_options("back");
    o.width = o.height = 160;
    o.shadows = false;
    const RgbImage background = render(Hair{}, nullptr, o);
    const RgbImage varied = render(hair, nullptr, o);
    o.strand_brightness = 0.f;
    o.strand_width = 0.f;
    const RgbImage uniform = render(hair, nullptr, o);
    double mean_varied = 0, mean_uniform = 0, step_varied = 0, step_uniform = 0;
    size_t n = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x + 1 < o.width; ++x) {
            const size_t i = 3 * (static_cast<size_t>(y) * o.width + x);
            auto is_hair = [&](const RgbImage& im, size_t j) {
                return im.rgb[j] != background.rgb[j] || im.rgb[j + 1] != background.rgb[j + 1];
            };
            if (!is_hair(uniform, i) || !is_hair(uniform, i + 3)) continue;
            mean_varied += luminance(&varied.rgb[i]);
            mean_uniform += luminance(&uniform.rgb[i]);
            step_varied += std::abs(luminance(&varied.rgb[i + 3]) - luminance(&varied.rgb[i]));
            step_uniform += std::abs(luminance(&uniform.rgb[i + 3]) - luminance(&uniform.rgb[i]));
            ++n;
        }
    ASSERT_GT(n, 2000u);
    EXPECT_NEAR(mean_varied / mean_uniform, 1.0, 0.03);
    // Measured +5.4%: pixels mix several strands even here, so the effect is modest; a hash
    // that gave every strand the same factor would give +0%.
    EXPECT_GT(step_varied, 1.03 * step_uniform) << "single strands stand out from their neighbours";
}

TEST(Render, AConvexHeadCastsNoShadowOnItself) {
    // A sphere cannot shadow itself: with the head's shadow map on, every pixel must match the
    // render without it, also where the key light grazes the facets (shadow acne there showed
    // as stripes on the built-in bust's neck and the MakeHuman shoulder).
    const Mesh sphere = test::sphere_mesh(Vec3f(0, 0, 0), 10.f, 48);
    RenderOptions o = small_options("three-quarter");
    o.width = o.height = 256;
    o.shadows = true;
    const RgbImage with = render(Hair{}, &sphere, o);
    o.shadows = false;
    const RgbImage without = render(Hair{}, &sphere, o);
    int worst = 0;
    size_t differ = 0;
    for (size_t i = 0; i < with.rgb.size(); ++i) {
        const int d = std::abs(int(with.rgb[i]) - int(without.rgb[i]));
        worst = std::max(worst, d);
        differ += d > 2;
    }
    EXPECT_EQ(differ, 0u) << "worst difference " << worst << " levels";
}

// A bust cut open at the chest on its body proxy: two surfaces meeting at an 11.5° crease. The
// skin's shading must run on across the seam, not step in a line along the cut; a mesh whose
// lower part is not a proxy keeps its own normals (the step shows).
TEST(Render, SkinShadingRunsOnAcrossTheSeamOfABustAndItsProxy) {
    const Mesh sphere = test::sphere_mesh(Vec3f(0, 0, 0), 10.f, 48);
    Mesh body;
    body.vertices = sphere.vertices;
    for (const Vec3i& f : sphere.faces)  // the cap above y = −2, open at its rim
        if (sphere.vertices[size_t(f[0])].y() > -2.f && sphere.vertices[size_t(f[1])].y() > -2.f &&
            sphere.vertices[size_t(f[2])].y() > -2.f)
            body.faces.push_back(f);
    float rim = 10.f;  // the rim's lowest ring
    for (const Vec3i& f : body.faces)
        for (int k = 0; k < 3; ++k)
            rim = std::min(rim, body.vertices[size_t(f[k])].y());
    // The "proxy": an upright cylinder from just under the rim down, its normals level where
    // the sphere's tilt down by 11.5°.
    const float r = std::sqrt(100.f - rim * rim) - 0.05f;
    const int cols = 96, rows = 24;
    const int base = static_cast<int>(body.vertices.size());
    for (int i = 0; i <= rows; ++i)
        for (int j = 0; j < cols; ++j) {
            const float a = 2.f * kPi * float(j) / float(cols);
            body.vertices.emplace_back(r * std::sin(a), rim + 0.05f - 12.f * float(i) / float(rows),
                                       r * std::cos(a));
        }
    const size_t head_faces = body.faces.size();
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) {
            const int a = base + i * cols + j, b = base + i * cols + (j + 1) % cols;
            body.faces.emplace_back(a, b + cols, b);
            body.faces.emplace_back(a, a + cols, b + cols);
        }
    body.face_group.assign(body.faces.size(), 1);
    std::fill(body.face_group.begin(), body.face_group.begin() + long(head_faces), 0);
    body.group_names = {"head", kBodyProxyGroup};
    // The largest luminance step between vertically adjacent skin pixels near the rim, down
    // the middle of a front view.
    RenderOptions o = small_options("front");
    o.width = o.height = 256;
    o.shadows = false;
    const RgbImage background = render(Hair{}, nullptr, o);
    auto worst_step = [&](const Mesh& mesh) {
        const RgbImage img = render(Hair{}, &mesh, o);
        float worst = 0;
        auto at = [&](int x, int y) { return (size_t(y) * size_t(o.width) + size_t(x)) * 3; };
        auto skin = [&](int x, int y) {  // away from the outline's anti-aliased pixels
            for (int k = -3; k <= 3; ++k) {
                const size_t i = at(x, std::clamp(y + k, 0, o.height - 1));
                if (std::equal(&img.rgb[i], &img.rgb[i] + 3, &background.rgb[i])) return false;
            }
            return true;
        };
        for (int x = 118; x < 138; ++x)
            for (int y = 1; y < o.height; ++y)
                if (skin(x, y))
                    worst = std::max(worst, std::abs(luminance(&img.rgb[at(x, y)]) -
                                                     luminance(&img.rgb[at(x, y - 1)])));
        return worst;
    };
    const float blended = worst_step(body);
    Mesh unjoined = body;
    unjoined.group_names[1] = "body";
    const float stepped = worst_step(unjoined);
    EXPECT_GT(stepped, 6.f);
    EXPECT_LT(blended, 0.4f * stepped) << "unjoined " << stepped;
}

// Luminance (sRGB levels, 0–255) of the hair's pixels: their mean and 95th percentile.
struct HairLuminance {
    double mean = 0, p95 = 0;
};
HairLuminance hair_luminance(const Hair& hair, const RenderOptions& o) {
    const RgbImage background = render(Hair{}, nullptr, o);
    const RgbImage img = render(hair, nullptr, o);
    std::vector<float> values;
    for (size_t i = 0; i < img.rgb.size(); i += 3)
        if (img.rgb[i] != background.rgb[i] || img.rgb[i + 1] != background.rgb[i + 1] ||
            img.rgb[i + 2] != background.rgb[i + 2])
            values.push_back(luminance(&img.rgb[i]));
    HairLuminance out;
    if (values.empty()) return out;
    std::sort(values.begin(), values.end());
    for (float v : values)
        out.mean += v;
    out.mean /= static_cast<double>(values.size());
    out.p95 = values[values.size() * 95 / 100];
    return out;
}

TEST(Render, DarkHairStaysDark) {
    // Highlights must not grey dark hair: with the colour of the `dark-brown` preset, the
    // hair's pixels stay dark on average and in all but their brightest 5%. Kajiya-Kay's
    // tinted-white lobe, the paper's model, lifts the same hair well above it.
    Hair hair = small_scene().hair;
    for (Vec3f& c : hair.colors)
        c = Vec3f(0.035f, 0.020f, 0.012f);
    RenderOptions o = small_options("back");
    o.width = o.height = 128;
    o.background = Vec3f::Zero();  // so that pixels the hair half covers are not lifted by it
    const HairLuminance lobes = hair_luminance(hair, o);
    o.shading = RenderOptions::Shading::kKajiyaKay;
    const HairLuminance kajiya = hair_luminance(hair, o);
    // With the rim light: measured 33.2 and 59.3 (47.6 and 85.1 before the primary was
    // weighed as Marschner's R and the lobes shadowed at a fibre's opacity).
    EXPECT_LT(lobes.mean, 40.0);  // measured 33.2 (Kajiya-Kay 56.7)
    EXPECT_LT(lobes.p95, 70.0);   // measured 59.3
    EXPECT_GT(kajiya.p95, 90.0);  // measured 106.9: the bound tells the two apart
}

// Mean saturation (max − min) / max of the sRGB pixels the hair changes, and their mean level.
struct HairChroma {
    double saturation = 0, level = 0;
};
HairChroma hair_chroma(const Hair& hair, const RenderOptions& o) {
    const RgbImage background = render(Hair{}, nullptr, o);
    const RgbImage img = render(hair, nullptr, o);
    HairChroma out;
    size_t n = 0;
    for (size_t i = 0; i < img.rgb.size(); i += 3) {
        const uint8_t* p = &img.rgb[i];
        if (std::equal(p, p + 3, &background.rgb[i])) continue;
        const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
        if (hi < 8) continue;  // black: no hue to keep
        out.saturation += static_cast<double>(hi - lo) / hi;
        out.level += hi;
        ++n;
    }
    if (n > 0) {
        out.saturation /= static_cast<double>(n);
        out.level /= static_cast<double>(n);
    }
    return out;
}

TEST(Render, HighlightsDoNotGreyASheetOfBrownHair) {
    // Seen from the back, a sheet of straight brown hair lies where the key light's primary
    // highlight (uncoloured) reflects toward the eye. It must keep most of its colour: the
    // highlight of the outer strands shows, strand by strand, but not that of every strand
    // beneath them (the lobes are shadowed at a fibre's full opacity), and not as one film.
    Hair hair = small_scene().hair;
    for (Vec3f& c : hair.colors)
        c = Vec3f(0.12f, 0.06f, 0.03f);  // the default style's brown
    RenderOptions o = small_options("back");
    o.width = o.height = 128;
    o.background = Vec3f::Zero();
    o.rim.color = Vec3f::Zero();
    RenderOptions matte = o;  // the hair's own colour: no highlights
    matte.hair.primary = matte.hair.secondary = matte.hair.transmission = 0.f;
    const HairChroma own = hair_chroma(hair, matte);
    const HairChroma lit = hair_chroma(hair, o);
    RenderOptions before = o;  // issue 13's first lobes: a strong, even, barely shadowed sheen
    before.hair.primary = 0.12f;
    before.hair.primary_jitter = 0.f;
    before.lobe_shadow_opacity = before.shadow_opacity;
    const HairChroma grey = hair_chroma(hair, before);
    std::printf("saturation: own %.3f, lit %.3f, before %.3f; level %.1f %.1f %.1f\n",
                own.saturation, lit.saturation, grey.saturation, own.level, lit.level, grey.level);
    // Measured: own colour 0.572, lit 0.460, before 0.350 (levels 56.1, 63.3, 71.5).
    EXPECT_GT(lit.saturation, 0.7 * own.saturation);
    EXPECT_LT(grey.saturation, 0.7 * own.saturation);  // the bound tells the two apart
}

TEST(Render, RimLightLightsTheHairWhereItsShadowsLetIt) {
    // The rim light, from behind, adds light and never takes any; its shadows (the head's and
    // the hair's, at a fibre's full opacity) keep it off most of the hair: without them it
    // would light the hair's far side through the head.
    const Scene& s = small_scene();
    RenderOptions o = small_options("front");
    o.width = o.height = 128;
    const RgbImage background = render(Hair{}, nullptr, o);
    auto mean_gain = [&](bool shadows) {
        RenderOptions on = o, off = o;
        on.shadows = off.shadows = shadows;
        off.rim.color = Vec3f::Zero();
        const RgbImage with = render(s.hair, &s.head, on);
        const RgbImage without = render(s.hair, &s.head, off);
        const RgbImage head_only = render(Hair{}, &s.head, off);
        double sum = 0;
        size_t n = 0;
        for (size_t i = 0; i < with.rgb.size(); i += 3) {
            auto differs = [&](const RgbImage& a) {
                return !std::equal(&without.rgb[i], &without.rgb[i + 3], &a.rgb[i]);
            };
            if (!differs(background) || !differs(head_only)) continue;  // not hair
            const double gain = luminance(&with.rgb[i]) - luminance(&without.rgb[i]);
            EXPECT_GE(gain, -0.5) << "the rim light darkened pixel " << i / 3;
            sum += gain;
            ++n;
        }
        EXPECT_GT(n, 1000u);
        return sum / static_cast<double>(std::max<size_t>(n, 1));
    };
    const double shadowed = mean_gain(true), unshadowed = mean_gain(false);
    EXPECT_GT(shadowed, 0.5);               // measured 1.7 levels of 255
    EXPECT_GT(unshadowed, 2.0 * shadowed);  // measured 4.6
}

TEST(Render, NamedViewsFrameTheFaceUnderShortHair) {
    // Hair that ends above the ears (a crop): the framing still reaches below the built-in
    // head's chin (y = -10.3), and not down to its shoulders (y < -19).
    const Mesh head = builtin_head_mesh();
    Hair hair;
    hair.points = {Vec3f(0, 12, 0), Vec3f(0, 11, -4), Vec3f(4, 10, 0), Vec3f(4, 6, -2)};
    hair.offsets = {0, 2, 4};
    const Box3 box = framing_bounds(hair, &head);
    EXPECT_LT(box.lo.y(), -10.3f);
    EXPECT_GT(box.lo.y(), -19.f);
    // Long hair: 4 cm below its ends, as before.
    hair.points[3] = Vec3f(4, -30, -2);
    EXPECT_NEAR(framing_bounds(hair, &head).lo.y(), -34.f, 0.5f);
}

TEST(Render, PictureDoesNotDependOnThreadCount) {
    const Scene& s = small_scene();
    RenderOptions o = small_options();
    o.width = 200;
    o.height = 150;  // several tiles, partial ones at the edges
    RgbImage one, two;
    {
        ThreadLimit limit(1);
        one = render(s.hair, &s.head, o);
    }
    {
        ThreadLimit limit(2);
        two = render(s.hair, &s.head, o);
    }
    EXPECT_EQ(one.rgb, two.rgb);
    o.shading = RenderOptions::Shading::kFiber;
    {
        ThreadLimit limit(1);
        one = render(s.hair, &s.head, o);
    }
    {
        ThreadLimit limit(2);
        two = render(s.hair, &s.head, o);
    }
    EXPECT_EQ(one.rgb, two.rgb) << "fiber";
}

// The fibre model takes a strand's colour as the melanin that makes it: black hair stays dark
// (what it shows is the surface's reflection), blonde hair takes its colour from the light
// passing through its fibres, brighter where the light arrives scattered through the hair
// than dark hair's, and a red's hue survives.
TEST(Render, FiberShadingGivesEachColourItsMelanin) {
    Hair hair = small_scene().hair;
    RenderOptions o = small_options("back");
    o.width = o.height = 128;
    o.background = Vec3f::Zero();
    o.shading = RenderOptions::Shading::kFiber;
    auto look = [&](const Vec3f& color) {
        for (Vec3f& c : hair.colors)
            c = color;
        return std::pair{hair_luminance(hair, o), hair_chroma(hair, o)};
    };
    const auto [black, black_chroma] = look({0.0075f, 0.0056f, 0.0048f});
    const auto [blonde, blonde_chroma] = look({0.48f, 0.34f, 0.13f});
    const auto [auburn, auburn_chroma] = look({0.09f, 0.026f, 0.012f});
    EXPECT_LT(black.mean, 45.0);
    EXPECT_GT(blonde.mean, 2.0 * black.mean);
    EXPECT_GT(auburn_chroma.saturation, black_chroma.saturation);
    EXPECT_GT(auburn_chroma.saturation, 0.4);
}

// The picture shows what the fibre model says: a flat sheet of straight strands facing the
// eye, unshadowed, takes in its middle the colour computed from FiberScattering directly
// (ambient, and the key's and fill's single and dual scattering). Dark hair's colour there is
// mostly the surface's grey reflection, so a renderer that lost a lobe would miss by far more
// than the tolerance.
TEST(Render, FiberPictureShowsTheModelsRadiance) {
    Hair sheet;
    const Vec3f color(0.09f, 0.026f, 0.012f);  // auburn
    constexpr int points = 16;
    for (int layer = 0; layer < 2; ++layer)
        for (int k = 0; k < 160; ++k) {
            std::array<Vec3f, points> strand;
            const float x = -4.f + 0.05f * k + 0.025f * layer;
            for (int i = 0; i < points; ++i)
                strand[i] = Vec3f(x, 4.f - 8.f * i / (points - 1), -0.05f * layer);
            sheet.add_strand(strand);
            sheet.colors.push_back(color);
        }
    sheet.default_width = 0.1f;
    RenderOptions o;
    o.width = o.height = 64;
    o.look_at = LookAt{Vec3f(0, 0, 60), Vec3f(0, 0, 0)};
    o.fov_y_degrees = 10.f;
    o.shadows = false;
    o.rim.color = Vec3f::Zero();
    o.strand_brightness = 0.f;
    o.strand_width = 0.f;
    o.background = Vec3f::Zero();
    o.shading = RenderOptions::Shading::kFiber;
    const RgbImage image = render(sheet, nullptr, o);

    const FiberScattering fiber(o.fiber);
    const Vec3f sigma_a = melanin_absorption(melanin_from_color(color, o.fiber.beta_n));
    const FiberScattering::Albedo albedo = fiber.albedo(sigma_a);
    const FiberScattering::View view = fiber.view(Vec3f(0, -1, 0), Vec3f(0, 0, 1));
    Vec3f expected = o.ambient.cwiseProduct(color);
    for (const DirectionalLight& light : {o.key, o.fill}) {
        const Vec3f dir = light.direction.normalized();
        const Vec3f scattered =
            fiber.eval(view, dir, sigma_a) + fiber.multiple(view, dir, albedo, 0.f);
        expected += kPi * light.color.cwiseProduct(scattered);
    }
    auto linear = [](uint8_t v) {
        const float s = v / 255.f;
        return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
    };
    const uint8_t* middle = &image.rgb[(32 * 64 + 32) * 3];
    for (int c = 0; c < 3; ++c) {
        // 8-bit sRGB and the colour's packing: a few per cent.
        EXPECT_NEAR(linear(middle[c]), expected[c], 0.04f * expected[c] + 0.0005f) << c;
    }
}

// The display's shoulder: colours up to the knee pass unchanged; above it the largest channel
// rises ever more slowly toward 1, without a kink at the knee, and the channels keep their
// ratios (a hue, not a clipped one).
TEST(Render, HighlightsRollOffKeepingTheirHue) {
    const Vec3f dim(0.8f, 0.5f, 0.2f);
    EXPECT_EQ(roll_off_highlights(dim), dim);
    const Vec3f orange(1.f, 0.6f, 0.25f);
    float last = kHighlightKnee;
    for (float scale : {1.001f, 1.2f, 1.5f, 2.f, 4.f}) {
        const Vec3f shown = roll_off_highlights(scale * orange);
        EXPECT_GT(shown.x(), last) << scale;
        EXPECT_LT(shown.x(), 1.f) << scale;
        EXPECT_NEAR(shown.y() / shown.x(), 0.6f, 1e-5f) << scale;
        EXPECT_NEAR(shown.z() / shown.x(), 0.25f, 1e-5f) << scale;
        last = shown.x();
    }
    EXPECT_LE(roll_off_highlights(1e6f * orange).x(), 1.f);
    // Slope 1 at the knee: just above it, the value has barely moved off the identity.
    const float d = 1e-3f;
    EXPECT_NEAR(roll_off_highlights(Vec3f(kHighlightKnee + d, 0, 0)).x(), kHighlightKnee + d,
                0.02f * d);
}

// Brown hair lit from behind glows orange where the light comes through its fibres: brighter
// than the display, that light is shown as a brighter orange, never with its red and green
// clipped and its blue left, the yellow of blonde hair.
TEST(Render, BacklitBrownHairKeepsItsHueInTheHighlights) {
    Hair hair = small_scene().hair;
    for (Vec3f& c : hair.colors)
        c = Vec3f(0.037f, 0.022f, 0.013f);  // dark brown
    RenderOptions o = small_options("back");
    o.width = o.height = 128;
    o.background = Vec3f::Zero();
    o.shading = RenderOptions::Shading::kFiber;
    o.rim.color *= 4.f;  // a strong back light, to take the hair's glow past the display's 1
    const RgbImage image = render(hair, nullptr, o);
    int bright = 0, yellow = 0;
    for (size_t i = 0; i < image.rgb.size(); i += 3) {
        const uint8_t* px = &image.rgb[i];
        bright += px[0] >= 200;
        yellow += px[0] >= 250 && px[1] >= 250 && px[2] < 200;
    }
    EXPECT_GT(bright, 20) << "the back light never took the hair near the display's 1";
    EXPECT_EQ(yellow, 0) << "of " << bright << " bright pixels";
}

// Pieces the head hides at every pixel they may touch are neither shaded nor drawn: hair
// wholly behind the head leaves the picture as the head alone makes it, and the hair on the
// sphere's far side is counted as hidden while the near side is drawn.
TEST(Render, HairTheHeadHidesIsSkippedAndChangesNothing) {
    const Scene& s = small_scene();
    RenderOptions o = small_options();
    o.shadows = false;
    o.look_at = LookAt{Vec3f(0, 3, 60), Vec3f(0, 3, -1)};
    RenderStats stats;
    render(s.hair, &s.head, o, &stats);
    EXPECT_GT(stats.hidden_pieces, stats.pieces / 10);
    EXPECT_LT(stats.hidden_pieces, stats.pieces);

    // Short strands 3 cm behind the sphere's centre, within 5 cm of its axis toward the eye:
    // inside its silhouette.
    Hair behind;
    constexpr int strands = 200, points = 8;
    for (int k = 0; k < strands; ++k) {
        const float angle = 0.1f * k, radius = 4.5f * (k % 10) / 10.f;
        const Vec3f root(radius * std::cos(angle), 3.f + radius * std::sin(angle), -4.f);
        std::array<Vec3f, points> strand;
        for (int i = 0; i < points; ++i)
            strand[i] = root + Vec3f(0.05f * i, -0.05f * i, -0.1f * i);
        behind.add_strand(strand);
        behind.colors.push_back(Vec3f(0.9f, 0.8f, 0.5f));
    }
    behind.default_width = 0.08f;
    const RgbImage with_hair = render(behind, &s.head, o, &stats);
    EXPECT_EQ(stats.hidden_pieces, stats.pieces);
    EXPECT_EQ(stats.fragments, 0u);
    const RgbImage head_alone = render(Hair{}, &s.head, o);
    EXPECT_EQ(with_hair.rgb, head_alone.rgb);
}

TEST(Render, EmptySceneIsBackground) {
    RenderOptions o = small_options();
    o.background = Vec3f(0.2f, 0.5f, 1.f);
    const RgbImage img = render(Hair{}, nullptr, o);
    ASSERT_EQ(img.width, 96);
    ASSERT_EQ(img.rgb.size(), 96u * 96u * 3u);
    for (size_t i = 0; i < img.rgb.size(); i += 3) {
        ASSERT_EQ(img.rgb[i], 124);  // sRGB of 0.2
        ASSERT_EQ(img.rgb[i + 1], 188);
        ASSERT_EQ(img.rgb[i + 2], 255);
    }
}

TEST(Render, ExplicitCameraAndBadOptions) {
    const Scene& s = small_scene();
    RenderOptions o = small_options();
    o.look_at = LookAt{Vec3f(0, 3, 60), Vec3f(0, 0, 0)};
    const Camera c = render_camera(s.hair, &s.head, o);
    EXPECT_NEAR((c.eye - Vec3f(0, 3, 60)).norm(), 0.f, 1e-5f);
    const RgbImage img = render(s.hair, &s.head, o);
    EXPECT_EQ(img.width, 96);
    o.look_at.reset();
    o.view = "nowhere";
    EXPECT_THROW(render(s.hair, &s.head, o), Error);
    o.view = "front";
    o.width = 0;
    EXPECT_THROW(render(s.hair, &s.head, o), Error);
}

TEST(Render, ContactSheetLaysViewsOnAGrid) {
    const Scene& s = small_scene();
    RenderOptions o = small_options();
    o.width = 40;
    o.height = 30;
    const RgbImage row = contact_sheet(s.hair, &s.head, {"front", "back", "left"}, o);
    EXPECT_EQ(row.width, 120);
    EXPECT_EQ(row.height, 30);
    const RgbImage grid =
        contact_sheet(s.hair, &s.head, {"front", "back", "left", "right", "top"}, o);
    EXPECT_EQ(grid.width, 120);
    EXPECT_EQ(grid.height, 60);
    // The first cell is the front view.
    o.view = "front";
    const RgbImage front = render(s.hair, &s.head, o);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(grid.rgb[(y * 120 + x) * 3 + c], front.rgb[(y * 40 + x) * 3 + c]);
}

// ---- Golden images.
//
// tests/render/golden/NAME.png, compared with a tolerance that absorbs floating-point
// differences between compilers and libms (a few levels on a few pixels) but not a change of
// the picture: mean absolute difference ≤ 1.0 level (of 255) per channel and at most 1% of
// pixels off by more than 24 levels. On failure the render and a diff image (|a − b| × 4)
// are written next to the test's temporary files. WISP_UPDATE_GOLDEN=1 rewrites the goldens.

void check_golden(const std::string& name, const RgbImage& img) {
    const std::filesystem::path golden =
        std::filesystem::path(WISP_SOURCE_DIR) / "tests/render/golden" / (name + ".png");
    const char* update = std::getenv("WISP_UPDATE_GOLDEN");
    if (update && std::string(update) == "1") {
        write_png(golden, img);
        GTEST_SKIP() << "rewrote " << golden;
    }
    int w = 0, h = 0, channels = 0;
    uint8_t* ref = stbi_load(golden.string().c_str(), &w, &h, &channels, 3);
    ASSERT_NE(ref, nullptr) << "missing golden " << golden
                            << " (run with WISP_UPDATE_GOLDEN=1 to create it)";
    ASSERT_EQ(w, img.width);
    ASSERT_EQ(h, img.height);
    double sum = 0;
    size_t bad = 0;
    RgbImage diff = img;
    for (size_t p = 0; p < static_cast<size_t>(w) * h; ++p) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            const int d = std::abs(static_cast<int>(img.rgb[p * 3 + c]) - ref[p * 3 + c]);
            sum += d;
            worst = std::max(worst, d);
            diff.rgb[p * 3 + c] = static_cast<uint8_t>(std::min(255, 4 * d));
        }
        bad += worst > 24;
    }
    stbi_image_free(ref);
    const double mean = sum / (3.0 * w * h);
    const double bad_fraction = static_cast<double>(bad) / (static_cast<double>(w) * h);
    if (mean > 1.0 || bad_fraction > 0.01) {
        const std::filesystem::path dir = testing::TempDir();
        write_png(dir / (name + ".actual.png"), img);
        write_png(dir / (name + ".diff.png"), diff);
        ADD_FAILURE() << name << ": mean difference " << mean << " levels, " << bad_fraction * 100
                      << "% pixels off by > 24; wrote " << (dir / (name + ".actual.png")) << " and "
                      << (dir / (name + ".diff.png"));
    }
}

TEST(RenderGolden, ThreeQuarterWithShadows) {
    const Scene& s = small_scene();
    check_golden("three_quarter_96", render(s.hair, &s.head, small_options("three-quarter")));
}

TEST(RenderGolden, BackWithoutShadows) {
    const Scene& s = small_scene();
    RenderOptions o = small_options("back");
    o.shadows = false;
    check_golden("back_noshadow_96", render(s.hair, &s.head, o));
}

TEST(RenderGolden, TopHairOnly) {
    const Scene& s = small_scene();
    check_golden("top_hair_only_64", [&] {
        RenderOptions o = small_options("top");
        o.width = o.height = 64;
        return render(s.hair, nullptr, o);
    }());
}

}  // namespace
}  // namespace wisp
