// Every shipped preset, solved: no hair point ends inside the head or shoulders (issue 3).
#include <gtest/gtest.h>

#include <atomic>

#include "core/parallel.hpp"
#include "geometry/mesh_distance.hpp"
#include "groom/style_toml.hpp"
#include "solve/pipeline.hpp"

namespace wisp {

class PresetTest : public testing::TestWithParam<std::string> {};

TEST_P(PresetTest, NoHairPointInsideTheHead) {
    Style style = load_preset(GetParam());
    // A tenth of the strands and wisps keeps the test quick; the wisps' shapes and the
    // solver's work per wisp stay those of the preset.
    style.strands = std::max(style.strands / 10, 1);
    style.wisps = std::max(std::min(style.wisps / 4, style.strands), 1);
    static const Head head = load_head(HeadSpec{});
    ASSERT_TRUE(style.head.obj.empty()) << "presets grow on the built-in head";
    const HairstyleResult r = generate_hairstyle(style, head);
    EXPECT_EQ(r.points_inside_head, 0u);
    static const MeshDistance exact(*head.mesh);
    std::atomic<size_t> inside{0};
    parallel_for(
        r.hair.strand_count(),
        [&](size_t i) {
            if (i % 3) return;  // every third strand against the exact mesh
            const auto s = r.hair.strand(i);
            for (size_t k = 1; k < s.size(); ++k)
                inside += exact.inside(s[k]);
        },
        16);
    EXPECT_EQ(inside.load(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Shipped, PresetTest, testing::ValuesIn(preset_names()),
                         [](const testing::TestParamInfo<std::string>& info) {
                             std::string name = info.param;
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

}  // namespace wisp
