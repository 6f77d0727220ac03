#include "io/pbrt.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/catmull_rom.hpp"
#include "core/rng.hpp"
#include "io/io_util.hpp"
#include "io_test_util.hpp"
#include "scene_tokens.hpp"

namespace wisp {
namespace {

Vec3f bezier(const Vec3f& b0, const Vec3f& b1, const Vec3f& b2, const Vec3f& b3, float u) {
    const float v = 1.f - u;
    return v * v * v * b0 + 3.f * v * v * u * b1 + 3.f * v * u * u * b2 + u * u * u * b3;
}

Hair curly_hair(size_t strands) {
    Hair hair;
    Rng rng(9);
    for (size_t s = 0; s < strands; ++s) {
        const int n = 2 + static_cast<int>(rng.next() % 20);
        std::vector<Vec3f> pts;
        for (int i = 0; i < n; ++i)
            pts.push_back(Vec3f(std::cos(0.8f * i), -0.5f * i, std::sin(0.8f * i)) +
                          Vec3f(static_cast<float>(s), 0, 0));
        hair.add_strand(pts);
        for (int i = 0; i < n; ++i)
            hair.widths.push_back(0.008f - 0.006f * i / (n - 1));
        hair.colors.push_back(s % 3 ? Vec3f(0.3f, 0.2f, 0.1f) : Vec3f(0.05f, 0.04f, 0.03f));
    }
    return hair;
}

TEST(Pbrt, CurvesAreExactBezierFormsOfTheSplines) {
    const Hair hair = curly_hair(30);
    const std::string text = encode_pbrt(hair, ExportCamera{});
    const auto t = test::tokenize_scene(text);

    bool look_at = false, camera = false, film = false, world = false, material = false;
    int lights = 0;
    size_t strand = 0;
    for (size_t k = 0; k < t.size(); ++k) {
        if (t[k].kind != test::SceneToken::kWord) continue;
        const std::string& w = t[k].text;
        if (w == "LookAt") {
            look_at = true;
            for (int j = 1; j <= 9; ++j)
                EXPECT_EQ(t[k + j].kind, test::SceneToken::kNumber);
        } else if (w == "Camera") {
            camera = t[k + 1].text == "perspective" && t[k + 2].text == "float fov";
        } else if (w == "Film") {
            film = t[k + 1].text == "rgb";
        } else if (w == "WorldBegin") {
            EXPECT_TRUE(look_at && camera && film) << "camera and film come before the world";
            world = true;
        } else if (w == "LightSource") {
            EXPECT_TRUE(world);
            ++lights;
        } else if (w == "Material") {
            EXPECT_EQ(t[k + 1].text, "hair");
            EXPECT_EQ(t[k + 2].text, "rgb reflectance");
            material = true;
        } else if (w == "Shape") {
            ASSERT_TRUE(material) << "a hair material precedes every curve";
            ASSERT_EQ(t[k + 1].text, "curve");
            std::vector<double> P;
            double width0 = -1, width1 = -1;
            std::string type, basis;
            int degree = 0;
            size_t j = k + 2;
            while (j < t.size() && t[j].kind == test::SceneToken::kString) {
                const std::string name = t[j++].text;
                if (name == "string type" || name == "string basis") {
                    (name == "string type" ? type : basis) = t[j].text;
                    ++j;
                    continue;
                }
                const auto values = test::read_array(t, j);
                if (name == "point3 P") P = values;
                if (name == "float width0") width0 = values.at(0);
                if (name == "float width1") width1 = values.at(0);
                if (name == "integer degree") degree = static_cast<int>(values.at(0));
            }
            k = j - 1;
            EXPECT_TRUE(type == "cylinder" || type == "flat");
            EXPECT_EQ(basis, "bezier");
            EXPECT_EQ(degree, 3);
            ASSERT_LT(strand, hair.strand_count());
            const auto pts = hair.strand(strand);
            const size_t n = pts.size();
            ASSERT_EQ(P.size(), 3 * (3 * (n - 1) + 1));  // 3k + 1 points for k segments
            auto b = [&](size_t i) {
                return Vec3f(static_cast<float>(P[3 * i]), static_cast<float>(P[3 * i + 1]),
                             static_cast<float>(P[3 * i + 2]));
            };
            for (size_t seg = 0; seg + 1 < n; ++seg)
                for (float u : {0.f, 0.25f, 0.5f, 0.9f, 1.f}) {
                    const Vec3f ours = catmull_rom_eval(pts, (seg + u) / static_cast<float>(n - 1));
                    const Vec3f theirs =
                        bezier(b(3 * seg), b(3 * seg + 1), b(3 * seg + 2), b(3 * seg + 3), u);
                    EXPECT_LT((ours - theirs).norm(), 1e-4f) << "strand " << strand;
                }
            EXPECT_FLOAT_EQ(static_cast<float>(width0), hair.widths[hair.offsets[strand]]);
            EXPECT_FLOAT_EQ(static_cast<float>(width1), hair.widths[hair.offsets[strand] + n - 1]);
            ++strand;
        }
    }
    EXPECT_TRUE(world);
    EXPECT_GE(lights, 1);
    EXPECT_EQ(strand, hair.strand_count());
}

TEST(Pbrt, WritesAtomically) {
    const Hair hair = curly_hair(2);
    test::TempPath path(".pbrt");
    write_pbrt(path, hair, ExportCamera{});
    const std::string text = io_detail::read_whole_file(path);
    EXPECT_NE(text.find("Shape \"curve\""), std::string::npos);
    EXPECT_NE(text.find(path.path().stem().string() + ".exr"), std::string::npos);
}

}  // namespace
}  // namespace wisp
