#include "io/rib.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/catmull_rom.hpp"
#include "core/rng.hpp"
#include "io/io_util.hpp"
#include "io_test_util.hpp"
#include "scene_tokens.hpp"

namespace wisp {
namespace {

Hair wavy_hair(size_t strands, uint64_t seed) {
    Hair hair;
    Rng rng(seed);
    for (size_t s = 0; s < strands; ++s) {
        const int n = 2 + static_cast<int>(rng.next() % 12);
        std::vector<Vec3f> pts;
        Vec3f p(static_cast<float>(rng.uniform_double()) * 10.f, 8.f, 0.f);
        for (int i = 0; i < n; ++i) {
            pts.push_back(p);
            p += Vec3f(0.3f * std::sin(0.9f * i + s), -1.f, 0.2f * std::cos(1.3f * i));
        }
        hair.add_strand(pts);
        for (int i = 0; i < n; ++i)
            hair.widths.push_back(0.01f * (1.f - 0.5f * i / n));
        hair.colors.push_back(Vec3f(0.1f, 0.05f + 0.001f * s, 0.02f));
    }
    const Vec3f lone[1] = {Vec3f::Zero()};  // a 1-point strand is skipped
    hair.add_strand(lone);
    hair.widths.push_back(0.01f);
    hair.colors.push_back(Vec3f::Ones());
    return hair;
}

TEST(Rib, CurvesParseBackToTheSameSplines) {
    const Hair hair = wavy_hair(25, 3);
    ExportCamera camera;
    camera.width = 320;
    camera.height = 240;
    const std::string text = encode_rib(hair, camera);
    const auto t = test::tokenize_scene(text);

    // Header: format, perspective projection, a 4×4 transform, world block, lights.
    bool format = false, projection = false, transform = false, basis = false;
    int world_begin = 0, world_end = 0, lights = 0;
    std::vector<double> nverts, P, width, Cs;
    for (size_t k = 0; k < t.size(); ++k) {
        const std::string& w = t[k].text;
        if (t[k].kind != test::SceneToken::kWord) continue;
        if (w == "Format") {
            format = t[k + 1].number == 320 && t[k + 2].number == 240;
        } else if (w == "Projection") {
            projection = t[k + 1].text == "perspective" && t[k + 2].text == "fov";
        } else if (w == "Transform") {
            size_t j = k + 1;
            transform = test::read_array(t, j).size() == 16;
        } else if (w == "Basis") {
            basis = t[k + 1].text == "catmull-rom" && t[k + 2].number == 1 &&
                    t[k + 3].text == "catmull-rom" && t[k + 4].number == 1;
        } else if (w == "WorldBegin") {
            ++world_begin;
        } else if (w == "WorldEnd") {
            ++world_end;
        } else if (w == "LightSource") {
            ++lights;
        } else if (w == "Curves") {
            ASSERT_TRUE(basis) << "Basis must precede Curves";
            EXPECT_EQ(t[k + 1].text, "cubic");
            size_t j = k + 2;
            const auto nv = test::read_array(t, j);
            nverts.insert(nverts.end(), nv.begin(), nv.end());
            EXPECT_EQ(t[j].text, "nonperiodic");
            ++j;
            while (j < t.size() && t[j].kind == test::SceneToken::kString) {
                const std::string name = t[j].text;
                ++j;
                const auto values = test::read_array(t, j);
                auto& dst = name == "P" ? P : name == "width" ? width : Cs;
                EXPECT_TRUE(name == "P" || name == "width" || name == "uniform color Cs") << name;
                dst.insert(dst.end(), values.begin(), values.end());
            }
            k = j - 1;
        }
    }
    EXPECT_TRUE(format);
    EXPECT_TRUE(projection);
    EXPECT_TRUE(transform);
    EXPECT_EQ(world_begin, 1);
    EXPECT_EQ(world_end, 1);
    EXPECT_GE(lights, 1);

    ASSERT_EQ(nverts.size(), 25u);  // the 1-point strand is skipped
    size_t total_v = 0, total_w = 0;
    for (size_t s = 0; s < 25; ++s) {
        EXPECT_EQ(nverts[s], hair.strand_size(s) + 2.0);
        total_v += static_cast<size_t>(nverts[s]);
        total_w += hair.strand_size(s);
    }
    ASSERT_EQ(P.size(), 3 * total_v);
    ASSERT_EQ(width.size(), total_w);  // varying: one per segment end = n per curve
    ASSERT_EQ(Cs.size(), 3u * 25u);

    // The RenderMan curve (Catmull-Rom, step 1) through the written vertices is wisp's
    // pinned spline: evaluate both mid-segment.
    size_t v = 0, w = 0;
    for (size_t s = 0; s < 25; ++s) {
        const auto pts = hair.strand(s);
        const size_t n = pts.size();
        auto vert = [&](size_t i) {
            return Vec3f(static_cast<float>(P[3 * (v + i)]), static_cast<float>(P[3 * (v + i) + 1]),
                         static_cast<float>(P[3 * (v + i) + 2]));
        };
        for (size_t seg = 0; seg + 1 < n; ++seg) {
            const Vec3f rib =
                catmull_rom(vert(seg), vert(seg + 1), vert(seg + 2), vert(seg + 3), 0.4f);
            const Vec3f ours = catmull_rom_eval(pts, (seg + 0.4f) / static_cast<float>(n - 1));
            EXPECT_LT((rib - ours).norm(), 1e-4f);
        }
        for (size_t i = 0; i < n; ++i)
            EXPECT_FLOAT_EQ(static_cast<float>(width[w + i]), hair.widths[hair.offsets[s] + i]);
        EXPECT_FLOAT_EQ(static_cast<float>(Cs[3 * s + 1]), hair.colors[s].y());
        v += n + 2;
        w += n;
    }
}

TEST(Rib, WritesAtomicallyAndRejectsABadCamera) {
    const Hair hair = wavy_hair(3, 1);
    test::TempPath path(".rib");
    write_rib(path, hair, ExportCamera{});
    const std::string text = io_detail::read_whole_file(path);
    EXPECT_NE(text.find("Curves \"cubic\""), std::string::npos);
    EXPECT_NE(text.find(path.path().stem().string() + ".tif"), std::string::npos);
    ExportCamera bad;
    bad.target = bad.eye;
    EXPECT_THROW(encode_rib(hair, bad), Error);
}

}  // namespace
}  // namespace wisp
